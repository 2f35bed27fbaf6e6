#pragma once
// Image file I/O through OpenImageIO.
//
// Every function throws ddt::Error with a one-line message on failure.
// Writing is atomic and exclusive (safe_file.hpp): the encoded bytes go
// through a checked writer into a private directory beside the target and
// are renamed over it only after a complete, synced write, so a failed run
// (full disk, signal) never leaves a truncated file or destroys an existing
// one. Inputs must be regular files (devices and FIFOs are refused).

#include "util/image.hpp"
#include "io/image_header.hpp"
#include "io/image_formats.hpp"
#include "io/encode_options.hpp"
#include "io/safe_file.hpp"
#include "util/size_limits.hpp"

#include <OpenImageIO/imagebuf.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ddt {

struct ImageFile {
  Image image;                             // float samples as stored (uint scaled to 0..1)
  SampleFormat format = SampleFormat::uint8;
  int alpha_channel = -1;                  // index of alpha, or -1
  // What the file says beside its pixels that a photographer expects kept:
  // the ICC profile, EXIF (the orientation included: the pixels are read as
  // stored, so the output carries the same tag and displays the same way),
  // GPS and IPTC tags, resolution, camera, author and copyright; and a data
  // window other than the display window (EXR), as "ddtscale:data_origin"
  // (int[2]) and "ddtscale:display_window" (int[4]: x, y, width, height).
  OIIO::ParamValueList metadata;
  int pages = 1;                           // subimages (TIFF pages, EXR parts); only the first is read
};

// Reads any image OpenImageIO reads (first subimage, first MIP level).
ImageFile read_image(const std::string& path, const ImageReadLimits& limits = {});

// The same file read by rows, for images too large to decode whole
// (pipeline/banded_upscale.hpp): the header checked as read_image checks it
// (but for the memory of the whole decoded image); rows read in any order,
// fastest top to bottom (formats without random access decode again from
// the top for rows above the last read). Errors: throws ddt::Error as
// read_image does, at construction or at the read.
class ImageRowReader {
 public:
  ImageRowReader(const std::string& path, const ImageReadLimits& limits = {});
  ~ImageRowReader();
  ImageRowReader(const ImageRowReader&) = delete;
  ImageRowReader& operator=(const ImageRowReader&) = delete;

  const ImageHeader& header() const { return header_; }
  // The file's metadata, format, alpha and pages; its image is empty.
  const ImageFile& file() const { return file_; }
  // Rows [first, end) as floats, width * channels a row.
  void read(int first, int end, float* rows);

 private:
  std::string path_;
  std::unique_ptr<OIIO::ImageInput> in_;
  ImageFile file_;
  ImageHeader header_;
};

// Writes `image` to `path`; the format follows the extension. EXR is written
// as half floats from 8-bit and half sources, else 32-bit floats
// (encode.half, encode.full_float choose); integer formats keep `source_format`'s depth (8 or 16 bit,
// float sources become 16 bit), rounded and clamped to 0..1.
// metadata, when given, is written with the image where the format stores
// it (ImageFile::metadata, through scaled_metadata; the windows in EXR).
// `encode` chooses the compression, JPEG quality and half floats
// (encode_options.hpp).
void write_image(const std::string& path, const Image& image,
                 SampleFormat source_format, int alpha_channel = -1,
                 const OIIO::ParamValueList* metadata = nullptr, const EncodeOptions& encode = {});

// `metadata` for an image scale_x x scale_y times the size it was read at:
// the resolution (pixels per unit) scaled so the printed size stays, the
// EXIF pixel dimensions dropped (the file's own size says it), the windows'
// corners and sizes scaled (rounded to whole pixels).
OIIO::ParamValueList scaled_metadata(const OIIO::ParamValueList& metadata, double scale_x, double scale_y);

// write_file_atomically(path, bytes), for text outputs such as SVG and CSV,
// is declared in safe_file.hpp.

// Encodes 8-bit PNG bytes in memory (for embedding, e.g. in SVG).
std::vector<unsigned char> encode_png(const Image& image);

// Conversions between ddt::Image and OpenImageIO's ImageBuf (float).
Image image_from_buf(const OIIO::ImageBuf& buf);
OIIO::ImageBuf buf_from_image(const Image& image);

// Throws when `path`'s format cannot store a width x height image of
// `channels` channels from `source_format` samples (channel count, type,
// size), so the refusal comes before any long work and before a plugin
// that aborts on it (DPX with 2 or 5 channels) is handed the image.
// write_image calls it too. `encode` is checked against the format.
void check_image_writable(const std::string& path, int width, int height, int channels, SampleFormat source_format,
                          int alpha_channel = -1, const EncodeOptions& encode = {});

}  // namespace ddt
