#pragma once
// Files in and out without losing data: the rules every reader and writer
// of ddtscale shares (image_io, volume_io, point_table, mesh_view).
//
// Reading:
//   check_regular_file(path, what) throws unless `path` (after symlinks) is a
//   regular file: devices, FIFOs, sockets and directories are refused before
//   anything opens them (a FIFO blocks open(); /dev/zero feeds every format
//   plugin for ever).
//
// Identity: two paths name the same file when their device and inode agree
// (symlinks followed, hard links and every spelling of a path caught).
//
// Writing: StagedOutput. Everything written goes first into a private
// directory beside the target, made by mkdtemp (mode 0700, a name nobody
// could have chosen beforehand), so nobody else can plant a link where we
// write; each file in it is created with O_CREAT | O_EXCL | O_NOFOLLOW under
// its final name (so a 255-character name fits), written with every error
// seen (short writes and ENOSPC remembered even when the library that
// writes through us ignores them), fsync'ed and closed with errors checked.
// Only then does commit() rename each file over its target, the named
// target last (a NRRD data file before its header), and fsync the
// directory. Without commit() — an error, an exception, or SIGINT, SIGTERM,
// SIGHUP or SIGQUIT during the write — the private directory and what is in
// it are removed and the targets are untouched. SIGKILL cannot be caught:
// it leaves a .ddtscale-XXXXXX directory (never a damaged target).
//
// Output symlinks: a target that is a symlink is followed (to the end of the
// chain) and the file it points to is replaced; the link itself stays, as
// with a shell redirection. A link to a missing file is refused.
//
// Every function throws ddt::Error with a one-line message on failure.

#include <sys/types.h>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ddt {

// Throws "cannot read '<path>': ..." unless `path` is an existing regular
// file (or a symlink to one).
void check_regular_file(const std::string& path);

struct FileId {
  dev_t device = 0;
  ino_t inode = 0;
  bool operator==(const FileId&) const = default;
};

// The identity of the file at `path` (symlinks followed); nullopt when
// there is none.
std::optional<FileId> file_id(const std::string& path);

// Throws "output '<output>' is the input file ..." when `output` exists and
// is one of `inputs` (by identity), naming the input it would destroy.
void check_not_an_input(const std::string& output, const std::vector<std::string>& inputs);

// `path`, or, when it is a symlink, the file the chain of links ends at.
// Throws when a link points at nothing or the chain is too long.
std::filesystem::path resolve_output_link(const std::string& path);

// Writes `bytes` to `path` atomically and exclusively, as described above.
void write_file_atomically(const std::string& path, const std::string& bytes);

class StagedOutput {
 public:
  // Creates the private directory beside `target` (resolved through
  // resolve_output_link). Throws when it cannot.
  explicit StagedOutput(const std::string& target);
  ~StagedOutput();  // removes the private directory unless committed
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;

  // The final path (symlinks resolved) and its directory.
  const std::filesystem::path& target() const { return target_; }

  // A new file `name` (no '/') in the private directory, created
  // exclusively, open for reading and writing. Writes through write_at()
  // and write() never fail to the caller: the first error is remembered and
  // reported by finish(). Returns an index for the calls below.
  int create(const std::string& name);
  std::size_t write(int file, const void* data, std::size_t size);  // at the file's position
  std::size_t write_at(int file, const void* data, std::size_t size, off_t offset);
  std::size_t read_at(int file, void* data, std::size_t size, off_t offset);  // what a library reads back
  off_t size(int file) const;
  // For libraries that can only write to a path: the path of `name` in the
  // private directory, and adopt(name) once the library has closed it (so
  // finish() syncs it; the caller checks its content).
  std::filesystem::path stage_path(const std::string& name) const { return stage_ / name; }
  int adopt(const std::string& name);
  // fsync and close, then throw "cannot write '<target>': <first error>"
  // if any write failed. Idempotent.
  void finish(int file);

  // Renames the files, in `order` (names given to create()), from the
  // private directory into the target's directory. Refuses (before renaming
  // anything) to replace a directory or any file in `keep` (the inputs the
  // output was made from, by identity). Every file must be finished.
  void commit(const std::vector<std::string>& order, const std::vector<FileId>& keep = {});

 private:
  struct File {
    std::string name;
    int fd = -1;
    off_t pos = 0;
    int error = 0;  // first errno of a failed write, or 0
  };
  void fail(const std::string& why) const;
  std::filesystem::path target_, directory_, stage_;
  std::vector<File> files_;
  int slot_ = -1;  // registration for the signal handler
  bool committed_ = false;
};

}  // namespace ddt
