#pragma once
// ddt::IdatEncoder — a PNG's image data (its IDAT chunks) filtered here and
// compressed by Intel ISA-L's igzip (level 1) instead of zlib: about zlib
// level 1's size in a quarter of its time on enlarged photographs
// (docs/performance.md). PngWriter (png_file.hpp) uses it for the `fast`
// compression: libpng writes the chunks before the image data, this the
// IDAT chunks and IEND.
//
// The zlib stream is standard (32 KB window), so every PNG reader reads it;
// igzip picks its code for the processor, so the compressed bytes (never
// the pixels) may differ between machines.

#include <cstddef>
#include <functional>
#include <memory>
#include <string>

namespace ddt {

class IdatEncoder {
 public:
  using Sink = std::function<void(const unsigned char* bytes, std::size_t size)>;
  // `height` rows of `row_bytes` bytes, `pixel_bytes` bytes a pixel (PNG's
  // filter unit), filtered by PNG filter type `filter` (0 none, 1 sub, 2 up,
  // 3 average, 4 Paeth; as libpng, none where a single row or column
  // leaves nothing to predict from); the file's bytes go to `sink`. Errors
  // name `path` ("cannot write 'out.png': ...").
  IdatEncoder(std::size_t row_bytes, std::size_t pixel_bytes, std::size_t height, int filter, Sink sink,
              std::string path);
  ~IdatEncoder();
  IdatEncoder(const IdatEncoder&) = delete;
  IdatEncoder& operator=(const IdatEncoder&) = delete;

  // The next `count` rows, top to bottom, packed.
  void write(const unsigned char* rows, int count);
  // The end of the compressed stream, the last IDAT chunk and IEND.
  void finish();

 private:
  struct Stream;
  void compress(const unsigned char* bytes, std::size_t size, bool last);
  void emit_chunk();
  std::unique_ptr<Stream> stream_;
};

// The PNG filter type of a libpng filter flag (PNG_FILTER_UP: 2), or -1 for
// several flags (libpng's adaptive choice).
int png_filter_type(int libpng_filter_flags);

}  // namespace ddt
