// ddtscale_bench — the performance benchmark of issue 4 (docs/performance.md).
//
//   ddtscale_bench [options]
//     --input IMAGE     the 1024x1024 RGB case (default: a mosaic of four Set5/Set14
//                       photographs when the datasets are there, else synthetic scenes)
//     --runs N          end-to-end runs of each command, medians reported (default 5)
//     --sizes LIST      growth case input sizes (default 256,512,1024,2048)
//     --large N         the large case: an N x N input at x2 (default 8192; 0 skips it)
//     --work DIR        scratch directory (default /tmp/ddtscale-bench)
//     --markdown FILE   also write the tables there
//     --only PARTS      run only these parts, comma-separated: end-to-end, growth,
//                       stages (the stages alone), large (default: all)
//   ddtscale_bench stages IN OUT SCALE [linear|cubic]
//                     (used by the above) one run in this process: read, upscale,
//                     write, printing the seconds of each stage
//
// End to end, `ddtscale` (next to this program) and `oiiotool` run as child
// processes, interleaved, so both see the same machine load; wall time and
// peak resident memory (wait4) of each run. The rasterizer, optimizer and
// triangulation are also timed alone, in this process, on 1 thread and on
// all of them.

#include "io/image_io.hpp"
#include "image/image_mesh.hpp"
#include "image/optimizer.hpp"
#include "image/rasterizer.hpp"
#include "eval/synthetic_scenes.hpp"
#include "image/triangulation.hpp"
#include "pipeline/upscale.hpp"
#include "image/cubic_surface.hpp"
#include "core/costs.hpp"

#include <CGAL/version.h>
#include <Eigen/Dense>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/oiioversion.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/version.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/utsname.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace ddt;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// CPU seconds of this process (all threads): unlike wall time, not inflated
// by other processes taking the cores on a shared machine.
double cpu_now() {
  timespec t{};
  ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string format(const char* f, double v) {
  char s[64];
  std::snprintf(s, sizeof s, f, v);
  return s;
}

std::string first_line_of(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) {
      const auto colon = line.find(':');
      std::string v = colon == std::string::npos ? line : line.substr(colon + 1);
      while (!v.empty() && v.front() == ' ') v.erase(v.begin());
      return v;
    }
  return "?";
}

struct Child {
  double seconds = 0;
  long max_rss_kb = 0;
  int status = -1;
  std::string out;  // stdout
};

// Runs argv as a child process; stdout captured, stderr discarded.
Child run(const std::vector<std::string>& argv) {
  int pipefd[2];
  if (::pipe(pipefd) != 0) throw std::runtime_error("pipe failed");
  const double t0 = now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(pipefd[1], 1);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 2);
    ::close(pipefd[0]);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  ::close(pipefd[1]);
  Child c;
  char buf[4096];
  ssize_t got;
  while ((got = ::read(pipefd[0], buf, sizeof buf)) > 0) c.out.append(buf, static_cast<std::size_t>(got));
  ::close(pipefd[0]);
  struct rusage ru {};
  int status = 0;
  ::wait4(pid, &status, 0, &ru);
  c.seconds = now() - t0;
  c.max_rss_kb = ru.ru_maxrss;
  c.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return c;
}

std::map<std::string, double> parse_fields(const std::string& text) {
  std::map<std::string, double> m;
  std::istringstream in(text);
  std::string item;
  while (in >> item) {
    const auto eq = item.find('=');
    if (eq != std::string::npos) m[item.substr(0, eq)] = std::atof(item.substr(eq + 1).c_str());
  }
  return m;
}

// ---------------------------------------------------------------------------
// `stages`: one run in this process.
int stages_main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: ddtscale_bench stages IN OUT SCALE [linear|cubic]\n");
    return 2;
  }
  const std::string in = argv[2], out_path = argv[3];
  const double scale = std::atof(argv[4]);
  double t0 = now();
  const ImageFile file = read_image(in);
  const double read_s = now() - t0;
  UpscaleOptions options;
  options.alpha_channel = file.alpha_channel;
  if (argc > 5) options.render = render_by_name(argv[5]);
  UpscaleStats st;
  t0 = now();
  const Image out = upscale(file.image, static_cast<int>(std::lround(file.image.width * scale)),
                            static_cast<int>(std::lround(file.image.height * scale)), options, &st);
  const double upscale_s = now() - t0;
  t0 = now();
  write_image(out_path, out, file.format, file.alpha_channel);
  const double write_s = now() - t0;
  std::printf(
      "read=%.4f triangulate=%.4f optimize=%.4f render=%.4f other=%.4f write=%.4f total=%.4f flips=%lld tests=%lld "
      "triangles=%lld phases=%d regions=%d tiles=%d in_pixels=%lld out_pixels=%lld\n",
      read_s, st.seconds_triangulate, st.seconds_optimize, st.seconds_render,
      upscale_s - st.seconds_triangulate - st.seconds_optimize - st.seconds_render, write_s,
      read_s + upscale_s + write_s, st.flips, st.tests, st.triangles, st.iterations, st.regions, st.tiles,
      static_cast<long long>(file.image.pixel_count()), static_cast<long long>(out.pixel_count()));
  return 0;
}

// ---------------------------------------------------------------------------
// Inputs.

Image crop(const Image& src, int x0, int y0, int w, int h) {
  Image out(w, h, src.channels);
  for (int y = 0; y < h; ++y)
    std::copy(src.pixels.begin() + static_cast<std::ptrdiff_t>(src.index(x0, y0 + y)),
              src.pixels.begin() + static_cast<std::ptrdiff_t>(src.index(x0, y0 + y) + std::size_t(w) * src.channels),
              out.pixels.begin() + static_cast<std::ptrdiff_t>(out.index(0, y)));
  return out;
}

// n x n from `tile`, repeated (mirrored on odd repeats, so no seams).
Image tiled(const Image& tile, int n) {
  Image out(n, n, tile.channels);
  tbb::parallel_for(0, n, [&](int y) {
    const int ty = (y / tile.height) % 2 ? tile.height - 1 - y % tile.height : y % tile.height;
    for (int x = 0; x < n; ++x) {
      const int tx = (x / tile.width) % 2 ? tile.width - 1 - x % tile.width : x % tile.width;
      for (int c = 0; c < tile.channels; ++c) out.at(x, y, c) = tile.at(tx, ty, c);
    }
  });
  return out;
}

void write_png(const std::string& path, const Image& img) {
  OIIO::ImageSpec spec(img.width, img.height, img.channels, OIIO::TypeDesc::UINT8);
  OIIO::ImageBuf buf(spec);
  buf.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, img.pixels.data());
  if (!buf.write(path)) throw std::runtime_error("cannot write " + path);
}

Image default_input(std::string& description) {
#ifdef DDTSCALE_DATASETS_DIR
  const fs::path sets = DDTSCALE_DATASETS_DIR;
  const std::vector<fs::path> parts = {sets / "Set14/lenna.png", sets / "Set5/baby.png", sets / "Set14/pepper.png",
                                       sets / "Set14/man.png"};
  bool all = true;
  for (const auto& p : parts) all = all && fs::exists(p);
  if (all) {
    Image out(1024, 1024, 3);
    for (int k = 0; k < 4; ++k) {
      const Image im = read_image(parts[k].string()).image;
      const Image c = crop(im, (im.width - 512) / 2, (im.height - 512) / 2, 512, 512);
      for (int y = 0; y < 512; ++y)
        for (int x = 0; x < 512; ++x)
          for (int ch = 0; ch < 3; ++ch) out.at((k % 2) * 512 + x, (k / 2) * 512 + y, ch) = c.at(x, y, std::min(ch, c.channels - 1));
    }
    description = "mosaic of Set14 lenna, Set5 baby, Set14 pepper, Set14 man (512x512 each)";
    return out;
  }
#endif
  Image out(1024, 1024, 3);
  const char* names[4] = {"smooth_waves", "colour_regions", "strokes", "checker_rotated"};
  for (int k = 0; k < 4; ++k) {
    const Image s = render_scene(find_scene(names[k]), 512, 512);
    for (int y = 0; y < 512; ++y)
      for (int x = 0; x < 512; ++x)
        for (int ch = 0; ch < 3; ++ch) out.at((k % 2) * 512 + x, (k / 2) * 512 + y, ch) = s.at(x, y, std::min(ch, s.channels - 1));
  }
  description = "mosaic of synthetic scenes smooth_waves, colour_regions, strokes, checker_rotated";
  return out;
}

// ---------------------------------------------------------------------------

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::string str() const {
    std::string s = "|";
    for (const auto& h : header) s += " " + h + " |";
    s += "\n|";
    for (std::size_t i = 0; i < header.size(); ++i) s += "---|";
    s += "\n";
    for (const auto& r : rows) {
      s += "|";
      for (const auto& c : r) s += " " + c + " |";
      s += "\n";
    }
    return s;
  }
};

std::string mb(long kb) { return format("%.0f MB", kb / 1024.0); }

// Where a render's time goes, from one-thread CPU seconds at several scales
// s of an n x n input: t(s) = mesh + rows s + pixels s^2 by least squares.
// The mesh term is paid per triangle whatever the scale (walk, setup),
// the rows term per row a triangle crosses (rows grow with s), the pixels
// term per output pixel; the first two bound the throughput at small scales.
// Linear only: the cubic's cost has no such form, since its patches are set
// up only for triangles that own pixels (fewer at x1) and its large
// triangles take their power form from about x5.7 (rasterizer.cpp).
std::string render_cost_model(const std::map<double, double>& cpu_seconds, long long triangles, int n) {
  Table t{{"render (1 thread)", "per triangle", "per triangle row", "per output pixel", "x4: mesh + rows / pixels",
           "x4 bound with free pixels"},
          {}};
  std::vector<std::pair<double, double>> samples;  // (scale, seconds)
  for (const auto& [scale, seconds] : cpu_seconds) samples.emplace_back(scale, seconds);
  if (samples.size() < 3) return "";
  Eigen::MatrixXd A(samples.size(), 3);
  Eigen::VectorXd b(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double s = samples[i].first;
    A.row(static_cast<Eigen::Index>(i)) << 1.0, s, s * s;
    b(static_cast<Eigen::Index>(i)) = samples[i].second;
  }
  const Eigen::Vector3d x = A.colPivHouseholderQr().solve(b);
  const double pixels_at_1 = double(n) * n;
  const double fixed_x4 = x(0) + 4 * x(1), pixels_x4 = 16 * x(2);
  t.rows.push_back({"linear, walked", format("%.0f ns", x(0) / triangles * 1e9),
                    format("%.1f ns x s", x(1) / triangles * 1e9), format("%.1f ns", x(2) / pixels_at_1 * 1e9),
                    format("%.3f s", fixed_x4) + format(" / %.3f s", pixels_x4),
                    format("%.0f Mpix/s", 16 * pixels_at_1 / fixed_x4 / 1e6)});
  return "Render cost model: one-thread CPU seconds at x1, x2, x4, x10 fitted as mesh + rows s + pixels s^2 "
         "(least squares; " + std::to_string(triangles) + " triangles; the walked linear render only: drawn by "
         "shape it has no rows, and the cubic's cost changes form between scales). \"x4 bound\" is the "
         "throughput at x4 if writing pixels cost nothing.\n\n" +
         t.str() + "\n";
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc >= 2 && std::strcmp(argv[1], "stages") == 0) return stages_main(argc, argv);
    std::string input, markdown, work = "/tmp/ddtscale-bench";
    int runs = 5, large = 8192;
    std::string only;  // empty: every part
    auto wanted = [&](const std::string& part) {
      return only.empty() || ("," + only + ",").find("," + part + ",") != std::string::npos;
    };
    std::vector<int> sizes = {256, 512, 1024, 2048};
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto next = [&]() -> std::string {
        if (i + 1 >= argc) throw std::runtime_error("missing value after " + a);
        return argv[++i];
      };
      if (a == "--input") input = next();
      else if (a == "--runs") runs = std::max(1, std::atoi(next().c_str()));
      else if (a == "--large") large = std::atoi(next().c_str());
      else if (a == "--work") work = next();
      else if (a == "--markdown") markdown = next();
      else if (a == "--only") only = next();
      else if (a == "--sizes") {
        sizes.clear();
        std::stringstream ss(next());
        std::string item;
        while (std::getline(ss, item, ',')) sizes.push_back(std::atoi(item.c_str()));
      } else if (a == "--help" || a == "-h") {
        std::printf("see the comment at the top of bench/ddtscale_bench.cpp\n");
        return 0;
      } else {
        throw std::runtime_error("unknown option " + a);
      }
    }
    const fs::path self = fs::canonical("/proc/self/exe");
    const std::string ddtscale = (self.parent_path() / "ddtscale").string();
    if (wanted("end-to-end") && !fs::exists(ddtscale)) throw std::runtime_error("no ddtscale beside this program: " + ddtscale);
    fs::create_directories(work);
    const fs::path W = work;
    std::string report;
    auto emit = [&](const std::string& s) {
      std::printf("%s", s.c_str());
      std::fflush(stdout);
      report += s;
    };

    // Machine.
    struct utsname un {};
    ::uname(&un);
    const unsigned cores = std::thread::hardware_concurrency();
    std::string load_before;
    std::getline(std::ifstream("/proc/loadavg"), load_before);
    const Child oiio_version = run({"oiiotool", "--version"});
    emit("## Machine\n\n");
    emit("- CPU: " + first_line_of("/proc/cpuinfo", "model name") + ", " + std::to_string(cores) + " cores\n");
    emit("- memory: " + first_line_of("/proc/meminfo", "MemTotal") + "\n");
    emit(std::string("- system: ") + un.sysname + " " + un.release + "\n");
    emit(std::string("- compiler: GCC ") + __VERSION__ + ", release build\n");
    emit(std::string("- libraries: OpenImageIO ") + OIIO_VERSION_STRING + ", CGAL " + CGAL_VERSION_STR + ", oneTBB " +
         std::to_string(TBB_VERSION_MAJOR) + "." + std::to_string(TBB_VERSION_MINOR) + "; oiiotool " +
         oiio_version.out.substr(0, oiio_version.out.find('\n')) + "\n");
    emit("- load average at start (other work on the machine): " + load_before + "\n\n");

    // Inputs.
    std::string description = "the file given";
    Image base;
    if (!input.empty()) base = read_image(input).image;
    else base = default_input(description);
    if (base.channels != 3 || base.width < 1024 || base.height < 1024) {
      if (base.width < 1024 || base.height < 1024) base = tiled(base, 1024);
    }
    base = crop(base, 0, 0, 1024, 1024);
    const std::string in1024 = (W / "in1024.png").string();
    write_png(in1024, base);
    emit("Input: 1024x1024 RGB 8-bit PNG, " + description + ".\n\n");

    // End to end, x4 to EXR, against oiiotool.
    if (wanted("end-to-end")) {
      std::vector<double> t_oiio, t_cubic, t_linear, t_point;
      std::vector<double> r_oiio, r_cubic, r_linear, r_point;
      const std::string out_oiio = (W / "out_oiio.exr").string(), out_ddt = (W / "out_ddt.exr").string();
      for (int r = 0; r < runs; ++r) {
        Child a = run({"oiiotool", in1024, "--resize:filter=catmull-rom", "400%", "-o", out_oiio});
        Child b = run({ddtscale, in1024, out_ddt, "--scale", "4", "--quiet"});
        Child c = run({ddtscale, in1024, out_ddt, "--scale", "4", "--quiet", "--render", "linear"});
        // The plain interpolation, the default before the consistent reconstruction.
        Child d = run({ddtscale, in1024, out_ddt, "--scale", "4", "--quiet", "--model", "point"});
        if (a.status || b.status || c.status || d.status) throw std::runtime_error("an end-to-end run failed");
        t_oiio.push_back(a.seconds), t_cubic.push_back(b.seconds), t_linear.push_back(c.seconds);
        t_point.push_back(d.seconds);
        r_oiio.push_back(a.max_rss_kb), r_cubic.push_back(b.max_rss_kb), r_linear.push_back(c.max_rss_kb);
        r_point.push_back(d.max_rss_kb);
        std::fprintf(stderr,
                     "end to end run %d/%d: oiiotool %.2f s, ddtscale %.2f s, ddtscale linear %.2f s, "
                     "ddtscale --model point %.2f s\n",
                     r + 1, runs, a.seconds, b.seconds, c.seconds, d.seconds);
      }
      Table t{{"command (1024x1024 RGB PNG -> 4096x4096 EXR)", "median wall", "min .. max", "ratio to oiiotool",
               "peak RSS (median)"},
              {}};
      auto row = [&](const std::string& name, const std::vector<double>& s, const std::vector<double>& m) {
        t.rows.push_back({name, format("%.2f s", median(s)),
                          format("%.2f", *std::min_element(s.begin(), s.end())) + " .. " +
                              format("%.2f s", *std::max_element(s.begin(), s.end())),
                          format("%.2f", median(s) / median(t_oiio)), mb(static_cast<long>(median(m)))});
      };
      row("`oiiotool in.png --resize:filter=catmull-rom 400% -o out.exr`", t_oiio, r_oiio);
      row("`ddtscale in.png out.exr --scale 4` (cubic render, box model: default)", t_cubic, r_cubic);
      row("`ddtscale in.png out.exr --scale 4 --render linear`", t_linear, r_linear);
      row("`ddtscale in.png out.exr --scale 4 --model point` (no consistency)", t_point, r_point);
      t.rows.push_back({"default / `--model point`", format("%.2f", median(t_cubic) / median(t_point)), "", "",
                        format("%.2f", median(r_cubic) / median(r_point))});
      emit("## End to end, x4 to EXR (" + std::to_string(runs) + " runs each, interleaved)\n\n" + t.str() + "\n");
    }

    // Stages and growth (child processes: own peak memory).
    if (wanted("growth")) {
      Table t{{"input", "output", "read", "triangulate", "optimize", "render", "write", "total", "Mpix in/s",
               "peak RSS", "RSS / input px"},
              {}};
      for (int n : sizes) {
        const std::string in = (W / ("grow" + std::to_string(n) + ".png")).string();
        if (n == 1024) fs::copy_file(in1024, in, fs::copy_options::overwrite_existing);
        else write_png(in, n <= 1024 ? crop(base, (1024 - n) / 2, (1024 - n) / 2, n, n) : tiled(base, n));
        const Child c = run({self.string(), "stages", in, (W / "grow_out.exr").string(), "4"});
        if (c.status) throw std::runtime_error("stages run failed for " + in);
        auto f = parse_fields(c.out);
        const double px = double(n) * n;
        t.rows.push_back({std::to_string(n) + "^2", std::to_string(4 * n) + "^2", format("%.3f", f["read"]),
                          format("%.3f", f["triangulate"]), format("%.3f", f["optimize"]), format("%.3f", f["render"] + f["other"]),
                          format("%.3f", f["write"]), format("%.3f s", f["total"]), format("%.2f", px / f["total"] / 1e6),
                          mb(c.max_rss_kb), format("%.0f B", c.max_rss_kb * 1024.0 / px)});
        std::fprintf(stderr, "growth %d: %s", n, c.out.c_str());
        fs::remove(in);
      }
      emit("## Stages and growth, x4 (cubic render; seconds, one run each)\n\n" + t.str() + "\n");
    }

    // The parts alone, in this process, on 1 thread and on all.
    if (wanted("stages")) {
      const std::vector<Point2> points = pixel_centres(1024, 1024);
      Table tri{{"stage alone (1024x1024)", "threads", "seconds (best of 3)", "throughput"}, {}};
      Mesh2 initial;
      for (int threads : {1, static_cast<int>(cores)}) {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
        double best = 1e9;
        for (int r = 0; r < 3; ++r) {
          const double t0 = now();
          initial = delaunay_triangulation(points);
          best = std::min(best, now() - t0);
        }
        tri.rows.push_back({"triangulate (CGAL, blocks of the grid)", std::to_string(threads), format("%.3f", best),
                            format("%.2f Mpoints/s", points.size() / best / 1e6)});
      }
      Mesh2 optimized;
      for (int threads : {1, static_cast<int>(cores)}) {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
        double best = 1e9;
        LawsonStats st;
        for (int r = 0; r < 3; ++r) {
          Mesh2 m = initial;
          LawsonOptions o;
          o.region_triangles = image_region_triangles(1024);
          const double t0 = now();
          st = optimize_lawson(m, base.pixels, 3, find_cost("sederberg"), o);
          const double s = now() - t0;
          if (s < best) best = s, optimized = std::move(m);
        }
        tri.rows.push_back({"optimize (sederberg, " + std::to_string(st.regions) + " regions, " +
                                std::to_string(st.iterations) + " phases)",
                            std::to_string(threads), format("%.3f", best),
                            format("%.2f M flips/s, ", st.flips / best / 1e6) +
                                format("%.2f M triangles/s, ", initial.triangle_count() / best / 1e6) +
                                format("%.2f M tests/s", st.tests / best / 1e6) + " (" + std::to_string(st.flips) +
                                " flips, " + std::to_string(st.tests) + " tests)"});
      }
      const std::vector<float> gradients = grid_gradients(base, SlopeLimiter::mc4);
      // One-thread CPU seconds of the walked linear render by scale, for the
      // cost model below.
      std::map<double, double> walked_linear_cpu;
      for (double scale : {1.0, 2.0, 4.0, 10.0})
        for (int mode = 0; mode < 4; ++mode) {
          // linear, cubic (each drawn by shape where that pays), and both walked
          const bool cubic = mode % 2 == 1, walked = mode >= 2;
          RenderGrid g;
          g.width = g.height = static_cast<int>(1024 * scale);
          g.scale_x = g.scale_y = scale;
          g.by_shapes = !walked;
          Image out(g.width, g.height, 3);  // allocated and touched once, outside the timing
          for (int threads : {1, static_cast<int>(cores)}) {
            if (walked && threads > 1) continue;
            tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
            double best = 1e9, best_cpu = 1e9;
            for (int r = 0; r < 3; ++r) {
              const double t0 = now(), c0 = cpu_now();
              render_mesh_into(out, 0, optimized, base.pixels, 3, g, nullptr, true, cubic ? &gradients : nullptr);
              best = std::min(best, now() - t0), best_cpu = std::min(best_cpu, cpu_now() - c0);
            }
            if (walked && !cubic) walked_linear_cpu[scale] = best_cpu;
            const double mpix = double(g.width) * g.height / 1e6;
            tri.rows.push_back({std::string("render ") + (cubic ? "cubic" : "linear") + " x" + format("%g", scale) +
                                    (walked ? " walked (by_shapes off)" : "") + " (RGB float, into an allocated image)",
                                std::to_string(threads), format("%.3f", best),
                                format("%.0f Mpix/s", mpix / best) + format(" = %.0f Mpix/s per core", mpix / best / threads) +
                                    format("; CPU %.3f s", best_cpu) + format(" = %.0f Mpix per CPU second", mpix / best_cpu)});
          }
        }
      emit("## Stages alone (in process, best of 3)\n\n" + tri.str() + "\n");
      emit(render_cost_model(walked_linear_cpu, optimized.triangle_count(), 1024));
    }

    // Large input.
    if (large > 0 && wanted("large")) {
      const std::string in = (W / ("large" + std::to_string(large) + ".png")).string();
      write_png(in, tiled(base, large));
      const std::string out = (W / "large_out.exr").string();
      const Child c = run({self.string(), "stages", in, out, "2"});
      auto f = parse_fields(c.out);
      std::fprintf(stderr, "large: %s", c.out.c_str());
      Table t{{"case", "status", "tiles", "read", "triangulate", "optimize", "render", "write", "total", "peak RSS"},
              {}};
      t.rows.push_back({std::to_string(large) + "^2 RGB PNG x2 -> " + std::to_string(2 * large) + "^2 EXR",
                        c.status == 0 ? "ok" : "failed (" + std::to_string(c.status) + ")",
                        format("%.0f", f["tiles"]), format("%.1f", f["read"]), format("%.1f", f["triangulate"]),
                        format("%.1f", f["optimize"]), format("%.1f", f["render"] + f["other"]), format("%.1f", f["write"]),
                        format("%.1f s", f["total"]), mb(c.max_rss_kb)});
      emit("## Large input (one run)\n\n" + t.str() + "\n");
      fs::remove(in);
      fs::remove(out);
    }
    std::string load_after;
    std::getline(std::ifstream("/proc/loadavg"), load_after);
    emit("Load average at the end: " + load_after + "\n");
    if (!markdown.empty()) std::ofstream(markdown) << report;
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ddtscale_bench: %s\n", e.what());
    return 1;
  }
}
