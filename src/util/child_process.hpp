#pragma once
// ddt::ChildProcess — a program run beside ours (posix_spawnp: looked up on
// PATH, no shell, so paths need no quoting), optionally with a pipe to its
// standard input or from its standard output; its standard error goes to
// an unnamed temporary file, whose last line explains a failure. What the
// video path runs FFmpeg with (io/video_io.hpp), and the experiments their
// peers.
//
// A ChildProcess that is destroyed before wait() kills its program.

#include <cstddef>
#include <string>
#include <vector>

#include <sys/types.h>

namespace ddt {

class ChildProcess {
 public:
  enum class Pipe { none, to_stdin, from_stdout };

  // Throws ddt::Error when the program cannot start (not installed).
  ChildProcess(const std::vector<std::string>& args, Pipe pipe = Pipe::none);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // Whole reads and writes through the pipe: false at the end of its output
  // (read: nothing more; a short last block throws ddt::Error) or when it
  // stopped reading (write).
  bool read(void* data, std::size_t bytes);
  std::size_t read_some(void* data, std::size_t bytes);  // 0 at the end
  bool write(const void* data, std::size_t bytes);
  // Closes our end of the pipe and waits: the exit status (-1 when killed).
  int wait();
  // The last line the program wrote on its standard error ("" if none).
  std::string last_error_line() const;

 private:
  pid_t pid_ = -1;
  int fd_ = -1;
  int stderr_fd_ = -1;
  bool waited_ = false;
};

// Runs a program to its end with its output discarded: the exit status, or
// -1 when it could not start.
int run_program(const std::vector<std::string>& args);

// The program's standard output, whole; throws ddt::Error when it fails.
std::string program_output(const std::vector<std::string>& args);

}  // namespace ddt
