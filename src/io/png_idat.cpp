#include "io/png_idat.hpp"

#include "util/error.hpp"

#include <isa-l/igzip_lib.h>
#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace ddt {

struct IdatEncoder::Stream {
  isal_zstream z;
  std::vector<std::uint8_t> level_buffer = std::vector<std::uint8_t>(ISAL_DEF_LVL1_DEFAULT);
  std::size_t row_bytes, pixel_bytes;
  int filter;
  Sink sink;
  std::string path;
  std::vector<unsigned char> previous, filtered;  // the last row written; a row filtered
  // A chunk being filled: length and type, then its data (CRC added at emission).
  std::vector<unsigned char> chunk;
  bool finished = false;
};

namespace {

constexpr std::size_t chunk_data_bytes = 1 << 18;  // IDAT chunks of 256 KB
constexpr std::size_t chunk_head = 8;              // length and type

void put_be32(unsigned char* p, std::uint32_t v) {
  p[0] = static_cast<unsigned char>(v >> 24);
  p[1] = static_cast<unsigned char>(v >> 16);
  p[2] = static_cast<unsigned char>(v >> 8);
  p[3] = static_cast<unsigned char>(v);
}

unsigned char paeth(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return static_cast<unsigned char>(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

// PNG's filter `type` of `row` against the row above (`up`: zeros for the
// first), `bpp` bytes a pixel; the type byte first.
void filter_row(int type, const unsigned char* row, const unsigned char* up, std::size_t n, std::size_t bpp,
                unsigned char* out) {
  *out++ = static_cast<unsigned char>(type);
  switch (type) {
    case 0:
      std::copy_n(row, n, out);
      break;
    case 1:
      for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<unsigned char>(row[i] - (i >= bpp ? row[i - bpp] : 0));
      break;
    case 2:
      for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<unsigned char>(row[i] - up[i]);
      break;
    case 3:
      for (std::size_t i = 0; i < n; ++i)
        out[i] = static_cast<unsigned char>(row[i] - ((i >= bpp ? row[i - bpp] : 0) + up[i]) / 2);
      break;
    default:
      for (std::size_t i = 0; i < n; ++i)
        out[i] = static_cast<unsigned char>(
            row[i] - paeth(i >= bpp ? row[i - bpp] : 0, up[i], i >= bpp ? up[i - bpp] : 0));
  }
}

}  // namespace

int png_filter_type(int flags) {
  switch (flags) {
    case PNG_FILTER_NONE: return 0;
    case PNG_FILTER_SUB: return 1;
    case PNG_FILTER_UP: return 2;
    case PNG_FILTER_AVG: return 3;
    case PNG_FILTER_PAETH: return 4;
    default: return -1;
  }
}

IdatEncoder::IdatEncoder(std::size_t row_bytes, std::size_t pixel_bytes, std::size_t height, int filter, Sink sink,
                         std::string path)
    : stream_(std::make_unique<Stream>()) {
  if (filter < 0 || filter > 4)
    throw Error("cannot write '" + path + "': PNG filter type " + std::to_string(filter) + " is not one of 0 to 4");
  // libpng's png_write_start_row: no row above in a one-row image, no
  // pixel to the left in a one-column one.
  if (height == 1 && (filter == 2 || filter == 3 || filter == 4)) filter = 0;
  if (row_bytes == pixel_bytes && (filter == 1 || filter == 3 || filter == 4)) filter = 0;
  Stream& s = *stream_;
  s.row_bytes = row_bytes;
  s.pixel_bytes = pixel_bytes;
  s.filter = filter;
  s.sink = std::move(sink);
  s.path = std::move(path);
  s.previous.assign(row_bytes, 0);
  isal_deflate_init(&s.z);
  s.z.level = 1;
  s.z.level_buf = s.level_buffer.data();
  s.z.level_buf_size = static_cast<std::uint32_t>(s.level_buffer.size());
  s.z.gzip_flag = IGZIP_ZLIB;
  s.chunk.resize(chunk_head + chunk_data_bytes);
  std::copy_n("IDAT", 4, s.chunk.begin() + 4);
  s.z.next_out = s.chunk.data() + chunk_head;
  s.z.avail_out = static_cast<std::uint32_t>(chunk_data_bytes);
}

IdatEncoder::~IdatEncoder() = default;

void IdatEncoder::write(const unsigned char* rows, int count) {
  Stream& s = *stream_;
  if (s.finished) throw Error("cannot write '" + s.path + "': image rows after the end of the image data");
  // Row by row, through one row's buffer: igzip buffers what it needs.
  s.filtered.resize(s.row_bytes + 1);
  for (int r = 0; r < count; ++r) {
    const unsigned char* row = rows + static_cast<std::size_t>(r) * s.row_bytes;
    const unsigned char* up = r == 0 ? s.previous.data() : row - s.row_bytes;
    filter_row(s.filter, row, up, s.row_bytes, s.pixel_bytes, s.filtered.data());
    compress(s.filtered.data(), s.filtered.size(), false);
  }
  if (count > 0) std::copy_n(rows + static_cast<std::size_t>(count - 1) * s.row_bytes, s.row_bytes, s.previous.begin());
}

void IdatEncoder::compress(const unsigned char* bytes, std::size_t size, bool last) {
  Stream& s = *stream_;
  s.z.next_in = const_cast<std::uint8_t*>(bytes);
  s.z.avail_in = static_cast<std::uint32_t>(size);  // bands are far below 4 GB
  s.z.end_of_stream = last ? 1 : 0;
  s.z.flush = NO_FLUSH;
  for (;;) {
    const std::uint32_t in_before = s.z.avail_in, out_before = s.z.avail_out;
    const auto state_before = s.z.internal_state.state;
    const int status = isal_deflate(&s.z);
    if (status != COMP_OK) throw Error("cannot write '" + s.path + "': igzip failed (status " + std::to_string(status) + ")");
    const bool done = last ? s.z.internal_state.state == ZSTATE_END : s.z.avail_in == 0;
    const bool stalled =
        s.z.avail_in == in_before && s.z.avail_out == out_before && s.z.internal_state.state == state_before;
    if (s.z.avail_out == 0) emit_chunk();
    if (done) break;
    if (stalled) throw Error("cannot write '" + s.path + "': igzip made no progress");
  }
}

void IdatEncoder::emit_chunk() {
  Stream& s = *stream_;
  const std::size_t length = chunk_data_bytes - s.z.avail_out;
  if (length > 0) {
    unsigned char* c = s.chunk.data();
    put_be32(c, static_cast<std::uint32_t>(length));
    const uLong crc = crc32(crc32(0L, Z_NULL, 0), c + 4, static_cast<uInt>(4 + length));
    unsigned char tail[4];
    put_be32(tail, static_cast<std::uint32_t>(crc));
    s.sink(c, chunk_head + length);
    s.sink(tail, 4);
  }
  s.z.next_out = s.chunk.data() + chunk_head;
  s.z.avail_out = static_cast<std::uint32_t>(chunk_data_bytes);
}

void IdatEncoder::finish() {
  Stream& s = *stream_;
  if (s.finished) return;
  compress(nullptr, 0, true);
  emit_chunk();
  s.finished = true;
  static constexpr unsigned char iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
  s.sink(iend, sizeof iend);
}

}  // namespace ddt
