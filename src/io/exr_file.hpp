#pragma once
// EXR files written through the OpenEXR library alone, for the second
// commonest job: a PNG enlarged into an EXR. The `ddtscale` front then
// runs it without OpenImageIO (0.3 s and 130 MB at start;
// docs/performance.md).
//
// The bytes are OpenImageIO 2.4's (tests/io/test_exr_file.cpp compares
// them with write_image's): its EXR writer is this library too, and the
// header is built as its exroutput.cpp (v2.4.7.1) builds it: channels
// named R, G, B, A (one channel: Y), half floats from 8-bit and half
// sources and 32-bit floats otherwise (--half, --float), the compression
// and its level (zip 4; DWA 45 unless given; one channel's DWA becomes
// zip), lines in increasing y, capDate from the metadata or else the local
// time, and the carried metadata under OpenEXR's names (DateTime as
// capDate, ImageDescription as comments, Copyright as owner, XResolution
// as xDensity with pixelAspectRatio from both resolutions, other text as
// strings; an ICC profile is not written, as OpenImageIO writes none).
// What it does not reproduce is left to OpenImageIO: tiles, and text
// whose name OpenImageIO treats specially.
//
// Errors: ddt::Error with a one-line message ("cannot write 'o.exr': ...").

#include "io/encode_options.hpp"
#include "io/image_header.hpp"
#include "io/safe_file.hpp"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace ddt {

// What an EXR carries of its source, under OpenImageIO's names.
struct ExrMetadata {
  std::string date_time;  // "YYYY:MM:DD hh:mm:ss"; empty: the local time when the file is opened
  bool has_resolution = false;
  std::string resolution_unit;  // "inch" or "none"
  float x_resolution = 0, y_resolution = 0;
  std::vector<std::pair<std::string, std::string>> text;
};

// Whether ExrWriter writes this job as OpenImageIO 2.4 would: an .exr path,
// scanlines (no --tile-size), 1 to 4 channels, encoding choices that
// check_encode_choice takes, text names it maps plainly (Artist,
// DocumentName, ImageDescription, Copyright, Make, Model, and names
// starting with Exif:, GPS: or IPTC:).
bool exr_writes(const std::string& path, int width, int height, int channels, SampleFormat source_format,
                const ExrMetadata& metadata, const EncodeOptions& encode);

// Encodes an EXR into a staged file (safe_file.hpp) by bands of rows, its
// compression on OpenEXR's threads.
class ExrWriter {
 public:
  ExrWriter(StagedOutput& stage, int file, const std::string& path, int width, int height, int channels,
            int alpha_channel, SampleFormat source_format, const ExrMetadata& metadata, const EncodeOptions& encode);
  ~ExrWriter();
  ExrWriter(const ExrWriter&) = delete;
  ExrWriter& operator=(const ExrWriter&) = delete;

  // The next `count` rows, width * channels floats a row.
  void write(const float* rows, int count);
  // The end of the file (every row written).
  void finish();

 private:
  struct Encoder;
  std::unique_ptr<Encoder> encoder_;
  std::string path_;
  int width_, height_, channels_;
  int written_ = 0;
};

}  // namespace ddt
