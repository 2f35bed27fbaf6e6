// build/ddtscale_lawson_2d IMAGE [--runs N] [--cost NAME]: the 2D optimizer
// (image/optimizer.cpp: half-edges, fast evaluators, triangle-id regions)
// against the dimension-generic core::optimize_lawson<2> (core/lawson.cpp:
// the Radon-partition flips, the reference costs, vertex-id bands) on the
// same image's pixel-grid mesh, with the same cost and acceptance rule.
// Prints, for each driver and schedule, the median seconds, the tests, the
// flips and the final total cost (total_cost of the result, the same sum for
// both): what moving 2D onto the generic driver would cost and change
// (docs/architecture.md, "What stays 2D-only").

#include "core/lawson.hpp"
#include "image/mesh.hpp"
#include "image/optimizer.hpp"
#include "image/triangulation.hpp"
#include "io/image_io.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace ddt;

namespace {

// The live cells of a core mesh as a Mesh2 (the inverse of as_simplex_mesh:
// half-edge 3t + k is facet slot 3t + (k + 2) % 3), so that both results
// are summed by the same total_cost.
Mesh2 as_mesh2(const core::SimplexMesh<2>& s) {
  std::vector<index_t> new_id(static_cast<std::size_t>(s.slot_count()), -1);
  index_t live = 0;
  for (index_t c = 0; c < s.slot_count(); ++c)
    if (s.is_live(c)) new_id[static_cast<std::size_t>(c)] = live++;
  Mesh2 m;
  for (const auto& p : s.points) m.points.push_back({p[0], p[1]});
  m.tri.resize(3 * static_cast<std::size_t>(live));
  m.opp.assign(3 * static_cast<std::size_t>(live), no_edge);
  for (index_t c = 0; c < s.slot_count(); ++c) {
    const index_t t = new_id[static_cast<std::size_t>(c)];
    if (t < 0) continue;
    for (int k = 0; k < 3; ++k) {
      m.tri[3 * t + k] = s.vertex(c, k);
      const index_t twin = s.opp[3 * static_cast<std::size_t>(c) + (k + 2) % 3];
      if (twin == core::no_facet) continue;
      const index_t other = new_id[static_cast<std::size_t>(twin / 3)];
      m.opp[3 * t + k] = 3 * other + (twin % 3 + 1) % 3;
    }
  }
  return m;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) try {
  std::string path, cost_name = "sederberg";
  int runs = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw Error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--runs") runs = std::max(1, std::atoi(next().c_str()));
    else if (a == "--cost") cost_name = next();
    else if (a == "--help" || a == "-h") {
      std::printf("usage: ddtscale_lawson_2d IMAGE [--runs N] [--cost NAME]\n");
      return 0;
    } else if (path.empty()) path = a;
    else throw Error("unexpected argument " + a);
  }
  if (path.empty()) throw Error("an input image is required (--help)");
  const ImageFile file = read_image(path);
  const Image& img = file.image;
  const int W = img.width, H = img.height, K = std::min(img.channels, 3);
  std::vector<float> values(static_cast<std::size_t>(W) * H * K);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int k = 0; k < K; ++k) values[(static_cast<std::size_t>(y) * W + x) * K + k] = img.at(x, y, k);
  std::vector<Point2> points;
  points.reserve(static_cast<std::size_t>(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) points.push_back({x + 0.5, y + 0.5});
  const Mesh2 grid = delaunay_triangulation(points);
  const CostFunction& cost = find_cost(cost_name);
  std::printf("%s: %dx%d, %d channels, %d triangles, cost %s, %d runs each (median seconds)\n\n", path.c_str(), W, H,
              K, grid.triangle_count(), cost_name.c_str(), runs);
  std::printf("| driver | schedule | seconds | tests | flips | total cost after |\n|---|---|---|---|---|---|\n");
  for (const bool regions : {true, false}) {
    std::vector<double> fast_seconds, core_seconds;
    LawsonStats fast_stats;
    core::LawsonStats core_stats;
    double fast_cost = 0, core_cost = 0;
    for (int r = 0; r < runs; ++r) {
      Mesh2 m = grid;
      LawsonOptions o;
      o.region_triangles = regions ? image_region_triangles(W) : -1;
      auto t = std::chrono::steady_clock::now();
      fast_stats = optimize_lawson(m, values, K, cost, o);
      fast_seconds.push_back(seconds_since(t));
      fast_cost = total_cost(m, values, K, cost);

      core::SimplexMesh<2> s = as_simplex_mesh(grid);
      core::LawsonOptions co;
      // Bands of vertex ids as many as the 2D schedule's regions hold (two
      // triangles a vertex), or one region.
      co.region_vertices = regions ? std::max<long long>(1, image_region_triangles(W) / 2) : -1;
      t = std::chrono::steady_clock::now();
      core_stats = core::optimize_lawson<2>(s, values, K, cost, co);
      core_seconds.push_back(seconds_since(t));
      const Mesh2 core_result = as_mesh2(s);
      if (!check_mesh(core_result).empty()) throw Error("the core's result is not a valid mesh");
      core_cost = total_cost(core_result, values, K, cost);
    }
    const char* schedule = regions ? "regions (2 threads)" : "one region";
    std::printf("| 2D (half-edges, fast evaluator) | %s | %.3f | %lld | %lld | %.4f |\n", schedule,
                median(fast_seconds), fast_stats.tests, fast_stats.flips, fast_cost);
    std::printf("| core::optimize_lawson<2> | %s | %.3f | %lld | %lld | %.4f |\n", schedule, median(core_seconds),
                core_stats.tests, core_stats.flips.total(), core_cost);
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "ddtscale_lawson_2d: %s\n", e.what());
  return 1;
}
