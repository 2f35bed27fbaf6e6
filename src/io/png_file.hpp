#pragma once
// PNG files through libpng itself, for the commonest job: a PNG enlarged
// into a PNG. The `ddtscale` command then runs without OpenImageIO, whose
// start alone (it loads about 270 libraries) takes 0.3 s and 130 MB
// (docs/performance.md).
//
// The floats read and the bytes written are OpenImageIO 2.4's, whose PNG
// plugin is libpng too (tests/io/test_png_file.cpp compares both ways), so
// a job gives the same file whichever reads and writes it, alpha
// included (OpenImageIO associates it on reading, in the file's sample
// type, and divides it out on writing; so does this). What this does not
// reproduce is left to OpenImageIO: PngReader::open returns null for
// EXIF or XMP, alpha under a gAMA without
// sRGB, text OpenImageIO reads as something else, an unusual date, a
// malformed chunk list.
//
// Carried, as OpenImageIO reads and writes them (image_io.hpp,
// ImageFile::metadata): the ICC profile (iCCP), the time (tIME,
// "DateTime"), the resolution (pHYs, scaled so the printed size stays) and
// text chunks whose OpenImageIO name
// is carried (Author as Artist, Title as DocumentName, Description as
// ImageDescription, Copyright, ...).
//
// Errors: ddt::Error with a one-line message ("cannot read 'in.png': ...").

#include "io/encode_options.hpp"
#include "io/image_header.hpp"
#include "io/safe_file.hpp"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace ddt {

struct PngMetadata {
  std::string date_time;  // "YYYY:MM:DD hh:mm:ss", or empty
  bool has_resolution = false;
  bool per_inch = false;  // read from pixels per metre; else a unit-less ratio
  float x_resolution = 0, y_resolution = 0;
  std::vector<std::pair<std::string, std::string>> text;  // OpenImageIO's names, in the file's order
  std::vector<unsigned char> icc_profile;                 // iCCP's profile, or empty
};

// The metadata of an image scale_x x scale_y times the size it was read at
// (as image_io.hpp's scaled_metadata).
PngMetadata scaled_png_metadata(const PngMetadata& metadata, double scale_x, double scale_y);

class PngReader {
 public:
  // Null when `path` is not a PNG read here as OpenImageIO reads it (see
  // above; an unreadable or malformed file too: OpenImageIO says why).
  // Otherwise the header is checked as read_image checks it (limits.check
  // included) and the reader stands before the first row.
  static std::unique_ptr<PngReader> open(const std::string& path, const ImageReadLimits& limits = {});
  ~PngReader();
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;

  const ImageHeader& header() const { return header_; }
  const PngMetadata& metadata() const { return metadata_; }
  // Rows [first, end) as floats, width * channels a row; fastest top to
  // bottom (rows above the last read are decoded again from the top; an
  // interlaced image is decoded whole at the first read, as OpenImageIO
  // decodes it).
  void read(int first, int end, float* rows);

 private:
  struct Decoder;
  PngReader(std::string path, std::unique_ptr<Decoder> decoder, ImageHeader header, PngMetadata metadata);
  void restart();
  std::string path_;
  std::unique_ptr<Decoder> decoder_;
  ImageHeader header_;
  PngMetadata metadata_;
  int next_row_ = 0;
};

// Whether a width x height PNG of `channels` channels is written here,
// byte for byte as OpenImageIO would (gray, gray and alpha, RGB, RGB and
// alpha, alpha last; PNG's options, checked: encode_options.hpp).
bool png_writes(const std::string& path, int width, int height, int channels, const EncodeOptions& encode);

// Encodes a PNG into a staged file (safe_file.hpp) row by row. 8-bit
// samples from 8-bit sources, else 16-bit; values rounded and clamped to
// 0..1 as OpenImageIO rounds them.
class PngWriter {
 public:
  PngWriter(StagedOutput& stage, int file, const std::string& path, int width, int height, int channels,
            SampleFormat source_format, const PngMetadata* metadata, const EncodeOptions& encode);
  ~PngWriter();
  PngWriter(const PngWriter&) = delete;
  PngWriter& operator=(const PngWriter&) = delete;

  // The next `count` rows, width * channels floats a row.
  void write(const float* rows, int count);
  // The end of the file (every row written).
  void finish();

 private:
  struct Encoder;
  std::unique_ptr<Encoder> encoder_;
  std::string path_;
  int width_, height_, channels_;
  bool sixteen_;
  int written_ = 0;
};

}  // namespace ddt
