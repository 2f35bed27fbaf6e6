#include "volume/volume_upscale.hpp"

#include "util/error.hpp"
#include "util/image.hpp"
#include "core/grid_delaunay.hpp"
#include "core/scan_convert.hpp"
#include "pipeline/upscale.hpp"
#include "eval/volume_resample.hpp"
#include "image/cubic_surface.hpp"
#include "volume/presmooth.hpp"

#include <algorithm>
#include <cstdio>

namespace ddt {
namespace {

// A single slice (or line, or voxel): the 2D method on the two widest axes,
// repeated along the others.
Volume upscale_planar(const Volume& src, const int out[3], const VolumeUpscaleOptions& options,
                      VolumeUpscaleStats& stats) {
  const int in[3] = {src.nx, src.ny, src.nz};
  int axes[3] = {0, 1, 2};
  std::stable_sort(axes, axes + 3, [&](int a, int b) { return (in[a] > 1) > (in[b] > 1); });
  const int u = axes[0], v = axes[1];
  const int C = src.channels;
  Image img(in[u], in[v], C);
  for (int j = 0; j < in[v]; ++j)
    for (int i = 0; i < in[u]; ++i) {
      int c[3] = {0, 0, 0};
      c[u] = i, c[v] = j;
      for (int ch = 0; ch < C; ++ch) img.at(i, j, ch) = src.at(c[0], c[1], c[2], ch);
    }
  UpscaleOptions o;
  o.cost = options.cost;
  o.optimize = options.method == "ddt";
  o.relative_tolerance = options.relative_tolerance;
  o.max_iterations = options.max_iterations;
  o.render = options.render;
  o.slopes = options.slopes;
  o.log = options.log;
  UpscaleStats s2;
  const Image big = upscale(img, out[u], out[v], o, &s2);
  stats.planar = true;
  static_cast<StageSeconds&>(stats) = s2;
  stats.iterations = s2.iterations;
  stats.planar_flips = s2.flips;
  stats.cost_before = s2.cost_before;
  stats.cost_after = s2.cost_after;
  Volume result(out[0], out[1], out[2], C, 0.0f);
  for (int Z = 0; Z < out[2]; ++Z)
    for (int Y = 0; Y < out[1]; ++Y)
      for (int X = 0; X < out[0]; ++X) {
        const int c[3] = {X, Y, Z};
        for (int ch = 0; ch < C; ++ch) result.at(X, Y, Z, ch) = big.at(c[u], c[v], ch);
      }
  return result;
}

}  // namespace

int volume_region_slices(int nx, int ny, int nz) {
  const long long cells_per_slice = 6LL * std::max(1, nx - 1) * std::max(1, ny - 1);  // 6 per cube
  if (cells_per_slice * std::max(1, nz - 1) <= 2 * core::default_region_cells) return nz;
  return static_cast<int>(std::max(16LL, core::default_region_cells / cells_per_slice));
}

const std::vector<std::string>& volume_upscale_methods() {
  static const std::vector<std::string> names = {"ddt", "delaunay", "trilinear", "tricubic"};
  return names;
}

Volume upscale_volume(const Volume& src, int nx, int ny, int nz, const VolumeUpscaleOptions& options,
                      VolumeUpscaleStats* stats) {
  if (src.empty() || src.nx <= 0 || src.ny <= 0 || src.nz <= 0) throw Error("the input volume is empty");
  if (src.channels < 1 || src.voxels.size() != src.voxel_count() * src.channels)
    throw Error("the input volume's samples do not match its size and channels");
  if (options.method == "ddt" && src.channels > max_cost_channels)
    throw Error("a volume of " + std::to_string(src.channels) + " channels: the flip costs take at most " +
                std::to_string(max_cost_channels));
  if (nx < 1 || ny < 1 || nz < 1) throw Error("the output size must be at least 1x1x1");
  const auto& methods = volume_upscale_methods();
  if (std::find(methods.begin(), methods.end(), options.method) == methods.end())
    throw Error("unknown method '" + options.method + "' (valid: ddt, delaunay, trilinear, tricubic)");
  const CostFunction& cost = find_cost(options.cost);
  VolumeUpscaleStats local;
  const StageRunner stages(options.log);
  auto log = [&](const std::string& line) { stages.log(line); };
  if (options.method == "trilinear" || options.method == "tricubic") {
    auto t0 = Clock::now();
    Volume out(nx, ny, nz, src.channels, 0.0f);
    for (int c = 0; c < src.channels; ++c)
      set_volume_channel(out, c, classic_resize_volume(src.channels == 1 ? src : volume_channel(src, c), nx, ny, nz,
                                                       options.method));
    local.seconds_render = seconds_since(t0);
    if (stats) *stats = local;
    return out;
  }
  const int out_size[3] = {nx, ny, nz};
  if (src.nx == 1 || src.ny == 1 || src.nz == 1) {
    log("a single slice: enlarged by the 2D method and repeated along the thin axis");
    Volume out = upscale_planar(src, out_size, options, local);
    if (stats) *stats = local;
    return out;
  }

  auto t0 = Clock::now();
  core::SimplexMesh<3> mesh = core::grid_delaunay<3>({src.nx, src.ny, src.nz});  // = CGAL's Delaunay of the voxel centres
  local.seconds_triangulate = seconds_since(t0);
  local.tetrahedra = mesh.cell_count();
  log("tetrahedralize: " + std::to_string(mesh.points.size()) + " points, " + std::to_string(mesh.cell_count()) +
      " tetrahedra, " + std::to_string(local.seconds_triangulate) + " s");

  t0 = Clock::now();
  if (options.method == "ddt") {
    core::LawsonOptions lawson = lawson_options<core::LawsonOptions>(options);
    const int slices = options.region_slices > 0 ? options.region_slices : volume_region_slices(src.nx, src.ny, src.nz);
    lawson.region_vertices = slices >= src.nz ? -1 : static_cast<long long>(slices) * src.nx * src.ny;
    if (stages.logging())
      lawson.on_iteration = [&](int iteration, const core::FlipCounts& flips, double total) {
        char line[300];
        std::snprintf(line, sizeof line, "optimize: iteration %d, flips %s, cost %.9g", iteration,
                      flips.summary().c_str(), total);
        log(line);
      };
    if (options.presmooth[0] > 0 || options.presmooth[1] > 0 || options.presmooth[2] > 0) {
      const std::vector<float> smooth = smoothed_grid(
          src.voxels, {src.nx, src.ny, src.nz}, src.channels,
          {options.presmooth[0], options.presmooth[1], options.presmooth[2]});
      const core::LawsonStats pre = core::optimize_lawson<3>(mesh, smooth, src.channels, cost, lawson);
      local.presmooth_flips = pre.flips.total();
      char line[300];
      std::snprintf(line, sizeof line, "optimize on the smoothed samples (sigma %g, %g, %g): %d iterations, flips %s",
                    options.presmooth[0], options.presmooth[1], options.presmooth[2], pre.iterations,
                    pre.flips.summary().c_str());
      log(line);
    }
    const core::LawsonStats ls = core::optimize_lawson<3>(mesh, src.voxels, src.channels, cost, lawson);
    local.take(ls);
    local.tetrahedra = mesh.cell_count();
    local.seconds_optimize = seconds_since(t0);
    char line[400];
    std::snprintf(line, sizeof line,
                  "optimize: cost %s, %d iterations, %d slabs, flips %s (total %lld), %lld tests (%lld deferred), cost "
                  "%.9g -> %.9g, %lld tetrahedra, %.3f s",
                  cost.name, local.iterations, ls.regions, local.flips.summary().c_str(), local.flips.total(), ls.tests,
                  ls.deferred, local.cost_before, local.cost_after, local.tetrahedra, local.seconds_optimize);
    log(line);
  }

  t0 = Clock::now();
  core::ScanStats rs;
  Volume out;
  out.nx = nx, out.ny = ny, out.nz = nz, out.channels = src.channels;
  const bool cubic = options.render == Render::cubic;
  const std::vector<float> gradients =
      cubic ? grid_slopes(src.voxels.data(), {src.nx, src.ny, src.nz}, src.channels, options.slopes)
            : std::vector<float>{};
  out.voxels = core::scan_convert<3>(mesh, src.voxels, src.channels,
                                     core::ScanGrid<3>::whole({src.nx, src.ny, src.nz}, {nx, ny, nz}, options.node_centred), &rs,
                                     cubic ? &gradients : nullptr);
  local.seconds_render = seconds_since(t0);
  log("render: " + std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz) + ", " +
      to_string(options.render) + ", " +
      std::to_string(rs.owned) + " voxels in tetrahedra + " + std::to_string(rs.rim) + " on the hull rim, " +
      std::to_string(local.seconds_render) + " s");
  if (stats) *stats = local;
  return out;
}

}  // namespace ddt
