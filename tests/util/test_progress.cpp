#include "util/progress.hpp"
#include "pipeline/upscale.hpp"

#include <doctest/doctest.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

using namespace ddt;

namespace {

std::string contents(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string s;
  char buf[4096];
  std::size_t got;
  while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) s.append(buf, got);
  return s;
}

}  // namespace

TEST_CASE("Progress: stages, units from many threads, fraction") {
  Progress p;
  CHECK(p.snapshot().stage.empty());
  CHECK(p.snapshot().fraction() == 0);
  p.begin("optimize", 4000);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&] {
      for (int i = 0; i < 500; ++i) p.add(1);
    });
  for (auto& t : threads) t.join();
  Progress::Snapshot s = p.snapshot();
  CHECK(s.stage == "optimize");
  CHECK(s.done == 2000);
  CHECK(s.fraction() == doctest::Approx(0.5));
  p.set(9000);
  CHECK(p.snapshot().fraction() == 1.0);  // clamped
  p.begin("write");                       // unknown total
  CHECK(p.snapshot().done == 0);
  CHECK(p.snapshot().fraction() == 0);
}

TEST_CASE("Progress: once cancelled, every report throws Cancelled, and the pipeline stops by it") {
  Progress progress;
  progress.begin("work", 10);
  progress.add(3);
  CHECK_FALSE(progress.cancelled());
  progress.cancel();
  CHECK(progress.cancelled());
  CHECK_THROWS_AS(progress.add(1), Cancelled);
  CHECK_THROWS_AS(progress.set(5), Cancelled);
  CHECK_THROWS_AS(progress.begin("next"), Cancelled);
  CHECK(progress.snapshot().done == 3);  // nothing counted after the cancel
  // During the work: cancelled when the triangulation is logged, the
  // enlargement stops at its next report (the optimizer's stage) by it.
  Image noise(96, 96, 1);
  for (std::size_t i = 0; i < noise.pixels.size(); ++i) noise.pixels[i] = float((i * 7919) % 101) / 100.0f;
  Progress running;
  UpscaleOptions options;
  options.progress = &running;
  std::vector<std::string> logged;
  options.log = [&](const std::string& line) {
    logged.push_back(line);
    if (line.rfind("triangulate", 0) == 0) running.cancel();
  };
  CHECK_THROWS_AS(upscale(noise, 960, 960, options), Cancelled);
  REQUIRE_FALSE(logged.empty());
  CHECK(logged.back().rfind("triangulate", 0) == 0);  // nothing after it ran to its end
}

TEST_CASE("ProgressBar: the text of the bar") {
  Progress::Snapshot s;
  s.stage = "render";
  s.total = 10, s.done = 5;
  const std::string half = ProgressBar::format(s, 2.0, 10);
  CHECK(half.find("render") == 0);
  CHECK(half.find("[=====>    ]") != std::string::npos);
  CHECK(half.find(" 50%") != std::string::npos);
  CHECK(half.find("2.0 s") != std::string::npos);
  s.total = 0;  // unknown: a marker, no percentage
  const std::string unknown = ProgressBar::format(s, 0.3, 10);
  CHECK(unknown.find('*') != std::string::npos);
  CHECK(unknown.find('%') == std::string::npos);
}

TEST_CASE("ProgressBar: silent for short runs, drawn and erased for long ones") {
  Progress p;
  p.begin("optimize", 100);
  {
    std::FILE* f = std::tmpfile();
    REQUIRE(f);
    ProgressBar bar(p, f);  // default delay: one second
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    bar.stop();
    CHECK(contents(f).empty());
    std::fclose(f);
  }
  {
    std::FILE* f = std::tmpfile();
    REQUIRE(f);
    ProgressBar::Options o;
    o.delay = std::chrono::milliseconds(0);
    o.period = std::chrono::milliseconds(5);
    ProgressBar bar(p, f, o);
    p.set(25);
    std::this_thread::sleep_for(std::chrono::milliseconds(40));
    bar.print("a log line");                                     // erases the bar, writes the line ...
    std::this_thread::sleep_for(std::chrono::milliseconds(40));  // ... and the bar comes back below it
    bar.stop();
    bar.stop();  // idempotent
    const std::string out = contents(f);
    CHECK(out.find("ddtscale: optimize") != std::string::npos);
    CHECK(out.find("25%") != std::string::npos);
    CHECK(out.find("a log line\n") != std::string::npos);
    CHECK(out.size() >= 4);
    CHECK(out.substr(out.size() - 4) == "\r\033[K");  // the line is erased at the end
    std::fclose(f);
  }
}

TEST_CASE("ProgressBar: a file is not a terminal") {
  std::FILE* f = std::tmpfile();
  REQUIRE(f);
  CHECK_FALSE(ProgressBar::is_terminal(f));
  std::fclose(f);
}
