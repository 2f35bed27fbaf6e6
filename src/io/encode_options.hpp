#pragma once
// How an output image is encoded: compression, quality and sample type,
// per format; checked here, handed to OpenImageIO's writers as ImageSpec
// attributes (image_io.cpp) or to libpng (png_file.cpp).
//
// compression (empty: the format's default, default_compression):
//   PNG   fast[:FILTER] (ISA-L's igzip, level 1), or LEVEL[:FILTER[:STRATEGY]],
//         LEVEL 0..9 (zlib), FILTER none, sub, up, avg, paeth or adaptive
//         (libpng picks one per row; not with fast), STRATEGY zlib's
//         default, filtered, huffman, rle or fixed; default fast:up
//         (docs/performance.md: zlib 6 took 9x the time of zlib 1 for 0.8x
//         the bytes; igzip a quarter of zlib 1's for 1.02x). Where
//         OpenImageIO writes the PNG (ddtscale-full), fast is zlib's 1:FILTER:rle.
//   EXR   none, rle, zips, zip, piz, pxr24, b44, b44a, dwaa, dwab, with
//         :LEVEL for dwaa/dwab (lossy; 45 by default); default piz
//   TIFF  none, lzw, zip[:LEVEL 1..9] (zip alone: level 6), packbits,
//         jpeg[:QUALITY]; default zip:1
//   other formats refuse the option
// quality: JPEG and WebP quality 1..100 (0: the default, 90); other formats
//   refuse it.
// half: EXR (and float TIFF) samples as 16-bit half floats instead of 32-bit
//   floats; refused for formats without half samples.
// full_float: EXR samples as 32-bit floats whatever the source. By default
//   an EXR holds half floats for 8-bit and half sources (11 bits of
//   precision: a sixteenth of an 8-bit step; what oiiotool writes for them)
//   and 32-bit floats for 16-bit and float sources (image_io.cpp).
// tile: TIFF and EXR written in tiles of tile x tile pixels (a multiple of
//   16) instead of scanlines or strips: what viewers of huge images read
//   fastest; 0: scanlines.
//
// Errors: check_encode_options throws ddt::Error with a one-line message
// naming the option and what it accepts.

#include <string>

namespace ddt {

struct EncodeOptions {
  std::string compression;
  int quality = 0;
  bool half = false;
  bool full_float = false;
  int tile = 0;
};

// The compression used when none is given ("" for formats without one).
std::string default_compression(const std::string& format_name);

// Throws unless `options` suit the output format of `path`
// (output_format_name, image_formats.hpp).
void check_encode_options(const std::string& path, const EncodeOptions& options);

// Throws unless `options` suit `format_name` (OpenImageIO's name: "png",
// "openexr", "tiff", ...) for samples that are floats (float_samples) or
// integers.
void check_encode_choice(const std::string& format_name, const EncodeOptions& options, bool float_samples);

// PNG's choices (checked) as libpng takes them: zlib level and strategy,
// the filter flags.
struct PngEncoding {
  bool fast = false;  // igzip (png_file.cpp); the other fields are zlib's nearest
  int level = 1, filter = 0, strategy = 0;
  std::string strategy_name;  // OpenImageIO's name of the strategy
};
PngEncoding png_encoding(const EncodeOptions& options);

// EXR's and TIFF's choice (checked): the compression's name and its level
// or quality (-1: none given; TIFF's zip alone: 6, jpeg alone: 90).
struct NamedCompression {
  std::string name;
  int level = -1;
};
NamedCompression named_compression(const std::string& format_name, const EncodeOptions& options);

}  // namespace ddt
