#include "io/encode_options.hpp"

#include "util/error.hpp"
#include "util/text.hpp"

#include "io/image_formats.hpp"

#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <filesystem>
#include <vector>

namespace ddt {
namespace {

struct NamedValue {
  const char* name;
  int value;
};

// libpng's filter flags (png_set_filter), as OpenImageIO's "png:filter" passes them.
constexpr NamedValue png_filters[] = {{"none", PNG_FILTER_NONE}, {"sub", PNG_FILTER_SUB},     {"up", PNG_FILTER_UP},
                                      {"avg", PNG_FILTER_AVG},   {"paeth", PNG_FILTER_PAETH}, {"adaptive", PNG_ALL_FILTERS}};

const std::vector<std::string> exr_compressions = {"none", "rle",   "zips", "zip",  "piz",
                                                   "pxr24", "b44", "b44a", "dwaa", "dwab"};
const std::vector<std::string> tiff_compressions = {"none", "lzw", "zip", "packbits", "jpeg"};

// "NAME" or "NAME:NUMBER": the name, and the number (or `absent`).
// Throws when the number is not a whole number within [lo, hi].
int split_level(const std::string& text, std::string& name, int absent, int lo, int hi, const std::string& what) {
  const auto colon = text.find(':');
  name = text.substr(0, colon);
  if (colon == std::string::npos) return absent;
  const std::string number = text.substr(colon + 1);
  const bool digits = !number.empty() && number.size() <= 3 &&
                      std::all_of(number.begin(), number.end(), [](char c) { return c >= '0' && c <= '9'; });
  const int value = digits ? std::stoi(number) : -1;
  if (!digits || value < lo || value > hi)
    throw Error("--compression " + text + ": " + what + " must be a whole number from " + std::to_string(lo) +
                " to " + std::to_string(hi));
  return value;
}

// zlib's strategies, as OpenImageIO's PNG writer names them ("compression").
const std::vector<std::string> png_strategies = {"default", "filtered", "huffman", "rle", "fixed"};

// PNG: fast[:FILTER] or LEVEL[:FILTER[:STRATEGY]]; returns the zlib level
// and sets `filter`, `strategy` (zlib's default when not given) and `fast`
// (then level 1 and rle: zlib's nearest, where OpenImageIO writes).
int parse_png(const std::string& text, int& filter, std::string& strategy, bool& fast) {
  const auto colon = text.find(':');
  const std::string level = text.substr(0, colon);
  const std::string rest = colon == std::string::npos ? "up" : text.substr(colon + 1);
  const auto second = rest.find(':');
  const std::string name = rest.substr(0, second);
  strategy = second == std::string::npos ? "default" : rest.substr(second + 1);
  fast = level == "fast";
  if (fast) {
    if (second != std::string::npos || name == "adaptive")
      throw Error("--compression " + text + ": PNG's fast takes a filter only: fast[:none|sub|up|avg|paeth]");
    strategy = "rle";
  } else if (level.size() != 1 || level[0] < '0' || level[0] > '9') {
    throw Error("--compression " + text +
                ": PNG takes fast[:FILTER] or LEVEL[:FILTER[:STRATEGY]], LEVEL a zlib level from 0 to 9 (e.g. 1:up)");
  }
  if (std::find(png_strategies.begin(), png_strategies.end(), strategy) == png_strategies.end())
    throw Error("--compression " + text + ": unknown zlib strategy '" + strategy + "' (" + joined(png_strategies) +
                ")");
  for (const NamedValue& f : png_filters)
    if (name == f.name) {
      filter = f.value;
      return fast ? 1 : level[0] - '0';
    }
  throw Error("--compression " + text + ": unknown PNG filter '" + name +
              "' (none, sub, up, avg, paeth or adaptive)");
}

}  // namespace

std::string default_compression(const std::string& format_name) {
  // ISA-L's igzip after the up filter: about zlib 1's size in a quarter of
  // its time (docs/performance.md).
  if (format_name == "png") return "fast";
  if (format_name == "openexr") return "piz";
  // zlib level 1: level 6 made jobs much slower for somewhat smaller files
  // (docs/performance.md); `zip` alone still means level 6.
  if (format_name == "tiff") return "zip:1";
  return "";
}

void check_encode_options(const std::string& path, const EncodeOptions& options) {
  // The sample type is known once the input's header is read
  // (check_image_writable); here the choices are checked by name.
  check_encode_choice(output_format_name(path), options, options.half);
}

void check_encode_choice(const std::string& format, const EncodeOptions& options, bool float_samples) {
  const std::string shown = format == "openexr" ? "EXR" : format.empty() ? "this format" : format;
  if (!options.compression.empty() && default_compression(format).empty())
    throw Error("--compression: " + shown + " output has no compression choice (PNG, EXR and TIFF do)");
  if (options.quality != 0 && format != "jpeg")
    throw Error("--quality is for JPEG output (TIFF: --compression jpeg:QUALITY)");
  if (options.quality < 0 || options.quality > 100) throw Error("--quality must be a whole number from 1 to 100");
  const bool float_tiff = format == "tiff" && float_samples;
  if (options.half && format != "openexr" && !float_tiff)
    throw Error("--half is for EXR output (and TIFF of float images)");
  if (options.full_float && format != "openexr") throw Error("--float is for EXR output");
  if (options.half && options.full_float) throw Error("--half and --float: give one of them");
  if (options.tile != 0 && format != "tiff" && format != "openexr")
    throw Error("--tile-size is for TIFF and EXR output");
  if (options.tile != 0 && (options.tile < 16 || options.tile % 16 != 0 || options.tile > 65536))
    throw Error("--tile-size must be a multiple of 16 from 16 to 65536");
  if (format == "jpeg") return;
  const std::string text = options.compression.empty() ? default_compression(format) : options.compression;
  if (text.empty()) return;
  if (format == "png") {
    png_encoding(options);
  } else if (format == "openexr") {
    std::string name;
    const int level = split_level(text, name, -1, 1, 999, "the DWA level");
    if (std::find(exr_compressions.begin(), exr_compressions.end(), name) == exr_compressions.end())
      throw Error("--compression " + text + ": EXR compression is one of " + joined(exr_compressions));
    if (level >= 0 && name != "dwaa" && name != "dwab")
      throw Error("--compression " + text + ": only dwaa and dwab take a level");
  } else if (format == "tiff") {
    std::string name;
    const int level = split_level(text, name, -1, 1, 100, "the level");
    if (std::find(tiff_compressions.begin(), tiff_compressions.end(), name) == tiff_compressions.end())
      throw Error("--compression " + text + ": TIFF compression is one of " + joined(tiff_compressions));
    if (level >= 0 && name != "zip" && name != "jpeg")
      throw Error("--compression " + text + ": only zip (1 to 9) and jpeg (quality 1 to 100) take a level");
    if (name == "zip" && level > 9) throw Error("--compression " + text + ": the zip level must be from 1 to 9");
  }
}

PngEncoding png_encoding(const EncodeOptions& options) {
  const std::string text = options.compression.empty() ? default_compression("png") : options.compression;
  PngEncoding e;
  e.filter = PNG_FILTER_UP;
  e.level = parse_png(text, e.filter, e.strategy_name, e.fast);
  const int strategies[] = {Z_DEFAULT_STRATEGY, Z_FILTERED, Z_HUFFMAN_ONLY, Z_RLE, Z_FIXED};
  for (std::size_t i = 0; i < png_strategies.size(); ++i)
    if (png_strategies[i] == e.strategy_name) e.strategy = strategies[i];
  return e;
}

NamedCompression named_compression(const std::string& format, const EncodeOptions& options) {
  check_encode_choice(format, options, false);
  const std::string text = options.compression.empty() ? default_compression(format) : options.compression;
  NamedCompression c;
  if (format == "openexr") c.level = split_level(text, c.name, -1, 1, 999, "the DWA level");
  if (format == "tiff") {
    c.level = split_level(text, c.name, -1, 1, 100, "the level");
    if (c.name == "zip" && c.level < 0) c.level = 6;
    if (c.name == "jpeg" && c.level < 0) c.level = 90;
  }
  return c;
}

}  // namespace ddt
