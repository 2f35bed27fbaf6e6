#include "io/image_io.hpp"
#include "util/file_names.hpp"

#include "io/oiio_output.hpp"
#include "util/error.hpp"

#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <OpenImageIO/filesystem.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace ddt {
using detail::first_line;
using detail::QuietLibraries;
using detail::StagedFileProxy;
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

OIIO::TypeDesc output_type(const std::string& path, SampleFormat source, const OIIO::ImageOutput& out) {
  const std::string ext = lower_extension(path);
  // EXR: half floats hold 8-bit and half sources to a sixteenth of their
  // step (as oiiotool writes them); --float or --half choose (encode_options.hpp).
  if (ext == ".exr") return source == SampleFormat::uint8 || source == SampleFormat::half ? OIIO::TypeDesc::HALF
                                                                                          : OIIO::TypeDesc::FLOAT;
  if (ext == ".hdr" || ext == ".pfm") return OIIO::TypeDesc::FLOAT;
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

// Attributes of an input carried to the output (ImageFile::metadata); the
// rest describe the file's encoding (compression, planar layout, plugin
// state) and are the writer's to choose.
// The windows of ImageFile::metadata: the data window's origin (int[2]) and
// the display window (int[4]: x, y, width, height).
constexpr const char* data_origin = "ddtscale:data_origin";
constexpr const char* display_window = "ddtscale:display_window";

bool carried(const std::string& name) {
  for (const char* exact : {"ICCProfile", "Orientation", "XResolution", "YResolution", "ResolutionUnit", "Artist",
                            "Copyright", "ImageDescription", "DateTime", "Make", "Model", "DocumentName"})
    if (name == exact) return true;
  for (const char* prefix : {"Exif:", "GPS:", "IPTC:"})
    if (name.rfind(prefix, 0) == 0) return true;
  return false;
}

}  // namespace

OIIO::ParamValueList scaled_metadata(const OIIO::ParamValueList& metadata, double scale_x, double scale_y) {
  OIIO::ParamValueList out;
  for (const OIIO::ParamValue& p : metadata) {
    const std::string name = p.name().string();
    if (name == "Exif:PixelXDimension" || name == "Exif:PixelYDimension") continue;
    if ((name == data_origin && p.type() == OIIO::TypeDesc(OIIO::TypeDesc::INT, 2)) ||
        (name == display_window && p.type() == OIIO::TypeDesc(OIIO::TypeDesc::INT, 4))) {
      // Window corners land where the enlargement maps them (output pixel X
      // is input position (X + 0.5) / scale_x), rounded half up to whole pixels.
      const int* v = static_cast<const int*>(p.data());
      int scaled[4] = {};
      for (int k = 0; k < p.type().arraylen; ++k)
        scaled[k] = static_cast<int>(std::clamp(std::floor(v[k] * (k % 2 == 0 ? scale_x : scale_y) + 0.5), -1e9, 1e9));
      if (name == display_window) scaled[2] = std::max(1, scaled[2]), scaled[3] = std::max(1, scaled[3]);
      out.attribute(name, p.type(), scaled);
      continue;
    }
    if ((name == "XResolution" || name == "YResolution") && p.type() == OIIO::TypeDesc::FLOAT) {
      const float resolution = p.get_float() * static_cast<float>(name == "XResolution" ? scale_x : scale_y);
      out.attribute(name, resolution);
      continue;
    }
    out.push_back(p);
  }
  return out;
}

namespace {

// Opens `path` and checks its header (size, and with decode_whole the
// memory of decoding it whole; then limits.check); `file` gets everything
// but the pixels.
std::unique_ptr<OIIO::ImageInput> open_checked(const std::string& path, const ImageReadLimits& limits,
                                               bool decode_whole, ImageFile& file) {
  check_regular_file(path);
  // OpenEXR 3.1's C++ header reader sizes a string attribute from the file
  // and allocates it before reading it: a 405-byte file (found by
  // fuzz/fuzz_image) took 2 GB and 4 s to refuse. Its core C library checks
  // attribute sizes against the file and refuses it at once.
  static const bool exr_core = OIIO::attribute("openexr:core", 1);
  (void)exr_core;
  auto in = [&] {
    const QuietLibraries quiet;
    return OIIO::ImageInput::open(path);
  }();
  if (!in) {
    std::string msg = first_line(OIIO::geterror());
    throw Error("cannot read '" + path + "': " + (msg.empty() ? "unsupported or corrupt image" : msg));
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw Error("cannot read '" + path + "': the image is empty");
  if (spec.depth > 1) throw Error("cannot read '" + path + "': volume images are not 2D images");
  // The header's claims, before a pixel is decoded (decompression bombs).
  const std::string input = "input '" + path + "'";
  check_size_limit(input, std::to_string(spec.width) + "x" + std::to_string(spec.height),
                   checked_product({spec.width, spec.height}), limits.max_pixels, limits.option);
  if (spec.tile_width > 0)
    check_size_limit(input + ": a tile", std::to_string(spec.tile_width) + "x" + std::to_string(spec.tile_height),
                     checked_product({spec.tile_width, std::max(1, spec.tile_height), std::max(1, spec.tile_depth)}),
                     limits.max_pixels, limits.option);
  if (decode_whole)
    check_memory_fits("decoding " + input + " (" + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                          "x" + std::to_string(spec.nchannels) + ")",
                      4.0 * spec.width * spec.height * spec.nchannels);
  if (limits.check)
    limits.check(ImageHeader{spec.width, spec.height, spec.nchannels, sample_format_of(spec.format), spec.alpha_channel});
  for (const OIIO::ParamValue& p : spec.extra_attribs)
    if (carried(p.name().string())) file.metadata.push_back(p);
  // A data window (the pixels read) placed in a display window other than
  // itself, as EXR stores them: kept for an EXR output.
  if (spec.x != 0 || spec.y != 0 || spec.full_x != spec.x || spec.full_y != spec.y || spec.full_width != spec.width ||
      spec.full_height != spec.height) {
    const int origin[2] = {spec.x, spec.y};
    const int display[4] = {spec.full_x, spec.full_y, spec.full_width, spec.full_height};
    file.metadata.attribute(data_origin, OIIO::TypeDesc(OIIO::TypeDesc::INT, 2), origin);
    file.metadata.attribute(display_window, OIIO::TypeDesc(OIIO::TypeDesc::INT, 4), display);
  }
  file.format = sample_format_of(spec.format);
  file.alpha_channel = spec.alpha_channel;
  return in;
}

// A read that succeeds with a message is a damaged file decoded anyway (a
// truncated JPEG comes back grey below the cut, "Premature end of JPEG
// file"): refused rather than enlarged; so are NaN and infinite samples.
void check_decoded(OIIO::ImageInput& in, bool ok, const std::string& path, const float* begin, const float* end) {
  if (!ok) {
    std::string msg = first_line(in.geterror());
    throw Error("cannot read '" + path + "': " + (msg.empty() ? "corrupt image data" : msg));
  }
  if (const std::string damage = first_line(in.geterror()); !damage.empty())
    throw Error("cannot read '" + path + "': " + damage);
  for (const float* v = begin; v != end; ++v)
    if (!std::isfinite(*v)) throw Error("cannot read '" + path + "': the image holds NaN or infinite samples");
}

}  // namespace

ImageFile read_image(const std::string& path, const ImageReadLimits& limits) {
  ImageFile file;
  std::unique_ptr<OIIO::ImageInput> in = open_checked(path, limits, true, file);
  const OIIO::ImageSpec& spec = in->spec();
  const QuietLibraries quiet;
  file.image = Image(spec.width, spec.height, spec.nchannels);
  const bool ok = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, file.image.pixels.data());
  check_decoded(*in, ok, path, file.image.pixels.data(), file.image.pixels.data() + file.image.pixels.size());
  // Further pages or parts, counted last: seeking changes in->spec().
  file.pages = in->spec().get_int_attribute("oiio:subimages", 0);
  if (file.pages < 1) file.pages = in->seek_subimage(1, 0) ? 2 : 1;
  return file;
}

ImageRowReader::ImageRowReader(const std::string& path, const ImageReadLimits& limits) : path_(path) {
  in_ = open_checked(path, limits, false, file_);
  const OIIO::ImageSpec& spec = in_->spec();
  header_ = ImageHeader{spec.width, spec.height, spec.nchannels, file_.format, file_.alpha_channel};
  // Counted as read_image counts them, by a second reader: a failed seek
  // can leave a plugin (TIFF) unable to read the first page.
  file_.pages = spec.get_int_attribute("oiio:subimages", 0);
  if (file_.pages < 1) {
    const QuietLibraries quiet;
    auto probe = OIIO::ImageInput::open(path);
    file_.pages = probe && probe->seek_subimage(1, 0) ? 2 : 1;
  }
}

ImageRowReader::~ImageRowReader() = default;

void ImageRowReader::read(int first, int end, float* rows) {
  if (first < 0 || end > header_.height || first > end) throw Error("cannot read rows outside '" + path_ + "'");
  if (first == end) return;
  const QuietLibraries quiet;
  const OIIO::ImageSpec& spec = in_->spec();
  const std::size_t row_floats = static_cast<std::size_t>(header_.width) * header_.channels;
  const int C = header_.channels;
  bool ok = false;
  if (spec.tile_width > 0 && spec.tile_height > 0) {
    // Tiled files are read by whole rows of tiles (OpenImageIO's scanline
    // reads do not take them), then the rows asked for copied out.
    const int th = spec.tile_height;
    const int a = first / th * th, b = std::min(header_.height, (end + th - 1) / th * th);
    std::vector<float> tiles(row_floats * (b - a));
    ok = in_->read_tiles(0, 0, spec.x, spec.x + spec.width, spec.y + a, spec.y + b, spec.z, spec.z + 1, 0, C,
                         OIIO::TypeDesc::FLOAT, tiles.data());
    if (ok)
      std::copy(tiles.begin() + static_cast<std::ptrdiff_t>(row_floats * (first - a)),
                tiles.begin() + static_cast<std::ptrdiff_t>(row_floats * (end - a)), rows);
  } else {
    ok = in_->read_scanlines(0, 0, spec.y + first, spec.y + end, spec.z, 0, C, OIIO::TypeDesc::FLOAT, rows);
  }
  check_decoded(*in_, ok, path_, rows, rows + row_floats * (end - first));
}

namespace {

// `options` (checked) as the attributes of `spec` for `format`; the sample
// type follows --half and --float for EXR. After the spec's format is set.
void apply_encode_options(const std::string& format, const EncodeOptions& options, OIIO::ImageSpec& spec) {
  check_encode_choice(format, options, spec.format.basetype == OIIO::TypeDesc::FLOAT);
  if (options.tile != 0) {
    spec.tile_width = spec.tile_height = options.tile;
    spec.tile_depth = 1;
  }
  if (format == "jpeg") {
    const int quality = options.quality > 0 ? options.quality : 90;
    spec.attribute("compression", "jpeg:" + std::to_string(quality));
    spec.attribute("CompressionQuality", quality);
    return;
  }
  if (default_compression(format).empty()) return;
  if (format == "png") {
    const PngEncoding png = png_encoding(options);
    spec.attribute("png:compressionLevel", png.level);
    spec.attribute("png:filter", png.filter);
    spec.attribute("compression", png.strategy_name);
    return;
  }
  const NamedCompression c = named_compression(format, options);
  if (format == "openexr") {
    // OpenImageIO 2.4 reads the DWA level from the name only ("dwaa:45").
    spec.attribute("compression", c.level >= 0 ? c.name + ":" + std::to_string(c.level) : c.name);
    if (options.half) spec.set_format(OIIO::TypeDesc::HALF);
    if (options.full_float) spec.set_format(OIIO::TypeDesc::FLOAT);
  } else if (format == "tiff") {
    if (c.name == "jpeg" && spec.format.basetype != OIIO::TypeDesc::UINT8 && spec.format.size() > 1)
      throw Error("--compression jpeg: TIFF stores JPEG for 8-bit images only");
    spec.attribute("compression", c.name);
    if (c.name == "zip") spec.attribute("tiff:zipquality", c.level);
    if (c.name == "jpeg") spec.attribute("CompressionQuality", c.level);
    if (options.half) spec.set_format(OIIO::TypeDesc::HALF);
  }
}

OIIO::ImageSpec output_spec(const std::string& path, int width, int height, int channels, SampleFormat source_format,
                            int alpha_channel, const OIIO::ImageOutput& out, const EncodeOptions& encode) {
  OIIO::ImageSpec spec(width, height, channels, output_type(path, source_format, out));
  if (alpha_channel >= 0 && alpha_channel < channels) {
    spec.alpha_channel = alpha_channel;
    spec.channelnames[alpha_channel].assign(1, 'A');
  }
  apply_encode_options(out.format_name(), encode, spec);
  return spec;
}

// Writers whose open() validates the size and that encode row by row, so a
// trial open at the full size costs nothing (checked for OIIO 2.4: the
// others, e.g. GIF, WebP, JPEG 2000, DPX, encode the whole image at close).
bool trial_at_full_size(const std::string& format) {
  for (const char* f : {"png", "tiff", "openexr", "bmp", "targa", "hdr", "pnm", "iff"})
    if (format == f) return true;
  return false;
}

}  // namespace

void check_image_writable(const std::string& path, int width, int height, int channels, SampleFormat source_format,
                          int alpha_channel, const EncodeOptions& encode) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw Error("cannot write '" + path + "': no image format for extension '" +
                        fs::path(path).extension().string() + "'");
  const std::string format = out->format_name();
  const std::string refuse = "cannot write '" + path + "': ";
  // libdpx aborts in open() for these (checked for OIIO 2.4).
  if (format == "dpx" && channels != 1 && channels != 3 && channels != 4)
    throw Error(refuse + "DPX stores 1, 3 or 4 channels, the image has " + std::to_string(channels));
  if (format == "jpeg" && (width > 65500 || height > 65500))
    throw Error(refuse + "JPEG stores at most 65500 pixels a side, the image is " + std::to_string(width) + "x" +
                std::to_string(height));
  const OIIO::ImageSpec checked = output_spec(path, 1, 1, channels, source_format, alpha_channel, *out, encode);
  (void)checked;  // the encoding options, checked against the sample type
  if (!out->supports("ioproxy")) return;  // a trial would create a file; its errors come at the write
  const bool full = trial_at_full_size(format);
  const OIIO::ImageSpec spec = output_spec(path, full ? width : std::min(width, 16), full ? height : std::min(height, 16),
                                           channels, source_format, alpha_channel, *out, encode);
  std::vector<unsigned char> scratch;
  OIIO::Filesystem::IOVecOutput memory(scratch);
  out->set_ioproxy(&memory);
  const QuietLibraries quiet;
  if (!out->open(fs::path(path).filename().string(), spec)) throw Error(refuse + first_line(out->geterror()));
  out.reset();  // close: a few bytes of header into `scratch`
}

OIIO::ImageSpec detail::written_spec(const std::string& path, int width, int height, int channels,
                                     SampleFormat source_format, int alpha_channel,
                                     const OIIO::ParamValueList* metadata, const EncodeOptions& encode,
                                     const OIIO::ImageOutput& out, bool tiff_by_path) {
  OIIO::ImageSpec spec = output_spec(path, width, height, channels, source_format, alpha_channel, out, encode);
  // OpenImageIO 2.4's TIFF writer, through an IOProxy, writes a file
  // without its ImageLength tag when EXIF or GPS tags are given (they go to
  // a sub-directory): they are kept only when the TIFF is written by path.
  const bool tiff = std::string(out.format_name()) == "tiff";
  if (metadata)
    for (const OIIO::ParamValue& p : *metadata) {
      const std::string name = p.name().string();
      if (tiff && !tiff_by_path && (name.rfind("Exif:", 0) == 0 || name.rfind("GPS:", 0) == 0)) continue;
      if (name.rfind("ddtscale:", 0) == 0) continue;
      spec.extra_attribs.add_or_replace(p);
    }
  if (metadata && out.format_name() == std::string("openexr")) {
    const auto origin = metadata->find(data_origin, OIIO::TypeDesc(OIIO::TypeDesc::INT, 2), false);
    const auto display = metadata->find(display_window, OIIO::TypeDesc(OIIO::TypeDesc::INT, 4), false);
    if (origin != metadata->cend() && display != metadata->cend()) {
      const int* o = static_cast<const int*>(origin->data());
      const int* d = static_cast<const int*>(display->data());
      spec.x = o[0], spec.y = o[1];
      spec.full_x = d[0], spec.full_y = d[1], spec.full_width = d[2], spec.full_height = d[3];
    }
  }
  return spec;
}

bool detail::tiff_needs_path(const OIIO::ImageOutput& out, const OIIO::ParamValueList* metadata) {
  if (std::string(out.format_name()) != "tiff" || !metadata) return false;
  for (const OIIO::ParamValue& p : *metadata) {
    const std::string name = p.name().string();
    if (name.rfind("Exif:", 0) == 0 || name.rfind("GPS:", 0) == 0) return true;
  }
  return false;
}

void write_image(const std::string& path, const Image& image, SampleFormat source_format, int alpha_channel,
                 const OIIO::ParamValueList* metadata, const EncodeOptions& encode) {
  if (image.empty()) throw Error("cannot write '" + path + "': the image is empty");
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw Error("cannot write '" + path + "': no image format for extension '" +
                        fs::path(path).extension().string() + "'");
  // The EXIF orientation: JPEG and TIFF carry the tag, which viewers honour;
  // for the other formats (PNG has none in OpenImageIO 2.4's writer) it is
  // applied to the pixels, so a portrait photograph stays upright.
  int turn = 1;
  if (metadata)
    if (const auto found = metadata->find("Orientation", OIIO::TypeUnknown, false); found != metadata->cend())
      turn = found->get_int();
  if (turn > 1 && turn <= 8 && out->format_name() != std::string("jpeg") && out->format_name() != std::string("tiff")) {
    OIIO::ImageBuf buf = buf_from_image(image);
    buf.specmod().attribute("Orientation", turn);
    OIIO::ParamValueList upright = *metadata;
    upright.remove("Orientation");
    upright.remove(data_origin);  // the windows describe the image as stored
    upright.remove(display_window);
    write_image(path, image_from_buf(OIIO::ImageBufAlgo::reorient(buf)), source_format, alpha_channel, &upright, encode);
    return;
  }
  // libpng refuses an ICC profile it judges malformed (and with it the
  // whole file): the image is then written without the profile.
  if (out->format_name() == std::string("png") && metadata && metadata->contains("ICCProfile") &&
      !metadata->contains("ddtscale:icc_checked")) {
    try {
      OIIO::ParamValueList checked = *metadata;
      checked.attribute("ddtscale:icc_checked", 1);
      write_image(path, image, source_format, alpha_channel, &checked, encode);
      return;
    } catch (const Error& e) {
      if (std::string(e.what()).find("profile") == std::string::npos) throw;
    }
    OIIO::ParamValueList without = *metadata;
    without.remove("ICCProfile");
    write_image(path, image, source_format, alpha_channel, &without, encode);
    return;
  }
  check_image_writable(path, image.width, image.height, image.channels, source_format, alpha_channel, encode);
  const bool by_path = !out->supports("ioproxy") || detail::tiff_needs_path(*out, metadata);
  const OIIO::ImageSpec spec = detail::written_spec(path, image.width, image.height, image.channels, source_format,
                                                    alpha_channel, metadata, encode, *out, by_path);

  StagedOutput stage(path);
  const std::string name = stage.target().filename().string();
  auto fail = [&](const std::string& why) { throw Error("cannot write '" + path + "': " + first_line(why)); };
  const QuietLibraries quiet;
  if (!by_path) {
    const int file = stage.create(name);
    StagedFileProxy proxy(stage, file, name);
    out->set_ioproxy(&proxy);
    if (!out->open(name, spec)) fail(out->geterror());
    if (!out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data())) fail(out->geterror());
    if (!out->close()) fail(out->geterror());
    out.reset();
    stage.finish(file);  // throws with the first write error (ENOSPC, EFBIG, EIO)
  } else {
    // The plugin opens the path itself, in the private directory (mode 0700,
    // a name nobody could plant a link at): read the file back in full,
    // since its write errors may go unseen.
    const std::string staged = stage.stage_path(name).string();
    // libtiff's messages drop the system's reason ("Write error at scanline
    // 864" on a full disk): it is taken from errno, right after the failure.
    auto fail_by_path = [&] {
      const int error = errno;
      const std::string why = first_line(out->geterror());
      if (error == ENOSPC || error == EDQUOT || error == EFBIG || error == EIO)
        fail(std::string(std::strerror(error)) + " (" + why + ")");
      fail(why);
    };
    errno = 0;
    if (!out->open(staged, spec)) fail_by_path();
    if (!out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data())) fail_by_path();
    if (!out->close()) fail_by_path();
    out.reset();
    stage.finish(stage.adopt(name));
    auto in = OIIO::ImageInput::open(staged);
    std::vector<float> check(image.pixels.size());
    if (!in || in->spec().width != image.width || in->spec().height != image.height ||
        !in->read_image(0, 0, 0, image.channels, OIIO::TypeDesc::FLOAT, check.data()))
      fail("the written file does not read back: " + (in ? in->geterror() : OIIO::geterror()));
  }
  stage.commit({name});
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
