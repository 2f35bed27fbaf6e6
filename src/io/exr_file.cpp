#include "io/exr_file.hpp"

#include "util/error.hpp"
#include "util/file_names.hpp"
#include "util/text.hpp"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfThreading.h>

#include <cpuid.h>
#include <immintrin.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <exception>
#include <thread>

namespace ddt {
namespace {

bool starts_with(const std::string& text, const char* prefix) { return text.rfind(prefix, 0) == 0; }

// Text OpenImageIO 2.4's EXR writer stores as a string attribute under
// its own name (or comments, owner), none of its special names.
bool plain_text_name(const std::string& name) {
  for (const char* plain : {"Artist", "DocumentName", "ImageDescription", "Copyright", "Make", "Model"})
    if (name == plain) return true;
  // Prefixes that name no OpenImageIO format (those are dropped).
  return starts_with(name, "Exif:") || starts_with(name, "GPS:") || starts_with(name, "IPTC:");
}

Imf::PixelType pixel_type(SampleFormat source, const EncodeOptions& encode) {
  if (encode.half) return Imf::HALF;
  if (encode.full_float) return Imf::FLOAT;
  // As output_type (image_io.cpp): half floats hold 8-bit and half sources.
  return source == SampleFormat::uint8 || source == SampleFormat::half ? Imf::HALF : Imf::FLOAT;
}

Imf::Compression compression_of(const std::string& name) {
  static const std::pair<const char*, Imf::Compression> names[] = {
      {"none", Imf::NO_COMPRESSION},   {"rle", Imf::RLE_COMPRESSION}, {"zips", Imf::ZIPS_COMPRESSION},
      {"zip", Imf::ZIP_COMPRESSION},   {"piz", Imf::PIZ_COMPRESSION}, {"pxr24", Imf::PXR24_COMPRESSION},
      {"b44", Imf::B44_COMPRESSION},   {"b44a", Imf::B44A_COMPRESSION}, {"dwaa", Imf::DWAA_COMPRESSION},
      {"dwab", Imf::DWAB_COMPRESSION}};
  for (const auto& [n, c] : names)
    if (name == n) return c;
  return Imf::ZIP_COMPRESSION;  // OpenImageIO's default for a name it does not know
}

// OpenImageIO's capDate when none is given: the local time.
std::string local_time_now() {
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  char text[64];
  std::snprintf(text, sizeof text, "%4d:%02d:%02d %02d:%02d:%02d", local.tm_year + 1900, local.tm_mon + 1,
                local.tm_mday, local.tm_hour, local.tm_min, local.tm_sec);
  return text;
}

// ImageSpec::default_channel_names for 1 to 4 channels, the alpha channel
// named "A" (output_spec, image_io.cpp), in the order of the samples.
std::vector<std::string> channel_names(int channels, int alpha_channel) {
  if (channels == 1) return {"Y"};
  static const char* const rgba[] = {"R", "G", "B", "A"};
  std::vector<std::string> names(rgba, rgba + channels);
  // assign, not = "A": GCC 12 warns falsely (-Wrestrict) of the latter.
  if (alpha_channel >= 0 && alpha_channel < channels) names[std::size_t(alpha_channel)].assign(1, 'A');
  return names;
}

// The header exroutput.cpp's spec_to_header and put_parameter build for
// this job.
Imf::Header exr_header(int width, int height, int channels, int alpha_channel, Imf::PixelType type,
                       const ExrMetadata& metadata, const EncodeOptions& encode) {
  const Imath::Box2i window(Imath::V2i(0, 0), Imath::V2i(width - 1, height - 1));
  Imf::Header header(window, window);
  for (const std::string& name : channel_names(channels, alpha_channel))
    header.channels().insert(name, Imf::Channel(type, 1, 1, false));

  const NamedCompression chosen = named_compression("openexr", encode);
  std::string name = chosen.name;
  const int level = chosen.level;
  // One channel's DWA "works reliably" only on power-of-two tiles: zip.
  if (channels == 1 && starts_with(name, "dwa")) name = "zip";
  if (starts_with(name, "dwa"))
    header.insert("dwaCompressionLevel", Imf::FloatAttribute(level > 0 ? float(level) : 45.0f));
  if (starts_with(name, "zip")) header.zipCompressionLevel() = level >= 1 && level <= 9 ? level : 4;
  header.compression() = compression_of(name);
  header.lineOrder() = Imf::INCREASING_Y;

  header.insert("capDate", Imf::StringAttribute(metadata.date_time.empty() ? local_time_now() : metadata.date_time));
  for (const auto& [key, value] : metadata.text) {
    const std::string exr_name = key == "ImageDescription" ? "comments" : key == "Copyright" ? "owner" : key;
    header.insert(exr_name, Imf::StringAttribute(value));
  }
  if (metadata.has_resolution) {
    header.insert("ResolutionUnit", Imf::StringAttribute(metadata.resolution_unit));
    header.insert("xDensity", Imf::FloatAttribute(metadata.x_resolution));
    if (metadata.x_resolution != 0 && metadata.y_resolution != 0)
      header.insert("pixelAspectRatio", Imf::FloatAttribute(metadata.x_resolution / metadata.y_resolution));
  }
  return header;
}

// OpenImageIO's EXR writer gives OpenEXR as many threads as the machine
// has cores (its "exr_threads" default).
void use_all_cores() {
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  if (Imf::globalThreadCount() != cores) Imf::setGlobalThreadCount(cores);
}

// Floats to half floats, rounded to nearest (ties to even) as Imath's
// half(float) rounds them: by F16C eight at a time where the processor has
// it (Imath itself uses it when built for such processors), else Imath's.
__attribute__((target("avx,f16c"))) void halves_by_f16c(const float* in, std::size_t n, Imath::half* out) {
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8)
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i),
                     _mm256_cvtps_ph(_mm256_loadu_ps(in + i), _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC));
  for (; i < n; ++i) out[i] = Imath::half(in[i]);
}

void to_halves(const float* in, std::size_t n, Imath::half* out) {
  static const bool f16c = [] {
    unsigned a = 0, b = 0, c = 0, d = 0;  // CPUID leaf 1: F16C in ECX (clang has no "f16c" for the builtin)
    return __builtin_cpu_supports("avx") && __get_cpuid(1, &a, &b, &c, &d) && (c & bit_F16C) != 0;
  }();
  if (f16c) return halves_by_f16c(in, n, out);
  std::transform(in, in + n, out, [](float v) { return Imath::half(v); });
}

// The staged file as OpenEXR's output stream: it seeks back at the end to
// write the table of line offsets.
class StagedStream final : public Imf::OStream {
 public:
  StagedStream(StagedOutput& stage, int file, const std::string& name)
      : Imf::OStream(name.c_str()), stage_(stage), file_(file) {}
  void write(const char c[], int n) override {
    stage_.write_at(file_, c, static_cast<std::size_t>(n), static_cast<off_t>(position_));
    position_ += static_cast<std::uint64_t>(n);
  }
  std::uint64_t tellp() override { return position_; }
  void seekp(std::uint64_t position) override { position_ = position; }

 private:
  StagedOutput& stage_;
  int file_;
  std::uint64_t position_ = 0;
};

}  // namespace

bool exr_writes(const std::string& path, int width, int height, int channels, SampleFormat source_format,
                const ExrMetadata& metadata, const EncodeOptions& encode) {
  if (lower_extension(path) != ".exr" || channels < 1 || channels > 4 || width < 1 || height < 1) return false;
  if (encode.tile != 0) return false;
  for (const auto& [name, value] : metadata.text)
    if (!plain_text_name(name)) return false;
  if (metadata.has_resolution && metadata.resolution_unit != "inch" && metadata.resolution_unit != "none")
    return false;
  try {
    const bool float_samples = !(source_format == SampleFormat::uint8 || source_format == SampleFormat::half);
    check_encode_choice("openexr", encode, float_samples);
  } catch (const Error&) {
    return false;  // refused in OpenImageIO's path's words
  }
  return true;
}

struct ExrWriter::Encoder {
  Imf::PixelType type = Imf::HALF;
  std::unique_ptr<StagedStream> stream;
  std::unique_ptr<Imf::OutputFile> file;
  std::vector<std::string> names;  // of the channels, in the order of the samples
  std::vector<Imath::half> halves;  // a band's samples, converted
};

ExrWriter::ExrWriter(StagedOutput& stage, int file, const std::string& path, int width, int height, int channels,
                     int alpha_channel, SampleFormat source_format, const ExrMetadata& metadata,
                     const EncodeOptions& encode)
    : encoder_(std::make_unique<Encoder>()), path_(path), width_(width), height_(height), channels_(channels) {
  if (!exr_writes(path, width, height, channels, source_format, metadata, encode))
    throw Error("cannot write '" + path + "' through OpenEXR alone");
  Encoder& e = *encoder_;
  e.type = pixel_type(source_format, encode);
  e.names = channel_names(channels, alpha_channel);
  use_all_cores();
  try {
    const Imf::Header header = exr_header(width, height, channels, alpha_channel, e.type, metadata, encode);
    e.stream = std::make_unique<StagedStream>(stage, file, stage.target().filename().string());
    e.file = std::make_unique<Imf::OutputFile>(*e.stream, header);
  } catch (const std::exception& error) {
    throw Error("cannot write '" + path + "': " + first_line(error.what()));
  }
}

ExrWriter::~ExrWriter() = default;

void ExrWriter::write(const float* rows, int count) {
  if (count <= 0) return;
  if (written_ + count > height_) throw Error("cannot write '" + path_ + "': more rows than the image has");
  Encoder& e = *encoder_;
  const std::size_t samples = std::size_t(width_) * channels_ * std::size_t(count);
  const char* data = reinterpret_cast<const char*>(rows);
  std::size_t sample_bytes = sizeof(float);
  if (e.type == Imf::HALF) {
    e.halves.resize(samples);
    to_halves(rows, samples, e.halves.data());
    data = reinterpret_cast<const char*>(e.halves.data());
    sample_bytes = sizeof(Imath::half);
  }
  const std::size_t pixel_bytes = sample_bytes * channels_, row_bytes = pixel_bytes * width_;
  try {
    Imf::FrameBuffer frame;
    for (int k = 0; k < channels_; ++k)
      frame.insert(e.names[std::size_t(k)],
                   Imf::Slice::Make(e.type, data + k * sample_bytes, Imath::V2i(0, written_), width_, count,
                                    pixel_bytes, row_bytes));
    e.file->setFrameBuffer(frame);
    e.file->writePixels(count);
  } catch (const std::exception& error) {
    throw Error("cannot write '" + path_ + "': " + first_line(error.what()));
  }
  written_ += count;
}

void ExrWriter::finish() {
  if (written_ != height_) throw Error("cannot write '" + path_ + "': only " + std::to_string(written_) + " rows");
  Encoder& e = *encoder_;
  try {
    e.file.reset();  // writes the table of line offsets
  } catch (const std::exception& error) {
    throw Error("cannot write '" + path_ + "': " + first_line(error.what()));
  }
}

}  // namespace ddt
