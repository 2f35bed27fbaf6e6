#pragma once
// Image file I/O through OpenImageIO.
//
// Every function throws ddt::Error with a one-line message on failure.
// Writing is atomic: pixels go to a temporary file in the target directory
// which is renamed over the target only after a complete write, so a failed
// run never leaves a truncated file or destroys an existing one.

#include "image.hpp"

#include <OpenImageIO/imagebuf.h>

#include <string>
#include <vector>

namespace ddt {

// How samples were stored in the file; used to pick the output depth.
enum class SampleFormat { uint8, uint16, half, float32 };

struct ImageFile {
  Image image;                             // float samples as stored (uint scaled to 0..1)
  SampleFormat format = SampleFormat::uint8;
  std::string alpha_name;                  // empty when there is no alpha channel
  int alpha_channel = -1;                  // index of alpha, or -1
};

// Reads any image OpenImageIO reads (first subimage, first MIP level).
ImageFile read_image(const std::string& path);

// Writes `image` to `path`; the format follows the extension. EXR is written
// as 32-bit float; integer formats keep `source_format`'s depth (8 or 16 bit,
// float sources become 16 bit), rounded and clamped to 0..1.
void write_image(const std::string& path, const Image& image,
                 SampleFormat source_format, int alpha_channel = -1);

// Writes `content` to `path` atomically (temporary file beside it, then
// rename), for text outputs such as SVG and CSV.
void write_file_atomically(const std::string& path, const std::string& content);

// Encodes 8-bit PNG bytes in memory (for embedding, e.g. in SVG).
std::vector<unsigned char> encode_png(const Image& image);

// Conversions between ddt::Image and OpenImageIO's ImageBuf (float).
Image image_from_buf(const OIIO::ImageBuf& buf);
OIIO::ImageBuf buf_from_image(const Image& image);

// Throws if `output` cannot be written: same file as `input`, or a directory
// that does not exist or is not writable, or (when image_format) an
// extension no image format claims. Called before any long work.
void check_output_path(const std::string& output, const std::string& input, bool image_format = true);

}  // namespace ddt
