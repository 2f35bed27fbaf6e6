#include "util/child_process.hpp"
#include "util/error.hpp"

#include <doctest/doctest.h>

#include <string>

using namespace ddt;

TEST_CASE("ChildProcess: exit status, output, pipes both ways, a missing program") {
  CHECK(run_program({"true"}) == 0);
  CHECK(run_program({"false"}) == 1);
  CHECK(run_program({"ddtscale-no-such-program"}) == -1);
  CHECK_THROWS_AS(ChildProcess({"ddtscale-no-such-program"}), Error);
  CHECK(program_output({"printf", "a b\\nc"}) == "a b\nc");  // no shell: the argument arrives as given
  CHECK_THROWS_WITH_AS(program_output({"sh", "-c", "echo first >&2; echo why >&2; exit 3"}),
                       doctest::Contains("sh failed: why"), Error);

  // Bytes through a pipe and back: cat copies stdin to a file we read.
  ChildProcess writer({"sh", "-c", "cat > /dev/null; exit 0"}, ChildProcess::Pipe::to_stdin);
  const std::string block(1 << 20, 'x');  // larger than a pipe's buffer
  CHECK(writer.write(block.data(), block.size()));
  CHECK(writer.wait() == 0);

  ChildProcess reader({"head", "-c", "10", "/dev/zero"}, ChildProcess::Pipe::from_stdout);
  char bytes[4] = {1, 1, 1, 1};
  CHECK(reader.read(bytes, 4));
  CHECK(bytes[0] == 0);
  CHECK(reader.read(bytes, 4));
  CHECK_THROWS_AS(reader.read(bytes, 4), Error);  // 2 bytes left: a short block
  CHECK(reader.wait() == 0);

  // A reader that stops: our write reports it instead of dying of SIGPIPE.
  ChildProcess quitter({"true"}, ChildProcess::Pipe::to_stdin);
  bool stopped = false;
  for (int k = 0; k < 64 && !stopped; ++k) stopped = !quitter.write(block.data(), block.size());
  CHECK(stopped);
  CHECK(quitter.wait() == 0);
}
