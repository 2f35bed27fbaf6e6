#include "io/png_file.hpp"

#include "io/png_idat.hpp"

#include "util/error.hpp"
#include "util/file_names.hpp"
#include "util/text.hpp"

#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>

namespace ddt {
namespace {

// libpng reports errors by longjmp: every call that may fail runs in a
// function of its own that holds no C++ object, and the message is kept in
// the stream's context.
struct PngContext {
  std::jmp_buf jump;
  char message[256] = {};
  std::FILE* in = nullptr;
  StagedOutput* stage = nullptr;
  int file = -1;
  std::size_t written = 0;  // bytes handed to the stage
};

[[noreturn]] void on_error(png_structp png, png_const_charp message) {
  auto* context = static_cast<PngContext*>(png_get_error_ptr(png));
  std::snprintf(context->message, sizeof context->message, "%s", message ? message : "PNG library error");
  std::longjmp(context->jump, 1);
}

void on_warning(png_structp, png_const_charp) {}

void stage_bytes(PngContext& context, const void* data, std::size_t size) {
  context.stage->write(context.file, data, size);  // its errors come at finish()
  context.written += size;
}

void write_to_stage(png_structp png, png_bytep data, png_size_t size) {
  stage_bytes(*static_cast<PngContext*>(png_get_io_ptr(png)), data, size);
}

void flush_nothing(png_structp) {}

// The chunks read here as OpenImageIO reads them: the critical ones, the
// transparency it turns into alpha, the time, resolution and text it
// carries, the ICC profile, and those it does not look at (colour-space
// hints it reads as attributes an enlargement drops, background,
// significant bits, offsets). Not here: eXIf, and any unknown critical
// chunk.
bool chunk_taken(const char type[4]) {
  static constexpr std::array<const char*, 17> taken = {"IHDR", "PLTE", "IDAT", "IEND", "tIME", "pHYs",
                                                        "tEXt", "zTXt", "iTXt", "gAMA", "sRGB", "cHRM",
                                                        "sBIT", "bKGD", "oFFs", "tRNS", "iCCP"};
  for (const char* t : taken)
    if (std::memcmp(type, t, 4) == 0) return true;
  const bool ancillary = (type[0] & 0x20) != 0;
  if (!ancillary) return false;
  for (const char* t : {"eXIf", "sPLT", "hIST", "pCAL", "sCAL", "sTER", "dSIG", "acTL", "fcTL", "fdAT"})
    if (std::memcmp(type, t, 4) == 0) return false;
  return true;  // a private ancillary chunk, which libpng skips
}

std::uint32_t big_endian(const unsigned char* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
}

// Walks the chunk list without decoding: whether every chunk is taken and
// the image within libpng's size limits. A malformed list is not taken.
bool file_taken(std::FILE* in) {
  unsigned char signature[8];
  if (std::fread(signature, 1, 8, in) != 8 || png_sig_cmp(signature, 0, 8) != 0) return false;
  bool first = true;
  for (;;) {
    unsigned char head[8];
    if (std::fread(head, 1, 8, in) != 8) return false;
    const std::uint32_t length = big_endian(head);
    const char* type = reinterpret_cast<const char*>(head + 4);
    if (length > 0x7fffffffu || !chunk_taken(type)) return false;
    if (first) {
      unsigned char ihdr[13];
      if (std::memcmp(type, "IHDR", 4) != 0 || length != 13 || std::fread(ihdr, 1, 13, in) != 13) return false;
      const std::uint32_t width = big_endian(ihdr), height = big_endian(ihdr + 4);
      if (width == 0 || height == 0 || width > PNG_USER_WIDTH_MAX || height > PNG_USER_HEIGHT_MAX) return false;
      if (std::fseek(in, 4, SEEK_CUR) != 0) return false;
      first = false;
      continue;
    }
    if (std::memcmp(type, "IEND", 4) == 0) return true;
    if (std::fseek(in, long(length) + 4, SEEK_CUR) != 0) return false;
  }
}

bool names_equal(const char* a, const char* b) { return lower(a) == lower(b); }

// OpenImageIO's name of a text chunk's key (its PNG plugin's mapping).
std::string text_name(const char* key) {
  if (names_equal(key, "Description")) return "ImageDescription";
  if (names_equal(key, "Author")) return "Artist";
  if (names_equal(key, "Title")) return "DocumentName";
  return key;
}

// The key a carried attribute is written under (the reverse mapping).
const char* text_key(const std::string& name) {
  if (names_equal(name.c_str(), "Artist")) return "Author";
  if (names_equal(name.c_str(), "DocumentName")) return "Title";
  if (names_equal(name.c_str(), "ImageDescription")) return "Description";
  return name.c_str();
}

// What image_io.cpp carries of a PNG's text (its `carried` list, the names
// a text chunk can give).
bool text_carried(const std::string& name) {
  for (const char* exact : {"Artist", "Copyright", "ImageDescription", "Make", "Model", "DocumentName"})
    if (name == exact) return true;
  for (const char* prefix : {"Exif:", "GPS:", "IPTC:"})
    if (name.rfind(prefix, 0) == 0) return true;
  return false;
}

// Text OpenImageIO reads as more than a string attribute, or that would
// collide with an attribute of its own: left to it.
bool text_declined(const std::string& key, const std::string& name) {
  const std::string low = lower(key);
  if (low.rfind("raw profile", 0) == 0 || low.rfind("xml:com.adobe.xmp", 0) == 0 || low == "exif" || low == "xmp")
    return true;
  for (const char* own : {"DateTime", "XResolution", "YResolution", "ResolutionUnit", "ICCProfile", "Orientation",
                          "PixelAspectRatio"})
    if (names_equal(name.c_str(), own)) return true;
  return low.rfind("oiio:", 0) == 0 || low.rfind("png:", 0) == 0 || low.rfind("ddtscale:", 0) == 0;
}

// OpenImageIO 2.4's PNG reader associates alpha (multiplies the colour by
// it) in the file's integers: colour * alpha / max, truncated. (With a
// gamma from a gAMA chunk it works in floats instead: such files are left
// to it.)
template <class Sample>
void associate_alpha(Sample* row, int width, int channels) {
  constexpr unsigned max = std::numeric_limits<Sample>::max();
  for (int x = 0; x < width; ++x, row += channels)
    for (int c = 0; c < channels - 1; ++c) row[c] = static_cast<Sample>(unsigned(row[c]) * row[channels - 1] / max);
}

// And its writer the reverse, after rounding to the integers: colour * max
// / alpha, truncated, at most max, where alpha is not 0.
template <class Sample>
void dissociate_alpha(Sample* row, int width, int channels) {
  constexpr unsigned max = std::numeric_limits<Sample>::max();
  for (int x = 0; x < width; ++x, row += channels) {
    const unsigned alpha = row[channels - 1];
    if (alpha == 0) continue;
    for (int c = 0; c < channels - 1; ++c) row[c] = static_cast<Sample>(std::min(max, unsigned(row[c]) * max / alpha));
  }
}

}  // namespace

namespace {

// The header's fields once libpng has read the chunks before the pixels
// (expanded to 8 bits, a palette to RGB), or false with the message.
struct PngInfo {
  png_uint_32 width = 0, height = 0;
  int depth = 0, colour = 0, channels = 0;
  bool has_time = false;
  png_time time{};
  bool has_resolution = false;
  png_uint_32 x_per_unit = 0, y_per_unit = 0;
  int unit = 0;
  png_textp text = nullptr;
  int texts = 0;
  bool gamma_without_srgb = false;  // OpenImageIO then associates alpha in floats
  png_bytep profile = nullptr;
  png_uint_32 profile_length = 0;
  bool interlaced = false;
};

bool start_decoding(png_structp png, png_infop info, PngContext& context, PngInfo& out) {
  if (setjmp(context.jump)) return false;
  png_init_io(png, context.in);
  png_read_info(png, info);
  png_set_expand(png);
  png_set_swap(png);  // 16-bit samples in the machine's order
  png_read_update_info(png, info);
  int interlace = PNG_INTERLACE_NONE;
  png_get_IHDR(png, info, &out.width, &out.height, &out.depth, &out.colour, &interlace, nullptr, nullptr);
  out.interlaced = interlace != PNG_INTERLACE_NONE;
  out.channels = png_get_channels(png, info);
  png_timep time = nullptr;
  if (png_get_tIME(png, info, &time) && time) out.has_time = true, out.time = *time;
  out.has_resolution = png_get_pHYs(png, info, &out.x_per_unit, &out.y_per_unit, &out.unit) != 0;
  out.texts = png_get_text(png, info, &out.text, nullptr);
  int intent = 0;
  double gamma = 0;
  out.gamma_without_srgb = !png_get_sRGB(png, info, &intent) && png_get_gAMA(png, info, &gamma) && gamma > 0;
  png_charp profile_name = nullptr;
  int compression = 0;
  if (png_get_valid(png, info, PNG_INFO_iCCP))
    png_get_iCCP(png, info, &profile_name, &compression, &out.profile, &out.profile_length);
  return true;
}

// An interlaced image is decoded whole, as OpenImageIO decodes it.
bool read_all_rows(png_structp png, PngContext& context, png_bytepp rows) {
  if (setjmp(context.jump)) return false;
  png_read_image(png, rows);
  return true;
}

bool read_one_row(png_structp png, PngContext& context, unsigned char* row) {
  if (setjmp(context.jump)) return false;
  png_read_row(png, row, nullptr);
  return true;
}

}  // namespace

struct PngReader::Decoder {
  PngContext context;
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::vector<unsigned char> row;
  bool interlaced = false;
  std::vector<unsigned char> whole;  // an interlaced image's rows, once decoded

  // Reads the chunks before the pixels from context.in (open, at the
  // file's start) into `out`; false on a libpng error (context.message).
  bool start(PngInfo& out) {
    png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &context, on_error, on_warning);
    if (png) info = png_create_info_struct(png);
    if (!info) {
      std::snprintf(context.message, sizeof context.message, "out of memory");
      return false;
    }
    if (!start_decoding(png, info, context, out)) return false;
    row.resize(png_get_rowbytes(png, info));
    interlaced = out.interlaced;
    return true;
  }

  ~Decoder() {
    if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    if (context.in) std::fclose(context.in);
  }
};

PngReader::PngReader(std::string path, std::unique_ptr<Decoder> decoder, ImageHeader header, PngMetadata metadata)
    : path_(std::move(path)), decoder_(std::move(decoder)), header_(header), metadata_(std::move(metadata)) {}

PngReader::~PngReader() = default;

std::unique_ptr<PngReader> PngReader::open(const std::string& path, const ImageReadLimits& limits) {
  if (lower_extension(path) != ".png") return nullptr;
  try {
    check_regular_file(path);
  } catch (const Error&) {
    return nullptr;  // OpenImageIO's reader refuses it in its words
  }
  auto decoder = std::make_unique<Decoder>();
  PngContext& context = decoder->context;
  context.in = std::fopen(path.c_str(), "rb");
  if (!context.in || !file_taken(context.in) || std::fseek(context.in, 0, SEEK_SET) != 0) return nullptr;
  PngInfo info;
  if (!decoder->start(info)) return nullptr;
  if (info.channels < 1 || info.channels > 4) return nullptr;
  if ((info.channels == 2 || info.channels == 4) && info.gamma_without_srgb) return nullptr;

  PngMetadata metadata;
  for (int i = 0; i < info.texts; ++i) {
    const png_text& t = info.text[i];
    const std::string name = text_name(t.key);
    if (text_declined(t.key, name)) return nullptr;
    for (const auto& [seen, value] : metadata.text)
      if (seen == name) return nullptr;  // OpenImageIO keeps the last; not reproduced
    if (text_carried(name)) metadata.text.emplace_back(name, t.text ? t.text : "");
  }
  if (info.has_time) {
    // OpenImageIO writes the time back through its own date parser, which
    // agrees with this format only for ordinary dates.
    const png_time& t = info.time;
    if (t.year < 1000 || t.year > 9999 || t.month < 1 || t.month > 12 || t.day < 1 || t.day > 31 || t.hour > 23 ||
        t.minute > 59 || t.second > 59)
      return nullptr;
    char date[64];
    std::snprintf(date, sizeof date, "%4d:%02d:%02d %02d:%02d:%02d", info.time.year, info.time.month, info.time.day,
                  info.time.hour, info.time.minute, info.time.second);
    metadata.date_time = date;
  }
  if (info.profile && info.profile_length > 0) metadata.icc_profile.assign(info.profile, info.profile + info.profile_length);
  if (info.has_resolution) {
    // OpenImageIO reads pixels per metre as per inch, in float arithmetic.
    metadata.has_resolution = true;
    metadata.per_inch = info.unit == PNG_RESOLUTION_METER;
    const float scale = metadata.per_inch ? float(2.54 / 100.0) : 1.0f;
    metadata.x_resolution = float(info.x_per_unit) * scale;
    metadata.y_resolution = float(info.y_per_unit) * scale;
  }

  // Two channels are gray and alpha, four RGB and alpha (tRNS expanded too).
  const int alpha = info.channels == 2 || info.channels == 4 ? info.channels - 1 : -1;
  const ImageHeader header{int(info.width), int(info.height), info.channels,
                           info.depth == 16 ? SampleFormat::uint16 : SampleFormat::uint8, alpha};
  check_size_limit("input '" + path + "'", std::to_string(header.width) + "x" + std::to_string(header.height),
                   checked_product({header.width, header.height}), limits.max_pixels, limits.option);
  if (limits.check) limits.check(header);
  return std::unique_ptr<PngReader>(new PngReader(path, std::move(decoder), header, std::move(metadata)));
}

void PngReader::restart() {
  auto decoder = std::make_unique<Decoder>();
  PngContext& context = decoder->context;
  context.in = std::fopen(path_.c_str(), "rb");
  if (!context.in) throw Error("cannot read '" + path_ + "': " + std::strerror(errno));
  PngInfo info;
  if (!decoder->start(info)) throw Error("cannot read '" + path_ + "': " + context.message);
  decoder_ = std::move(decoder);
  next_row_ = 0;
}

void PngReader::read(int first, int end, float* rows) {
  if (first < 0 || end > header_.height || first > end) throw Error("cannot read rows outside '" + path_ + "'");
  if (decoder_->interlaced) {
    Decoder& d = *decoder_;
    if (d.whole.empty() && first < end) {
      const std::size_t row_bytes = d.row.size();
      d.whole.resize(row_bytes * std::size_t(header_.height));
      std::vector<png_bytep> pointers(std::size_t(header_.height));
      for (std::size_t y = 0; y < pointers.size(); ++y) pointers[y] = d.whole.data() + y * row_bytes;
      if (!read_all_rows(d.png, d.context, pointers.data()))
        throw Error("cannot read '" + path_ + "': " + d.context.message);
    }
    next_row_ = first;
  } else if (first < next_row_) {
    restart();
  }
  Decoder& d = *decoder_;
  const std::size_t samples = std::size_t(header_.width) * header_.channels;
  const bool sixteen = header_.format == SampleFormat::uint16;
  for (; next_row_ < end; ++next_row_) {
    if (d.interlaced)
      std::copy_n(d.whole.begin() + std::ptrdiff_t(d.row.size() * std::size_t(next_row_)), d.row.size(), d.row.begin());
    else if (!read_one_row(d.png, d.context, d.row.data()))
      throw Error("cannot read '" + path_ + "': " + d.context.message);
    if (next_row_ < first) continue;
    float* out = rows + std::size_t(next_row_ - first) * samples;
    // OpenImageIO's conversion: a multiplication by the reciprocal, after
    // its alpha association in the file's own sample type.
    if (sixteen) {
      auto* in = reinterpret_cast<std::uint16_t*>(d.row.data());
      if (header_.alpha_channel >= 0) associate_alpha(in, header_.width, header_.channels);
      for (std::size_t i = 0; i < samples; ++i) out[i] = float(in[i]) * (1.0f / 65535.0f);
    } else {
      if (header_.alpha_channel >= 0) associate_alpha(d.row.data(), header_.width, header_.channels);
      for (std::size_t i = 0; i < samples; ++i) out[i] = float(d.row[i]) * (1.0f / 255.0f);
    }
  }
}

PngMetadata scaled_png_metadata(const PngMetadata& metadata, double scale_x, double scale_y) {
  PngMetadata out = metadata;
  out.x_resolution = metadata.x_resolution * static_cast<float>(scale_x);
  out.y_resolution = metadata.y_resolution * static_cast<float>(scale_y);
  return out;
}

bool png_writes(const std::string& path, int width, int height, int channels, const EncodeOptions& encode) {
  if (lower_extension(path) != ".png" || channels < 1 || channels > 4) return false;
  // OpenImageIO 2.4 refuses larger PNGs; its message is left to it.
  if (width < 1 || height < 1 || width > 65535 || height > 65535) return false;
  try {
    check_encode_choice("png", encode, false);
  } catch (const Error&) {
    return false;  // refused in OpenImageIO's path's words
  }
  return true;
}

struct PngWriter::Encoder {
  PngContext context;
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::vector<unsigned char> bytes;
  std::vector<png_bytep> rows;
  std::unique_ptr<IdatEncoder> fast;  // the image data by igzip (`fast`), else by libpng

  ~Encoder() {
    if (png) png_destroy_write_struct(&png, info ? &info : nullptr);
  }
};

namespace {

struct PngHeaderChoice {
  png_uint_32 width, height;
  int depth, colour;
  PngEncoding encoding;
  const PngMetadata* metadata;
  std::vector<png_text>* text;
  bool with_profile;
};

bool start_encoding(png_structp png, png_infop info, PngContext& context, const PngHeaderChoice& c) {
  if (setjmp(context.jump)) return false;
  // OpenImageIO's PNG writer's calls, in its order.
  png_set_write_fn(png, &context, write_to_stage, flush_nothing);
  png_set_compression_level(png, c.encoding.level);
  png_set_compression_strategy(png, c.encoding.strategy);
  png_set_filter(png, 0, c.encoding.filter);
  png_set_option(png, PNG_SKIP_sRGB_CHECK_PROFILE, PNG_OPTION_ON);
  png_set_IHDR(png, info, c.width, c.height, c.depth, c.colour, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_oFFs(png, info, 0, 0, PNG_OFFSET_PIXEL);
  if (c.metadata && !c.metadata->icc_profile.empty() && c.with_profile)
    png_set_iCCP(png, info, "Embedded Profile", 0, c.metadata->icc_profile.data(),
                 png_uint_32(c.metadata->icc_profile.size()));
  if (c.metadata && c.metadata->has_resolution) {
    const float scale = c.metadata->per_inch ? float(100.0 / 2.54) : 1.0f;
    png_set_pHYs(png, info, png_uint_32(c.metadata->x_resolution * scale),
                 png_uint_32(c.metadata->y_resolution * scale),
                 c.metadata->per_inch ? PNG_RESOLUTION_METER : PNG_RESOLUTION_UNKNOWN);
  }
  if (c.metadata && !c.metadata->date_time.empty()) {
    int year, month, day, hour, minute, second;
    if (std::sscanf(c.metadata->date_time.c_str(), "%4d:%02d:%02d %02d:%02d:%02d", &year, &month, &day, &hour,
                    &minute, &second) == 6) {
      png_time time;
      time.year = png_uint_16(year);
      time.month = png_byte(month);
      time.day = png_byte(day);
      time.hour = png_byte(hour);
      time.minute = png_byte(minute);
      time.second = png_byte(second);
      png_set_tIME(png, info, &time);
    }
  }
  if (!c.text->empty()) png_set_text(png, info, c.text->data(), int(c.text->size()));
  png_write_info(png, info);
  png_set_packing(png);
  return true;
}

bool write_rows(png_structp png, PngContext& context, png_bytepp rows, png_uint_32 count) {
  if (setjmp(context.jump)) return false;
  png_write_rows(png, rows, count);
  return true;
}

bool end_encoding(png_structp png, png_infop info, PngContext& context) {
  if (setjmp(context.jump)) return false;
  png_write_end(png, info);
  return true;
}

// std::clamp(std::round(v), 0, top) without a call to libm: a float plus
// one half is exact in double (not in float: 0.5 - 2^-25 would round up),
// so truncating it rounds halves away from zero as std::round does. NaN
// gives 0. Without branches, so that a row's loop runs on vectors.
inline unsigned quantized(float v, float top) {
  const float low = v > 0.0f ? v : 0.0f;  // NaN too
  const float clamped = low < top ? low : top;
  return static_cast<unsigned>(static_cast<int>(static_cast<double>(clamped) + 0.5));
}

}  // namespace

PngWriter::PngWriter(StagedOutput& stage, int file, const std::string& path, int width, int height, int channels,
                     SampleFormat source_format, const PngMetadata* metadata, const EncodeOptions& encode)
    : encoder_(std::make_unique<Encoder>()),
      path_(path),
      width_(width),
      height_(height),
      channels_(channels),
      sixteen_(source_format != SampleFormat::uint8) {
  if (!png_writes(path, width, height, channels, encode))
    throw Error("cannot write '" + path + "' through libpng alone");
  Encoder& e = *encoder_;
  e.context.stage = &stage;
  e.context.file = file;
  auto create = [&] {
    if (e.png) png_destroy_write_struct(&e.png, &e.info);
    e.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &e.context, on_error, on_warning);
    if (!e.png || !(e.info = png_create_info_struct(e.png))) throw Error("cannot write '" + path + "': out of memory");
  };
  create();
  constexpr int colour_types[4] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                   PNG_COLOR_TYPE_RGB_ALPHA};
  std::vector<png_text> text;
  if (metadata)
    for (const auto& [name, value] : metadata->text) {
      png_text t{};
      t.compression = PNG_TEXT_COMPRESSION_NONE;
      t.key = const_cast<char*>(text_key(name));
      t.text = const_cast<char*>(value.c_str());
      text.push_back(t);
    }
  PngHeaderChoice choice{png_uint_32(width), png_uint_32(height), sixteen_ ? 16 : 8, colour_types[channels - 1],
                         png_encoding(encode), metadata, &text, true};
  if (!start_encoding(e.png, e.info, e.context, choice)) {
    // libpng refuses a profile it judges malformed (and with it the file):
    // the image is then written without it, as write_image does.
    const std::string why = e.context.message;
    if (!metadata || metadata->icc_profile.empty() || e.context.written > 0)
      throw Error("cannot write '" + path + "': " + why);
    create();
    choice.with_profile = false;
    if (!start_encoding(e.png, e.info, e.context, choice))
      throw Error("cannot write '" + path + "': " + e.context.message);
  }
  if (choice.encoding.fast) {
    const std::size_t sample_bytes = sixteen_ ? 2 : 1;
    PngContext* context = &e.context;
    e.fast = std::make_unique<IdatEncoder>(
        std::size_t(width) * channels * sample_bytes, channels * sample_bytes, std::size_t(height),
        png_filter_type(choice.encoding.filter),
        [context](const unsigned char* bytes, std::size_t size) { stage_bytes(*context, bytes, size); }, path);
  }
}

PngWriter::~PngWriter() = default;

void PngWriter::write(const float* rows, int count) {
  if (count <= 0) return;
  if (written_ + count > height_) throw Error("cannot write '" + path_ + "': more rows than the image has");
  Encoder& e = *encoder_;
  const std::size_t samples = std::size_t(width_) * channels_;
  const std::size_t row_bytes = samples * (sixteen_ ? 2 : 1);
  e.bytes.resize(row_bytes * std::size_t(count));
  e.rows.resize(std::size_t(count));
  // OpenImageIO's rounding: to nearest, halves away from zero, clamped;
  // then, in the sample type, it divides the colour by alpha (PNG stores
  // it unassociated).
  const float top = sixteen_ ? 65535.0f : 255.0f;
  const bool alpha = channels_ == 2 || channels_ == 4;
  std::vector<std::uint16_t> wide(sixteen_ ? samples : 0);
  for (int r = 0; r < count; ++r) {
    const float* in = rows + std::size_t(r) * samples;
    unsigned char* out = e.bytes.data() + std::size_t(r) * row_bytes;
    e.rows[std::size_t(r)] = out;
    if (sixteen_) {
      for (std::size_t i = 0; i < samples; ++i)
        wide[i] = static_cast<std::uint16_t>(quantized(in[i] * top, top));
      if (alpha) dissociate_alpha(wide.data(), width_, channels_);
      for (std::size_t i = 0; i < samples; ++i)
        out[2 * i] = static_cast<unsigned char>(wide[i] >> 8), out[2 * i + 1] = static_cast<unsigned char>(wide[i] & 0xff);
    } else {
      for (std::size_t i = 0; i < samples; ++i)
        out[i] = static_cast<unsigned char>(quantized(in[i] * top, top));
      if (alpha) dissociate_alpha(out, width_, channels_);
    }
  }
  if (e.fast)
    e.fast->write(e.bytes.data(), count);
  else if (!write_rows(e.png, e.context, e.rows.data(), png_uint_32(count)))
    throw Error("cannot write '" + path_ + "': " + e.context.message);
  written_ += count;
}

void PngWriter::finish() {
  if (written_ != height_) throw Error("cannot write '" + path_ + "': only " + std::to_string(written_) + " rows");
  Encoder& e = *encoder_;
  if (e.fast)
    e.fast->finish();
  else if (!end_encoding(e.png, e.info, e.context))
    throw Error("cannot write '" + path_ + "': " + e.context.message);
}

}  // namespace ddt
