#include "io/safe_file.hpp"

#include "util/error.hpp"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <system_error>

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace ddt {
namespace {

std::string errno_text(int error) { return std::strerror(error); }

// ---- Cleanup on signals -------------------------------------------------
// The private directories being written, for the handler. Fixed storage
// and atomics only: the handler may run at any instruction.
constexpr int max_stages = 32;
struct StageSlot {
  std::atomic<bool> used{false};
  char path[4096] = {};
};
StageSlot stage_slots[max_stages];
constexpr int cleanup_signals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
struct sigaction previous_actions[sizeof cleanup_signals / sizeof cleanup_signals[0]];

// Removes the files in `dir` and `dir`, with system calls only
// (async-signal-safe): getdents64, unlinkat, rmdir.
void remove_stage_signal_safe(const char* dir) {
  const int fd = ::open(dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd >= 0) {
    struct Entry {
      ino64_t inode;
      off64_t offset;
      unsigned short length;
      unsigned char type;
      char name[1];
    };
    alignas(8) char buffer[4096];
    for (int pass = 0; pass < 4; ++pass) {  // unlinking while listing may hide entries: list again
      ::lseek(fd, 0, SEEK_SET);
      long n = 0;
      bool removed = false;
      while ((n = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer)) > 0)
        for (long at = 0; at < n;) {
          const Entry* e = reinterpret_cast<const Entry*>(buffer + at);
          at += e->length;
          if (std::strcmp(e->name, ".") == 0 || std::strcmp(e->name, "..") == 0) continue;
          if (::unlinkat(fd, e->name, 0) == 0) removed = true;
        }
      if (!removed) break;
    }
    ::close(fd);
  }
  ::rmdir(dir);
}

void on_cleanup_signal(int sig) {
  const int saved_errno = errno;
  for (auto& slot : stage_slots)
    if (slot.used.load(std::memory_order_acquire)) remove_stage_signal_safe(slot.path);
  // Then what would have happened without us: the previous action (the
  // default ends the process with the signal's status).
  for (std::size_t i = 0; i < sizeof cleanup_signals / sizeof cleanup_signals[0]; ++i)
    if (cleanup_signals[i] == sig) ::sigaction(sig, &previous_actions[i], nullptr);
  errno = saved_errno;
  ::raise(sig);
}

void install_cleanup_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (std::size_t i = 0; i < sizeof cleanup_signals / sizeof cleanup_signals[0]; ++i) {
      struct sigaction old {};
      ::sigaction(cleanup_signals[i], nullptr, &old);
      previous_actions[i] = old;
      if (old.sa_handler == SIG_IGN) continue;  // e.g. nohup: keep ignoring
      struct sigaction action {};
      action.sa_handler = on_cleanup_signal;
      sigemptyset(&action.sa_mask);
      for (int s : cleanup_signals) sigaddset(&action.sa_mask, s);
      ::sigaction(cleanup_signals[i], &action, nullptr);
    }
  });
}

int register_stage(const std::string& path) {
  install_cleanup_handlers();
  if (path.size() >= sizeof stage_slots[0].path) return -1;
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  for (int i = 0; i < max_stages; ++i)
    if (!stage_slots[i].used.load(std::memory_order_relaxed)) {
      std::memcpy(stage_slots[i].path, path.c_str(), path.size() + 1);
      stage_slots[i].used.store(true, std::memory_order_release);
      return i;
    }
  return -1;  // more than max_stages writes at once: no cleanup on a signal, still atomic
}

void unregister_stage(int slot) {
  if (slot >= 0) stage_slots[slot].used.store(false, std::memory_order_release);
}

}  // namespace

void check_regular_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int error = errno;
    throw Error("cannot read '" + path + "': " + (error == ENOENT ? std::string("no such file") : errno_text(error)));
  }
  if (S_ISREG(st.st_mode)) return;
  const char* kind = S_ISDIR(st.st_mode)    ? "it is a directory"
                     : S_ISFIFO(st.st_mode) ? "it is a FIFO, not a regular file"
                     : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "it is a device, not a regular file"
                     : S_ISSOCK(st.st_mode)                       ? "it is a socket, not a regular file"
                                                                  : "not a regular file";
  throw Error("cannot read '" + path + "': " + kind);
}

std::optional<FileId> file_id(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::nullopt;
  return FileId{st.st_dev, st.st_ino};
}

void check_not_an_input(const std::string& output, const std::vector<std::string>& inputs) {
  const auto out = file_id(output);
  if (!out) return;
  for (const auto& input : inputs)
    if (file_id(input) == out)
      throw Error("output '" + output + "' is the input file" + (input == inputs.front() ? "" : " '" + input + "'") +
                  "; refusing to overwrite it");
}

fs::path resolve_output_link(const std::string& path) {
  fs::path p(path);
  for (int depth = 0; depth < 40; ++depth) {
    std::error_code ec;
    const fs::file_status status = fs::symlink_status(p, ec);
    if (!fs::is_symlink(status)) {
      if (depth > 0 && !fs::exists(status))
        throw Error("cannot write '" + path + "': it is a symlink to '" + p.string() + "', which does not exist");
      return p;
    }
    const fs::path link = fs::read_symlink(p, ec);
    if (ec) throw Error("cannot write '" + path + "': " + ec.message());
    p = link.is_absolute() ? link : p.parent_path() / link;
  }
  throw Error("cannot write '" + path + "': too many levels of symbolic links");
}

void write_file_atomically(const std::string& path, const std::string& bytes) {
  StagedOutput stage(path);
  const std::string name = stage.target().filename().string();
  const int file = stage.create(name);
  stage.write(file, bytes.data(), bytes.size());
  stage.finish(file);
  stage.commit({name});
}

// ---- StagedOutput --------------------------------------------------------

StagedOutput::StagedOutput(const std::string& target) {
  target_ = resolve_output_link(target);
  directory_ = target_.parent_path().empty() ? fs::path(".") : target_.parent_path();
  if (target_.filename().empty()) throw Error("cannot write '" + target + "': no file name");
  std::string pattern = (directory_ / ".ddtscale-XXXXXX").string();
  if (!::mkdtemp(pattern.data()))
    throw Error("cannot write '" + target + "': cannot create a temporary directory in '" + directory_.string() +
                "': " + errno_text(errno));
  stage_ = pattern;
  slot_ = register_stage(stage_.string());
}

StagedOutput::~StagedOutput() {
  for (File& f : files_)
    if (f.fd >= 0) ::close(f.fd);
  if (!committed_) remove_stage_signal_safe(stage_.c_str());  // also what a library left there
  unregister_stage(slot_);
}

void StagedOutput::fail(const std::string& why) const { throw Error("cannot write '" + target_.string() + "': " + why); }

int StagedOutput::create(const std::string& name) {
  if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..")
    fail("bad file name '" + name + "'");
  const int fd = ::open((stage_ / name).c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) fail(errno_text(errno));
  files_.push_back({name, fd, 0, 0});
  return static_cast<int>(files_.size()) - 1;
}

std::size_t StagedOutput::write_at(int file, const void* data, std::size_t size, off_t offset) {
  File& f = files_.at(static_cast<std::size_t>(file));
  const char* bytes = static_cast<const char*>(data);
  std::size_t done = 0;
  while (f.error == 0 && f.fd >= 0 && done < size) {
    const ssize_t n = ::pwrite(f.fd, bytes + done, size - done, offset + static_cast<off_t>(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) f.error = n < 0 ? errno : EIO;
    else done += static_cast<std::size_t>(n);
  }
  // The whole size is reported written even after a failure: libraries
  // that see a short write may call exit() (libjpeg) or go on regardless
  // (libpng); finish() reports the remembered error instead.
  return size;
}

std::size_t StagedOutput::write(int file, const void* data, std::size_t size) {
  File& f = files_.at(static_cast<std::size_t>(file));
  write_at(file, data, size, f.pos);
  f.pos += static_cast<off_t>(size);
  return size;
}

std::size_t StagedOutput::read_at(int file, void* data, std::size_t size, off_t offset) {
  const File& f = files_.at(static_cast<std::size_t>(file));
  std::size_t done = 0;
  while (f.fd >= 0 && done < size) {
    const ssize_t n = ::pread(f.fd, static_cast<char*>(data) + done, size - done, offset + static_cast<off_t>(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  return done;
}

int StagedOutput::adopt(const std::string& name) {
  const int fd = ::open((stage_ / name).c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) fail(errno_text(errno));
  files_.push_back({name, fd, 0, 0});
  return static_cast<int>(files_.size()) - 1;
}

off_t StagedOutput::size(int file) const {
  const File& f = files_.at(static_cast<std::size_t>(file));
  struct stat st {};
  return f.fd >= 0 && ::fstat(f.fd, &st) == 0 ? st.st_size : 0;
}

void StagedOutput::finish(int file) {
  File& f = files_.at(static_cast<std::size_t>(file));
  if (f.fd >= 0) {
    if (::fsync(f.fd) != 0 && f.error == 0 && errno != EINVAL) f.error = errno;
    if (::close(f.fd) != 0 && f.error == 0 && errno != EINTR) f.error = errno;
    f.fd = -1;
  }
  if (f.error) fail(errno_text(f.error));
}

void StagedOutput::commit(const std::vector<std::string>& order, const std::vector<FileId>& keep) {
  for (const std::string& name : order) {
    bool known = false;
    for (const File& f : files_)
      if (f.name == name) {
        if (f.fd >= 0 || f.error) fail("internal error: '" + name + "' not finished");
        known = true;
      }
    if (!known) fail("internal error: '" + name + "' was not written");
    const fs::path destination = directory_ / name;
    struct stat st {};
    if (::lstat(destination.c_str(), &st) == 0) {
      if (S_ISDIR(st.st_mode)) fail("a directory is in the way at '" + destination.string() + "'");
      // A link at a file name other than the target (a NRRD data file) is
      // replaced, not followed: what it pointed at is not ours to write.
      const auto existing = file_id(destination.string());
      for (const FileId& id : keep)
        if (existing && *existing == id && !S_ISLNK(st.st_mode))
          fail("it would replace '" + destination.string() + "', a file the input was read from; refusing");
    }
  }
  for (const std::string& name : order)
    if (::rename((stage_ / name).c_str(), (directory_ / name).c_str()) != 0) fail(errno_text(errno));
  committed_ = true;
  ::rmdir(stage_.c_str());
  const int dir = ::open(directory_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);  // the renames themselves durable; a failure here loses nothing already there
    ::close(dir);
  }
}

}  // namespace ddt
