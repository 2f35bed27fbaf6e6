#include "image_io.hpp"

#include "error.hpp"

#include <OpenImageIO/imageio.h>

#include <OpenImageIO/filesystem.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace ddt {
namespace {

SampleFormat sample_format_of(const OIIO::TypeDesc& t) {
  switch (t.basetype) {
    case OIIO::TypeDesc::UINT8:
    case OIIO::TypeDesc::INT8: return SampleFormat::uint8;
    case OIIO::TypeDesc::UINT16:
    case OIIO::TypeDesc::INT16: return SampleFormat::uint16;
    case OIIO::TypeDesc::HALF: return SampleFormat::half;
    default: return SampleFormat::float32;
  }
}

std::string first_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  auto nl = s.find('\n');
  if (nl != std::string::npos) s = s.substr(0, nl);
  return s;
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

OIIO::TypeDesc output_type(const std::string& path, SampleFormat source, const OIIO::ImageOutput& out) {
  const std::string ext = lower_extension(path);
  if (ext == ".exr" || ext == ".hdr" || ext == ".pfm") return OIIO::TypeDesc::FLOAT;
  OIIO::TypeDesc wanted = OIIO::TypeDesc::UINT8;
  if (source == SampleFormat::uint16 || source == SampleFormat::half || source == SampleFormat::float32)
    wanted = OIIO::TypeDesc::UINT16;
  if (ext == ".tif" || ext == ".tiff") {
    if (source == SampleFormat::half) return OIIO::TypeDesc::HALF;
    if (source == SampleFormat::float32) return OIIO::TypeDesc::FLOAT;
  }
  // Formats such as JPEG store 8 bits only; OIIO would convert anyway, but say it plainly.
  if (wanted == OIIO::TypeDesc::UINT16 && (ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".gif"))
    wanted = OIIO::TypeDesc::UINT8;
  (void)out;
  return wanted;
}

// libpng, under OpenImageIO, prints its own "libpng error: ..." (and
// warnings) on stderr before OpenImageIO hands the same error to us; we
// report it once, so stderr points at /dev/null while a file is read or
// written (one line per bad input). Nested and concurrent guards share the
// redirection; the last one out restores stderr.
class QuietLibraries {
 public:
  QuietLibraries() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (users_++ > 0) return;
    std::fflush(stderr);
    saved_ = ::dup(STDERR_FILENO);
    const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (saved_ >= 0 && null >= 0) ::dup2(null, STDERR_FILENO);
    if (null >= 0) ::close(null);
  }
  ~QuietLibraries() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (--users_ > 0) return;
    std::fflush(stderr);
    if (saved_ >= 0) ::dup2(saved_, STDERR_FILENO), ::close(saved_);
    saved_ = -1;
  }
  QuietLibraries(const QuietLibraries&) = delete;
  QuietLibraries& operator=(const QuietLibraries&) = delete;

 private:
  static inline std::mutex mutex_;
  static inline int users_ = 0;
  static inline int saved_ = -1;
};

}  // namespace

ImageFile read_image(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error("cannot read '" + path + "': no such file");
  if (fs::is_directory(path, ec)) throw Error("cannot read '" + path + "': it is a directory");
  const QuietLibraries quiet;
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    std::string msg = first_line(OIIO::geterror());
    throw Error("cannot read '" + path + "': " + (msg.empty() ? "unsupported or corrupt image" : msg));
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw Error("cannot read '" + path + "': the image is empty");
  if (spec.depth > 1) throw Error("cannot read '" + path + "': volume images are not 2D images");
  ImageFile file;
  file.format = sample_format_of(spec.format);
  file.alpha_channel = spec.alpha_channel;
  if (spec.alpha_channel >= 0) file.alpha_name = spec.channelnames[spec.alpha_channel];
  file.image = Image(spec.width, spec.height, spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, file.image.pixels.data())) {
    std::string msg = first_line(in->geterror());
    throw Error("cannot read '" + path + "': " + (msg.empty() ? "corrupt image data" : msg));
  }
  // A read that succeeds with a message is a damaged file decoded anyway
  // (a truncated JPEG comes back grey below the cut, "Premature end of
  // JPEG file"): refuse it rather than enlarge the damage.
  if (const std::string damage = first_line(in->geterror()); !damage.empty())
    throw Error("cannot read '" + path + "': " + damage);
  for (float v : file.image.pixels)
    if (!std::isfinite(v)) throw Error("cannot read '" + path + "': the image holds NaN or infinite samples");
  return file;
}

void check_output_path(const std::string& output, const std::string& input, bool image_format) {
  std::error_code ec;
  if (output.empty()) throw Error("no output file given");
  if (!input.empty() && fs::exists(output, ec) && fs::equivalent(output, input, ec))
    throw Error("output '" + output + "' is the input file; refusing to overwrite it");
  if (!input.empty() && fs::weakly_canonical(output, ec) == fs::weakly_canonical(input, ec))
    throw Error("output '" + output + "' is the input file; refusing to overwrite it");
  if (fs::is_directory(output, ec)) throw Error("output '" + output + "' is a directory");
  fs::path dir = fs::path(output).parent_path();
  if (dir.empty()) dir = ".";
  if (!fs::is_directory(dir, ec)) throw Error("output directory '" + dir.string() + "' does not exist");
  if (::access(dir.c_str(), W_OK) != 0) throw Error("output directory '" + dir.string() + "' is not writable");
  if (!image_format) return;
  auto probe = OIIO::ImageOutput::create(output);
  if (!probe) throw Error("cannot write '" + output + "': no image format for extension '" +
                          fs::path(output).extension().string() + "'");
}

void write_image(const std::string& path, const Image& image, SampleFormat source_format, int alpha_channel) {
  if (image.empty()) throw Error("cannot write '" + path + "': the image is empty");
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw Error("cannot write '" + path + "': no image format for extension '" +
                        fs::path(path).extension().string() + "'");
  OIIO::ImageSpec spec(image.width, image.height, image.channels, output_type(path, source_format, *out));
  if (alpha_channel >= 0 && alpha_channel < image.channels) {
    spec.alpha_channel = alpha_channel;
    spec.channelnames[alpha_channel].assign(1, 'A');
  }
  if (spec.format == OIIO::TypeDesc::FLOAT && lower_extension(path) == ".exr")
    spec.attribute("compression", "zip");

  // Same directory as the target so the rename is atomic; same extension
  // so any plugin that checks it is satisfied.
  fs::path target(path);
  fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::random_device rd;
  std::string tmp_name = ".";
  tmp_name += target.stem().string();
  tmp_name += ".tmp" + std::to_string(rd() % 1000000);
  tmp_name += target.extension().string();
  const fs::path tmp = dir / tmp_name;
  auto fail = [&](const std::string& why) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw Error("cannot write '" + path + "': " + first_line(why));
  };
  const QuietLibraries quiet;
  if (!out->open(tmp.string(), spec)) fail(out->geterror());
  if (!out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data())) fail(out->geterror());
  if (!out->close()) fail(out->geterror());
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) fail(ec.message());
}

void write_file_atomically(const std::string& path, const std::string& content) {
  fs::path target(path);
  fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::random_device rd;
  std::string tmp_name = ".";
  tmp_name += target.filename().string();
  tmp_name += ".tmp" + std::to_string(rd() % 1000000);
  const fs::path tmp = dir / tmp_name;
  {
    std::ofstream out(tmp, std::ios::binary);
    out << content;
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw Error("cannot write '" + path + "'");
    }
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw Error("cannot write '" + path + "': " + ec.message());
  }
}

std::vector<unsigned char> encode_png(const Image& image) {
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  auto out = OIIO::ImageOutput::create("png");
  if (!out) throw Error("PNG support is missing from OpenImageIO");
  OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::UINT8);
  out->set_ioproxy(&memory);
  if (!out->open("memory.png", spec) || !out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()) ||
      !out->close())
    throw Error("cannot encode PNG: " + first_line(out->geterror()));
  return bytes;
}

Image image_from_buf(const OIIO::ImageBuf& buf) {
  const OIIO::ImageSpec& spec = buf.spec();
  Image image(spec.width, spec.height, spec.nchannels);
  buf.get_pixels(OIIO::ROI(spec.x, spec.x + spec.width, spec.y, spec.y + spec.height, 0, 1, 0, spec.nchannels),
                 OIIO::TypeDesc::FLOAT, image.pixels.data());
  return image;
}

OIIO::ImageBuf buf_from_image(const Image& image) {
  OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf buf(spec);
  buf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, image.pixels.data());
  return buf;
}

}  // namespace ddt
