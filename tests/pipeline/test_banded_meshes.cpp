// BandedMeshes (pipeline/banded_meshes.hpp): the streamed reconstruction's
// meshes made a band of rows at a time draw the one mesh's pixels.

#include "consistency/consistent_reconstruction.hpp"
#include "image/cubic_surface.hpp"
#include "image/rasterizer.hpp"
#include "image/triangulation.hpp"
#include "pipeline/banded_meshes.hpp"
#include "util/error.hpp"

#include <doctest/doctest.h>

#include <chrono>
#include <memory>
#include <random>
#include <thread>

using namespace ddt;

namespace {

// The Delaunay mesh of input rows [top, bottom) of a grid `width` pixels
// wide, its vertices at the whole image's pixel centres.
Mesh2 rows_mesh(int width, int top, int bottom) {
  std::vector<Point2> points;
  for (int y = top; y < bottom; ++y)
    for (int x = 0; x < width; ++x) points.push_back({x + 0.5, y + 0.5});
  return delaunay_triangulation(points);
}

Image random_image(int width, int height, int channels, unsigned seed) {
  Image src(width, height, channels);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> value(0.0f, 1.0f);
  for (float& v : src.pixels) v = value(rng);
  return src;
}

RenderGrid enlarged_grid(int width, int height, int scale) {
  RenderGrid grid;
  grid.width = scale * width;
  grid.height = scale * height;
  grid.scale_x = grid.scale_y = scale;
  return grid;
}

}  // namespace

TEST_CASE("BandedMeshes: surfaces and added renders are the one mesh's, drawn a band at a time") {
  const int W = 23, H = 90, C = 2, scale = 3;
  const Image src = random_image(W, H, C, 3);
  const RenderGrid grid = enlarged_grid(W, H, scale);
  const Mesh2 whole = rows_mesh(W, 0, H);
  const RenderPlan plan(whole, grid);
  const std::vector<float> gradients = grid_gradients(src, SlopeLimiter::mc4);
  const VertexValues all_gradients{gradients.data(), 0, W * H};
  const VertexValues all_values{src.pixels.data(), 0, W * H};

  // The input held whole, or read by rows from a source and dropped as the
  // bands pass (what a wavefront reading a file does).
  const RowSource source{W, H, C, [&](int first, int end, float* rows) {
                           std::copy(src.pixels.begin() + static_cast<std::ptrdiff_t>(src.index(0, first)),
                                     src.pixels.begin() + static_cast<std::ptrdiff_t>(src.index(0, end)), rows);
                         }};
  std::unique_ptr<InputRows> held;
  bool by_rows = false;
  SUBCASE("the input held whole") { held = std::make_unique<InputRows>(src); }
  SUBCASE("the input read by rows") {
    held = std::make_unique<InputRows>(source);
    by_rows = true;
  }
  InputRows& input = *held;
  int made = 0;
  // Margin 3 is too narrow for 4-row regions: every cut band is made again, wider.
  BandedMeshes meshes(input, grid, 20, 4, 3, [&](int top, int bottom, const std::vector<float>& rows) {
    CHECK(rows.size() == static_cast<std::size_t>(W) * C * (bottom - top));
    CHECK(rows.front() == src.at(0, top, 0));
    ++made;
    return BandMesh{rows_mesh(W, top, bottom), 0};
  });
  Image linear(grid.width, grid.height, C), cubic(grid.width, grid.height, C), added(grid.width, grid.height, C, 0.5f);
  // Cuts every 17 rows: most of them inside a band's groups of rows.
  for (int row = 0; row < grid.height;) {
    const int ready = meshes.prepare(row);
    REQUIRE(ready > row);
    const int cut = std::min(ready, row + 17);
    meshes.draw(linear, row, row, cut, nullptr, nullptr);
    meshes.draw(cubic, row, row, cut, &all_gradients, nullptr);
    meshes.add(added, row, row, cut, src.pixels, 0, W * H);
    meshes.release(row);
    input.release(meshes.first_input_row());
    row = cut;
  }
  if (by_rows) CHECK(input.peak_rows() < H);
  CHECK(meshes.bands_made() == 5);
  CHECK(meshes.most_held() == 1);  // released up to the draw: each band takes over from the one before
  CHECK(meshes.bands_redone() >= 1);
  CHECK(made == meshes.bands_made() + meshes.bands_redone());
  CHECK(meshes.margin() >= 12);  // band_margin_needed(0 phases, 4) + a triangle's row + 1

  Image want_linear(grid.width, grid.height, C), want_cubic(grid.width, grid.height, C),
      want_added(grid.width, grid.height, C, 0.5f);
  render_mesh_into(want_linear, 0, plan, src.pixels, C, 0, grid.height);
  render_mesh_into(want_cubic, 0, plan, src.pixels, C, 0, grid.height, all_gradients);
  add_mesh_render_into(want_added, 0, plan, all_values, C, 0, grid.height);
  CHECK(linear.pixels == want_linear.pixels);
  CHECK(cubic.pixels == want_cubic.pixels);
  CHECK(added.pixels == want_added.pixels);

  // Rows of a band released are refused, not left unset.
  CHECK_THROWS_AS(meshes.draw(linear, 0, 0, 10, nullptr, nullptr), Error);
  CHECK_THROWS_AS(meshes.add(added, 0, 0, 10, src.pixels, 0, W * H), Error);
}

TEST_CASE("BandedMeshes: a band's mesh that is not its rows' pixel grid is an error") {
  const int W = 10, H = 60;
  Image src(W, H, 1);
  RenderGrid grid;
  grid.width = 2 * W;
  grid.height = 2 * H;
  grid.scale_x = grid.scale_y = 2;
  InputRows input(src);
  BandedMeshes meshes(input, grid, 20, 4, 30, [&](int top, int bottom, const std::vector<float>&) {
    return BandMesh{rows_mesh(W, top, bottom - 1), 0};  // a row short
  });
  CHECK_THROWS_WITH_AS(meshes.prepare(0), doctest::Contains("not its rows' pixel grid"), Error);
}

TEST_CASE("make_consistent_streamed: the surface's seconds hold every band's making, the first included") {
  const int W = 16, H = 80, C = 1, scale = 2;
  const Image src = random_image(W, H, C, 5);
  const RenderGrid grid = enlarged_grid(W, H, scale);
  InputRows input(src);
  int made = 0;
  const auto pause = std::chrono::milliseconds(40);
  BandedMeshes meshes(input, grid, 20, 4, 30, [&](int top, int bottom, const std::vector<float>&) {
    ++made;
    std::this_thread::sleep_for(pause);  // a band's making, longer than drawing this small image
    return BandMesh{rows_mesh(W, top, bottom), 0};
  });
  ConsistencyOptions options;
  int handed = 0;
  options.output_rows = [&](Image rows, int) { handed += rows.height; };
  ConsistencyStats stats;
  make_consistent_streamed(grid.width, grid.height, meshes, nullptr, input, options, &stats);
  CHECK(handed == grid.height);
  REQUIRE(made >= 2);
  CHECK(stats.seconds_surface >= made * std::chrono::duration<double>(pause).count());
}
