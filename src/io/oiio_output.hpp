#pragma once
// What the image writers share (image_io.cpp, band_writer.cpp): quiet
// libraries, the staged file OpenImageIO writes through, the spec of an
// output. Internal to src/io.

#include "io/image_io.hpp"
#include "io/safe_file.hpp"
#include "util/text.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <mutex>
#include <string>

#include <fcntl.h>
#include <unistd.h>

namespace ddt::detail {

using ddt::first_line;

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

// OIIO's writer goes through this proxy into a file of a StagedOutput: a
// failed write is remembered there (and reported after close) instead of
// being returned to a plugin that may ignore it (libpng) or exit() on it
// (libjpeg).
class StagedFileProxy final : public OIIO::Filesystem::IOProxy {
 public:
  StagedFileProxy(StagedOutput& stage, int file, const std::string& name)
      : IOProxy(name, Write), stage_(stage), file_(file) {}
  const char* proxytype() const override { return "ddtscale-staged"; }
  void close() override { m_mode = Closed; }  // the StagedOutput syncs and closes
  bool seek(int64_t offset) override {
    m_pos = offset;
    return offset >= 0;
  }
  size_t read(void* buf, size_t size) override {
    const size_t n = stage_.read_at(file_, buf, size, m_pos);
    m_pos += static_cast<int64_t>(n);
    return n;
  }
  size_t write(const void* buf, size_t size) override {
    stage_.write_at(file_, buf, size, m_pos);
    m_pos += static_cast<int64_t>(size);
    return size;
  }
  size_t pread(void* buf, size_t size, int64_t offset) override { return stage_.read_at(file_, buf, size, offset); }
  size_t pwrite(const void* buf, size_t size, int64_t offset) override {
    return stage_.write_at(file_, buf, size, offset);
  }
  size_t size() const override { return static_cast<size_t>(stage_.size(file_)); }

 private:
  StagedOutput& stage_;
  int file_;
};

// The spec write_image gives a width x height x channels image for `out`:
// sample type, alpha, encoding options (throws when they do not suit), the
// metadata the format stores and, for EXR, the data and display windows.
// TIFF EXIF and GPS tags only when tiff_by_path (the plugin writes the path
// itself: through an IOProxy OpenImageIO 2.4 writes a broken TIFF with them).
OIIO::ImageSpec written_spec(const std::string& path, int width, int height, int channels, SampleFormat source_format,
                             int alpha_channel, const OIIO::ParamValueList* metadata, const EncodeOptions& encode,
                             const OIIO::ImageOutput& out, bool tiff_by_path = false);
// Whether `metadata` holds tags that make a TIFF be written by path.
bool tiff_needs_path(const OIIO::ImageOutput& out, const OIIO::ParamValueList* metadata);

}  // namespace ddt::detail
