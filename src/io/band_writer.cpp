#include "io/band_writer.hpp"

#include "io/band_queue.hpp"
#include "io/oiio_output.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <optional>

namespace ddt {
namespace {

// Plugins that encode rows as they come (checked for OpenImageIO 2.4; the
// others, e.g. GIF, WebP, JPEG 2000, DPX, gather the image until close).
bool encodes_rows(const std::string& format) {
  for (const char* f : {"png", "tiff", "openexr", "jpeg", "bmp", "targa", "hdr", "pnm"})
    if (format == f) return true;
  return false;
}

int orientation(const OIIO::ParamValueList* metadata) {
  if (!metadata) return 1;
  const auto found = metadata->find("Orientation", OIIO::TypeUnknown, false);
  return found == metadata->cend() ? 1 : found->get_int();
}

}  // namespace

struct ImageBandWriter::State {
  std::string path;
  int width = 0, height = 0, channels = 0;
  SampleFormat source_format = SampleFormat::uint8;
  int alpha_channel = -1;
  OIIO::ParamValueList metadata;
  bool has_metadata = false;
  EncodeOptions encode;
  std::optional<BandOrder> order;

  // Not streamed: the bands gathered, written whole by finish().
  Image whole;

  // Streamed. Declared in this order so the plugin goes before its proxy
  // and the proxy before the staged file.
  std::unique_ptr<StagedOutput> stage;
  int file = -1;
  std::string name;
  std::unique_ptr<detail::StagedFileProxy> proxy;
  std::unique_ptr<OIIO::ImageOutput> out;
  int tile = 0;                   // tile height, 0: scanlines
  std::vector<float> pending;     // rows waiting for a full row of tiles
  int pending_first = 0;

  std::unique_ptr<BandQueue> encoder;

  bool streaming() const { return out != nullptr; }
  void fail(const std::string& why) const { throw Error("cannot write '" + path + "': " + detail::first_line(why)); }
  void open(const OIIO::ParamValueList* meta);
  void encode_band(const Image& rows, int first);
};

void ImageBandWriter::State::open(const OIIO::ParamValueList* meta) {
  out = OIIO::ImageOutput::create(path);
  if (!out) fail("no image format for its extension");
  OIIO::ImageSpec spec =
      detail::written_spec(path, width, height, channels, source_format, alpha_channel, meta, encode, *out);
  tile = spec.tile_width > 0 ? spec.tile_height : 0;
  if (std::string(out->format_name()) == "tiff" && double(spec.image_bytes()) > 3.5e9) spec.attribute("tiff:bigtiff", 1);
  stage = std::make_unique<StagedOutput>(path);
  name = stage->target().filename().string();
  file = stage->create(name);
  proxy = std::make_unique<detail::StagedFileProxy>(*stage, file, name);
  out->set_ioproxy(proxy.get());
  const detail::QuietLibraries quiet;
  if (!out->open(name, spec)) {
    const std::string why = out->geterror();
    out.reset();
    fail(why);
  }
}

void ImageBandWriter::State::encode_band(const Image& rows, int first) {
  if (tile == 0) {
    if (!out->write_scanlines(first, first + rows.height, 0, OIIO::TypeDesc::FLOAT, rows.pixels.data()))
      fail(out->geterror());
    return;
  }
  const std::size_t row_floats = static_cast<std::size_t>(width) * channels;
  pending.insert(pending.end(), rows.pixels.begin(), rows.pixels.end());
  int held = static_cast<int>(pending.size() / row_floats);
  // A row of tiles once tile rows are here, or the last rows of the image.
  while (held >= tile || (held > 0 && pending_first + held == height)) {
    const int n = std::min(tile, held);
    if (!out->write_tiles(0, width, pending_first, pending_first + n, 0, 1, OIIO::TypeDesc::FLOAT, pending.data()))
      fail(out->geterror());
    pending.erase(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(row_floats * n));
    pending_first += n;
    held -= n;
  }
}

ImageBandWriter::ImageBandWriter(const std::string& path, int width, int height, int channels,
                                 SampleFormat source_format, int alpha_channel, const OIIO::ParamValueList* metadata,
                                 const EncodeOptions& encode)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.path = path;
  s.width = width, s.height = height, s.channels = channels;
  s.order.emplace(path, width, height, channels);
  s.source_format = source_format;
  s.alpha_channel = alpha_channel;
  if (metadata) s.metadata = *metadata, s.has_metadata = true;
  s.encode = encode;
  if (width < 1 || height < 1 || channels < 1) s.fail("the image is empty");
  check_image_writable(path, width, height, channels, source_format, alpha_channel, encode);
  auto probe = OIIO::ImageOutput::create(path);
  const std::string format = probe ? probe->format_name() : "";
  const int turn = orientation(metadata);
  const bool turned = turn > 1 && turn <= 8 && format != "jpeg" && format != "tiff";
  // Written whole: a TIFF with EXIF too (written by path, image_io.cpp).
  if (!probe || !probe->supports("ioproxy") || !encodes_rows(format) || turned ||
      detail::tiff_needs_path(*probe, metadata))
    return;
  probe.reset();
  const OIIO::ParamValueList* meta = s.has_metadata ? &s.metadata : nullptr;
  try {
    s.open(meta);
  } catch (const Error& e) {
    // libpng refuses an ICC profile it judges malformed (and with it the
    // whole file): the image is then written without the profile, as
    // write_image does.
    if (!(format == "png" && meta && meta->contains("ICCProfile") &&
          std::string(e.what()).find("profile") != std::string::npos))
      throw;
    s.out.reset(), s.proxy.reset(), s.stage.reset();
    s.metadata.remove("ICCProfile");
    s.open(&s.metadata);
  }
  s.encoder = std::make_unique<BandQueue>([&s](const Image& rows, int first) { s.encode_band(rows, first); });
}

ImageBandWriter::~ImageBandWriter() {
  State& s = *state_;
  s.encoder.reset();
  const detail::QuietLibraries quiet;  // a plugin closed early complains ("No IDATs written")
  s.out.reset();
}

bool ImageBandWriter::streaming() const { return state_->streaming(); }

void ImageBandWriter::write(Image rows, int first_row) {
  State& s = *state_;
  if (!s.order->take(rows, first_row)) return;
  if (!s.streaming()) {
    if (s.whole.empty()) s.whole = Image(s.width, s.height, s.channels);
    std::copy(rows.pixels.begin(), rows.pixels.end(),
              s.whole.pixels.begin() + static_cast<std::ptrdiff_t>(s.whole.index(0, first_row)));
    return;
  }
  s.encoder->push(std::move(rows), first_row);
}

void ImageBandWriter::finish() {
  State& s = *state_;
  if (!s.order->finish()) return;
  if (!s.streaming()) {
    write_image(s.path, s.whole, s.source_format, s.alpha_channel, s.has_metadata ? &s.metadata : nullptr, s.encode);
    return;
  }
  s.encoder->finish();
  const detail::QuietLibraries quiet;
  if (!s.out->close()) s.fail(s.out->geterror());
  s.out.reset();
  s.stage->finish(s.file);  // throws with the first write error (ENOSPC, EFBIG, EIO)
  s.stage->commit({s.name});
}

}  // namespace ddt
