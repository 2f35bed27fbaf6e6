#include "util/child_process.hpp"

#include "util/error.hpp"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <sstream>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace ddt {

ChildProcess::ChildProcess(const std::vector<std::string>& args, Pipe pipe) {
  if (args.empty()) throw Error("no program to run");
  // The messages go to a file with no name (unlinked at once, so nothing
  // is left behind whatever ends us), read back through our descriptor.
  std::string name = "/tmp/ddtscale-stderr-XXXXXX";
  const int err = ::mkostemp(name.data(), O_CLOEXEC);
  if (err < 0) throw Error("cannot make a temporary file for " + args[0] + "'s messages");
  ::unlink(name.c_str());
  stderr_fd_ = err;
  int fds[2] = {-1, -1};
  if (pipe != Pipe::none && ::pipe2(fds, O_CLOEXEC) != 0) {
    ::close(err);
    stderr_fd_ = -1;
    throw Error("cannot make a pipe to " + args[0]);
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, err, 2);
  if (pipe == Pipe::to_stdin) {
    posix_spawn_file_actions_adddup2(&actions, fds[0], 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  } else if (pipe == Pipe::from_stdout) {
    posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  } else {
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  }
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const int started = posix_spawnp(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (pipe == Pipe::to_stdin) ::close(fds[0]), fd_ = fds[1];
  if (pipe == Pipe::from_stdout) ::close(fds[1]), fd_ = fds[0];
  if (started != 0) {
    if (fd_ >= 0) ::close(fd_);
    ::close(stderr_fd_);
    pid_ = -1;
    throw Error("cannot run '" + args[0] + "' (is it installed?)");
  }
}

ChildProcess::~ChildProcess() {
  if (fd_ >= 0) ::close(fd_);
  if (pid_ > 0 && !waited_) {
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }
  if (stderr_fd_ >= 0) ::close(stderr_fd_);
}

std::size_t ChildProcess::read_some(void* data, std::size_t bytes) {
  for (;;) {
    const ssize_t n = ::read(fd_, data, bytes);
    if (n >= 0) return static_cast<std::size_t>(n);
    if (errno != EINTR) throw Error("reading from a program failed");
  }
}

bool ChildProcess::read(void* data, std::size_t bytes) {
  auto* p = static_cast<char*>(data);
  std::size_t done = 0;
  while (done < bytes) {
    const std::size_t n = read_some(p + done, bytes - done);
    if (n == 0) {
      if (done == 0) return false;
      throw Error("a program's output ended in the middle of a block");
    }
    done += n;
  }
  return true;
}

bool ChildProcess::write(const void* data, std::size_t bytes) {
  const auto* p = static_cast<const char*>(data);
  std::size_t done = 0;
  // A reader that stopped would raise SIGPIPE: ignored while we write.
  struct sigaction ignore {}, previous {};
  ignore.sa_handler = SIG_IGN;
  ::sigaction(SIGPIPE, &ignore, &previous);
  bool ok = true;
  while (done < bytes) {
    const ssize_t n = ::write(fd_, p + done, bytes - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ok = false;
      break;
    }
    done += static_cast<std::size_t>(n);
  }
  ::sigaction(SIGPIPE, &previous, nullptr);
  return ok;
}

int ChildProcess::wait() {
  if (fd_ >= 0) ::close(fd_), fd_ = -1;
  if (pid_ <= 0 || waited_) return -1;
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0)
    if (errno != EINTR) return -1;
  waited_ = true;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string ChildProcess::last_error_line() const {
  std::string text;
  char block[4096];
  for (off_t at = 0;;) {
    const ssize_t n = ::pread(stderr_fd_, block, sizeof block, at);
    if (n <= 0) break;
    text.append(block, static_cast<std::size_t>(n));
    at += n;
  }
  std::string line, last;
  std::istringstream in(text);
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

int run_program(const std::vector<std::string>& args) {
  try {
    ChildProcess child(args);
    return child.wait();
  } catch (const Error&) {
    return -1;
  }
}

std::string program_output(const std::vector<std::string>& args) {
  ChildProcess child(args, ChildProcess::Pipe::from_stdout);
  std::string text;
  char block[4096];
  while (const std::size_t n = child.read_some(block, sizeof block)) text.append(block, n);
  if (child.wait() != 0) {
    const std::string error = child.last_error_line();
    throw Error(args[0] + " failed" + (error.empty() ? "" : ": " + error));
  }
  return text;
}

}  // namespace ddt
