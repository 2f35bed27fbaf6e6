#pragma once
// The image files a program reads and writes, as the file pipeline
// (pipeline/file_upscale.hpp) sees them: an input read by rows, an output
// written by bands of rows, with what the input carries (metadata) scaled
// into the output.
//
// The functions marked "chosen at link time" have two definitions:
//   io/image_formats.cpp   in the library: a PNG that png_file.hpp reads
//                          and writes through libpng alone, every other
//                          file through OpenImageIO (image_io.hpp);
//   cli/png_formats.cpp    in the `ddtscale` command's front: PNG through
//                          libpng only, so that it starts without loading
//                          OpenImageIO; anything else throws
//                          NeedsOpenImageIO, on which the front runs its
//                          command line again as ddtscale-full.
// Both give the same files (tests/io/test_png_file.cpp).

#include "io/encode_options.hpp"
#include "io/image_header.hpp"
#include "util/error.hpp"
#include "util/image.hpp"

#include <memory>
#include <string>

namespace ddt {

// Thrown by the front's definitions for what only OpenImageIO reads or
// writes, before anything is written.
struct NeedsOpenImageIO : Error {
  using Error::Error;
};

// An output image written by bands of rows, top to bottom, each row once;
// the file appears (renamed over the target) only at finish().
class OutputImage {
 public:
  virtual ~OutputImage() = default;
  virtual void write(Image rows, int first_row) = 0;
  virtual void finish() = 0;
};

class InputImage {
 public:
  virtual ~InputImage() = default;
  virtual const ImageHeader& header() const = 0;
  // Pages or parts the file holds (only the first is read).
  virtual int pages() const = 0;
  // Rows [first, end) as floats, width * channels a row (fastest top to
  // bottom).
  virtual void read(int first, int end, float* rows) = 0;
  // The writer of `path`: this image enlarged to width x height, its
  // metadata carried and scaled, its sample type kept where the format
  // stores it (image_io.hpp, write_image).
  virtual std::unique_ptr<OutputImage> create_output(const std::string& path, int width, int height,
                                                     const EncodeOptions& encode) = 0;
};

// Chosen at link time: opens `path` and checks its header as read_image
// does (limits.check included).
std::unique_ptr<InputImage> open_input_image(const std::string& path, const ImageReadLimits& limits = {});

// Chosen at link time: throws when `path` cannot hold a width x height
// image of `source`'s channels and samples with `encode` (as
// check_image_writable).
void check_output_image(const std::string& path, int width, int height, const ImageHeader& source,
                        const EncodeOptions& encode);

// Chosen at link time: OpenImageIO's format name of an output path
// ("png", "openexr", "tiff", "jpeg", ...), or "" when no format claims
// its extension.
std::string output_format_name(const std::string& path);

// Throws if `output` cannot be written: same file as `input`, or a directory
// that does not exist or is not writable, or (when image_format) an
// extension no image format claims. Called before any long work.
// A symlink output is checked at the file it points to (safe_file.hpp).
void check_output_path(const std::string& output, const std::string& input, bool image_format = true);

}  // namespace ddt
