#include "volume/volume_upscale.hpp"

#include "util/error.hpp"
#include "util/image.hpp"
#include "core/grid_delaunay.hpp"
#include "core/delaunay.hpp"
#include "core/scan_convert.hpp"
#include "pipeline/upscale.hpp"
#include "eval/volume_resample.hpp"
#include "image/cubic_surface.hpp"
#include "volume/dominant_motion.hpp"
#include "volume/presmooth.hpp"
#include "volume/slow_texture.hpp"
#include "volume/volume_tiles.hpp"
#include "util/timing.hpp"

#include <algorithm>
#include <cmath>
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
  o.optimize = options.method == VolumeMethod::ddt;
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

// The values and the axes of the mesh reconstruction in D dimensions.
template <int D>
struct GridProblem {
  const std::vector<float>& values;  // #samples by channels
  std::array<int, D> input{}, output{};
  std::array<bool, D> node_centred{};
  int channels = 1;
  std::array<double, D> presmooth{};  // the graduated optimization's sigmas, per axis
  bool last_axis_is_time = false;     // a series: the last axis is time
};

// The flips keep the pairing along time of a sequence's slow texture
// (VolumeUpscaleOptions::keep_slow_texture): sets lawson.kept_simplex
// over `slow`, which it fills.
void keep_slow_texture(const GridProblem<3>& grid, std::vector<char>& slow, core::LawsonOptions& lawson) {
  const int W = grid.input[0], H = grid.input[1], T = grid.input[2];
  slow = slow_texture_samples(grid.values, W, H, T, grid.channels);
  const index_t frame = static_cast<index_t>(W) * H;
  const index_t last_frame = frame * (T - 1);
  lawson.kept_simplex = [&slow, frame, last_frame](const index_t* v, int count) {
    const auto [lo, hi] = std::minmax_element(v, v + count);
    if (count == 2 && *hi - *lo == frame) return slow[*lo] != 0;  // the edge along time
    if (*lo / frame != *hi / frame) return false;
    // Inside one frame: the last frame's samples go by the gap before it.
    return std::all_of(v, v + count, [&](index_t u) { return slow[u < last_frame ? u : u - frame] != 0; });
  };
}

// "ddt" and "delaunay" on a D-dimensional grid (D = 3: volumes, D = 4:
// series; every axis > 1 sample): the grid's Delaunay mesh, the Lawson
// procedure in slabs along the last axis, the scan conversion.
template <int D>
std::vector<float> mesh_reconstruction(const GridProblem<D>& grid, const VolumeUpscaleOptions& options,
                                       const CostFunction& cost, const StageRunner& stages,
                                       VolumeUpscaleStats& local) {
  auto log = [&](const std::string& line) { stages.log(line); };
  auto sizes_text = [](const std::array<int, D>& n) {
    std::string text;
    for (int k = 0; k < D; ++k) text.append(k ? "x" : "").append(std::to_string(n[k]));
    return text;
  };
  auto t0 = Clock::now();
  core::SimplexMesh<D> mesh;
  bool sheared = false;
  if constexpr (D == 3)
    if (grid.last_axis_is_time && (options.time_shear[0] != 0 || options.time_shear[1] != 0 || options.time_zoom != 0)) {
      mesh = motion_delaunay(grid.input, options.time_shear, options.time_zoom, options.time_origin);
      sheared = true;
    }
  if (!sheared) mesh = core::grid_delaunay<D>(grid.input);  // = CGAL's Delaunay of the sample points
  local.seconds_triangulate = seconds_since(t0);
  local.tetrahedra = mesh.cell_count();
  log(std::string(D == 3 ? "tetrahedralize: " : "triangulate: ") + std::to_string(mesh.points.size()) +
      " points, " + std::to_string(mesh.cell_count()) + (D == 3 ? " tetrahedra, " : " simplices, ") + std::to_string(local.seconds_triangulate) + " s");

  t0 = Clock::now();
  if (options.method == VolumeMethod::ddt) {
    core::LawsonOptions lawson = lawson_options<core::LawsonOptions>(options);
    std::array<int, 4> size4{1, 1, 1, 1};
    for (int k = 0; k < D; ++k) size4[k] = grid.input[k];
    const int last = grid.input[D - 1];
    const int slices = options.region_slices > 0 ? options.region_slices : volume_region_slices(size4);
    long long per_slice = 1;
    for (int k = 0; k < D - 1; ++k) per_slice *= grid.input[k];
    lawson.region_vertices = slices >= last ? -1 : static_cast<long long>(slices) * per_slice;
    if (stages.logging())
      lawson.on_iteration = [&](int iteration, const core::FlipCounts& flips, double total) {
        char line[300];
        std::snprintf(line, sizeof line, "optimize: iteration %d, flips %s, cost %.9g", iteration,
                      flips.summary().c_str(), total);
        log(line);
      };
    std::vector<char> slow;
    if constexpr (D == 3)
      if (grid.last_axis_is_time && options.keep_slow_texture) {
        keep_slow_texture(grid, slow, lawson);
        log("slow texture: " + std::to_string(std::count(slow.begin(), slow.end(), char(1))) + " of " +
            std::to_string(slow.size()) + " samples stay paired along time");
      }
    if (std::any_of(grid.presmooth.begin(), grid.presmooth.end(), [](double sigma) { return sigma > 0; })) {
      const std::vector<float> smooth =
          smoothed_grid(grid.values, std::vector<int>(grid.input.begin(), grid.input.end()), grid.channels,
                        std::vector<double>(grid.presmooth.begin(), grid.presmooth.end()));
      const core::LawsonStats pre = core::optimize_lawson<D>(mesh, smooth, grid.channels, cost, lawson);
      local.presmooth_flips = pre.flips.total();
      local.presmooth_iterations = pre.iterations;
      log("optimize on the smoothed samples: " + std::to_string(pre.iterations) + " iterations, flips " +
          pre.flips.summary());
    }
    const core::LawsonStats ls = core::optimize_lawson<D>(mesh, grid.values, grid.channels, cost, lawson);
    local.take(ls);
    local.tetrahedra = mesh.cell_count();
    local.seconds_optimize = seconds_since(t0);
    char line[400];
    std::snprintf(line, sizeof line,
                  "optimize: cost %s, %d iterations, %d slabs, flips %s (total %lld), %lld tests (%lld deferred), cost "
                  "%.9g -> %.9g, %lld %s, %.3f s",
                  cost.name, local.iterations, ls.regions, local.flips.summary().c_str(), local.flips.total(), ls.tests,
                  ls.deferred, local.cost_before, local.cost_after, local.tetrahedra,
                  D == 3 ? "tetrahedra" : "simplices", local.seconds_optimize);
    log(line);
  }

  t0 = Clock::now();
  core::ScanStats rs;
  const bool cubic = options.render == Render::cubic;
  const std::vector<float> gradients =
      cubic ? grid_slopes(grid.values.data(), std::vector<int>(grid.input.begin(), grid.input.end()), grid.channels,
                          options.slopes)
            : std::vector<float>{};
  core::ScanGrid<D> scan = core::ScanGrid<D>::whole(grid.input, grid.output, grid.node_centred);
  if (options.last_axis.scale > 0) {
    const double s = options.last_axis.scale;
    scan.scale[D - 1] = s;
    scan.phase[D - 1] = (grid.node_centred[D - 1] ? s / 2 : 0.5) + options.last_axis.first;
  }
  std::vector<float> out = core::scan_convert<D>(mesh, grid.values, grid.channels, scan, &rs, cubic ? &gradients : nullptr);
  local.seconds_render = seconds_since(t0);
  log("render: " + sizes_text(grid.output) + ", " + to_string(options.render) + ", " + std::to_string(rs.owned) +
      (D == 3 ? " voxels in tetrahedra + " : " samples in simplices + ") + std::to_string(rs.rim) + " on the hull rim, " +
      std::to_string(local.seconds_render) + " s");
  return out;
}

// `small` (of size out with 1 on the axes in `repeat`) repeated along
// those axes to the size `out`. A size-1 axis does not change the layout,
// so each sample of `small` is copied to every position of its line.
Volume repeat_along(const Volume& small, const std::array<int, 4>& out, const std::array<bool, 4>& repeat) {
  Volume result(out, small.channels, 0.0f);
  const std::size_t C = small.channels;
  for (int t = 0; t < out[3]; ++t)
    for (int z = 0; z < out[2]; ++z)
      for (int y = 0; y < out[1]; ++y)
        for (int x = 0; x < out[0]; ++x) {
          const std::size_t from = small.index(repeat[0] ? 0 : x, repeat[1] ? 0 : y, repeat[2] ? 0 : z,
                                               repeat[3] ? 0 : t);
          const std::size_t to = result.index(x, y, z, t);
          std::copy_n(small.voxels.begin() + from * C, C, result.voxels.begin() + to * C);
        }
  return result;
}

bool is_3d(const Volume& src, const std::array<int, 4>& size) { return src.nt == 1 && size[3] == 1; }

// The classic methods, channel by channel.
Volume classic_upscale(const Volume& src, const std::array<int, 4>& size, const VolumeUpscaleOptions& options) {
  const bool node_axes = options.node_centred[0] || options.node_centred[1] || options.node_centred[2];
  AxisWindow window;
  window.axis = is_3d(src, size) ? 2 : 3;
  window.scale = options.last_axis.scale;
  window.first = options.last_axis.first;
  Volume out(size, src.channels, 0.0f);
  for (int c = 0; c < src.channels; ++c) {
    const Volume channel = src.channels == 1 ? src : volume_channel(src, c);
    // 3D without node-centred axes: the 3D resamplers as they always were.
    set_volume_channel(out, c,
                       is_3d(src, size) && !node_axes && window.scale == 0
                           ? classic_resize_volume(channel, size[0], size[1], size[2], to_string(options.method))
                           : classic_resize_axes(channel, size, to_string(options.method), options.node_centred,
                                                 window));
  }
  return out;
}

}  // namespace

// The orientation argument for the zoom: docs/sequences.md, "Zoom".
core::SimplexMesh<3> motion_delaunay(const std::array<int, 3>& size, const std::array<double, 2>& given_shear,
                                     double zoom, int time_origin) {
  const std::array<double, 2> shear{to_eighth_pixel(given_shear[0]), to_eighth_pixel(given_shear[1])};
  std::vector<core::Vec<3>> points;
  points.reserve(static_cast<std::size_t>(size[0]) * size[1] * size[2]);
  for (int t = 0; t < size[2]; ++t)
    for (int y = 0; y < size[1]; ++y)
      for (int x = 0; x < size[0]; ++x) points.push_back({x + 0.5, y + 0.5, t + 0.5});
  std::vector<core::Vec<3>> sheared = points;
  if (zoom == 0) {
    for (core::Vec<3>& p : sheared) p[0] -= shear[0] * p[2], p[1] -= shear[1] * p[2];
  } else {
    // Frame t's samples carried back form the lattice u = x s + o; with s
    // and o taken to 2^-20 every u is exact in doubles (no rounding noise
    // for CGAL's predicates to decide exactly, and tiles compute the same
    // positions as the whole).
    auto dyadic = [](double v) { return std::ldexp(std::round(std::ldexp(v, 20)), -20); };
    const std::size_t frame = static_cast<std::size_t>(size[0]) * size[1];
    const double c[2] = {size[0] / 2.0, size[1] / 2.0};
    for (int t = 0; t < size[2]; ++t) {
      const double frames = double(time_origin) + t;
      const double scale = dyadic(std::exp(-frames * std::log1p(zoom)));        // 1 / g^t
      const double carried = std::expm1(frames * std::log1p(zoom)) / zoom;  // (g^t - 1) / (g - 1)
      const double o[2] = {dyadic(c[0] - (c[0] + shear[0] * carried) * scale),
                           dyadic(c[1] - (c[1] + shear[1] * carried) * scale)};
      // A zoom held so long that a frame shrinks to nothing (or overflows)
      // has no lattice to carry: the lattice's mesh.
      if (!(scale >= 1 / max_sequence_zoom && scale <= max_sequence_zoom) || !std::isfinite(o[0]) ||
          !std::isfinite(o[1]))
        return core::grid_delaunay<3>(size);
      for (std::size_t i = frame * t; i < frame * (t + 1); ++i)
        for (int k = 0; k < 2; ++k) sheared[i][k] = points[i][k] * scale + o[k];
    }
  }
  // Then one in-plane shear (x + y / 256), the same on every frame: it
  // keeps the orientation argument (the same linear map on each frame, up
  // to a positive scale; for the translation, an affine map of determinant
  // 1) and turns the lattice's cocircular squares into parallelograms,
  // which CGAL's filters decide without exact arithmetic. Exact in doubles.
  for (core::Vec<3>& p : sheared) p[0] += std::ldexp(p[1], -8);
  core::SimplexMesh<3> mesh;
  if (!core::layered_delaunay(sheared, static_cast<index_t>(size[0]) * size[1], mesh)) {
    if (zoom != 0) return core::grid_delaunay<3>(size);  // one triangulation of all frames could fold
    mesh = core::delaunay<3>(sheared);
  }
  mesh.points = std::move(points);
  return mesh;
}

std::array<bool, 4> mesh_problem_axes(const std::array<int, 4>& in) {
  std::array<bool, 4> keep{};
  int kept = 0;
  for (int a = 0; a < 4; ++a) kept += keep[a] = in[a] > 1;
  for (int a = 0; a < 4 && kept < 3; ++a)
    if (!keep[a]) keep[a] = true, ++kept;
  return keep;
}

int enlarged_size(int n, double s, bool node_centred) {
  const double m = node_centred && n > 1 ? std::round((n - 1) * s) + 1 : std::round(n * s);
  return static_cast<int>(std::clamp(m, 1.0, 2147483647.0));
}

int scale_time_axis(int steps, double time_scale, VolumeUpscaleOptions& options) {
  if (!options.node_centred[3] || steps < 2 || time_scale == std::floor(time_scale))
    return enlarged_size(steps, time_scale, options.node_centred[3]);
  options.last_axis.scale = time_scale;
  options.last_axis.first = 0;
  return tiled_output_slices(steps, time_scale, true);
}

int volume_region_slices(const std::array<int, 4>& size) {
  const int D = size[3] > 1 ? 4 : 3;
  long long cells_per_slice = simplices_per_grid_cell(D);
  for (int k = 0; k < D - 1; ++k) cells_per_slice *= std::max(1, size[k] - 1);
  const int last = size[D - 1];
  if (cells_per_slice * std::max(1, last - 1) <= 2 * core::default_region_cells) return last;
  // A flip reaches one slice on either side, so thinner slabs defer too much.
  return static_cast<int>(std::max(16LL, core::default_region_cells / cells_per_slice));
}

int volume_region_slices(int nx, int ny, int nz) { return volume_region_slices({nx, ny, nz, 1}); }

std::array<double, 4> presmooth_in_space(bool series, double sigma) {
  if (sigma < 0) sigma = series ? 1.0 : 0.0;
  return {sigma, sigma, sigma, 0.0};
}

VolumeMethod volume_method_by_name(const std::string& name) {
  static const std::pair<const char*, VolumeMethod> names[] = {
      {"ddt", VolumeMethod::ddt},
      {"delaunay", VolumeMethod::delaunay},
      {"trilinear", VolumeMethod::trilinear},
      {"tricubic", VolumeMethod::tricubic},
      {"quadrilinear", VolumeMethod::quadrilinear},
      {"tricubic-linear", VolumeMethod::tricubic_linear}};
  for (const auto& [text, method] : names)
    if (name == text) return method;
  throw Error("unknown method '" + name + "' (valid: ddt, delaunay, trilinear, tricubic, quadrilinear, tricubic-linear)");
}

const char* to_string(VolumeMethod method) {
  switch (method) {
    case VolumeMethod::ddt: return "ddt";
    case VolumeMethod::delaunay: return "delaunay";
    case VolumeMethod::trilinear: return "trilinear";
    case VolumeMethod::tricubic: return "tricubic";
    case VolumeMethod::quadrilinear: return "quadrilinear";
    case VolumeMethod::tricubic_linear: return "tricubic-linear";
  }
  return "?";
}

const std::vector<std::string>& volume_upscale_methods() {
  static const std::vector<std::string> names = {"ddt", "delaunay", "trilinear", "tricubic"};
  return names;
}

const std::vector<std::string>& volume_series_upscale_methods() {
  static const std::vector<std::string> names = {"ddt",          "delaunay",  "quadrilinear", "tricubic-linear",
                                                 "trilinear",    "tricubic"};
  return names;
}

Volume upscale_volume(const Volume& src, int nx, int ny, int nz, const VolumeUpscaleOptions& options,
                      VolumeUpscaleStats* stats) {
  return upscale_volume(src, {nx, ny, nz, src.nt}, options, stats);
}

Volume upscale_volume(const Volume& src, const std::array<int, 4>& size, const VolumeUpscaleOptions& options,
                      VolumeUpscaleStats* stats) {
  if (src.empty() || src.nx <= 0 || src.ny <= 0 || src.nz <= 0 || src.nt <= 0) throw Error("the input volume is empty");
  if (src.channels < 1 || src.voxels.size() != src.voxel_count() * src.channels)
    throw Error("the input volume's samples do not match its size and channels");
  if (options.method == VolumeMethod::ddt && src.channels > max_cost_channels)
    throw Error("a volume of " + std::to_string(src.channels) + " channels: the flip costs take at most " +
                std::to_string(max_cost_channels));
  if (size[0] < 1 || size[1] < 1 || size[2] < 1 || size[3] < 1)
    throw Error("the output size must be at least 1 on every axis");
  const bool series = !is_3d(src, size);
  const auto& methods = series ? volume_series_upscale_methods() : volume_upscale_methods();
  if (std::find(methods.begin(), methods.end(), to_string(options.method)) == methods.end())
    throw Error(std::string("method '") + to_string(options.method) + "' is not for " +
                (series ? "series" : "3D volumes") + " (valid: " +
                (series ? "ddt, delaunay, quadrilinear, tricubic-linear" : "ddt, delaunay, trilinear, tricubic") + ")");
  const CostFunction& cost = find_cost(options.cost);
  VolumeUpscaleStats local;
  const StageRunner stages(options.log);
  auto log = [&](const std::string& line) { stages.log(line); };
  if (!is_mesh_method(options.method)) {
    auto t0 = Clock::now();
    Volume out = classic_upscale(src, size, options);
    local.seconds_render = seconds_since(t0);
    if (stats) *stats = local;
    return out;
  }
  const std::array<int, 4> in = src.size();
  if (series) {
    // A dropped axis has one sample, so dropping it keeps the layout; the
    // result is repeated along it.
    const std::array<bool, 4> keep = mesh_problem_axes(in);
    if (std::count(keep.begin(), keep.end(), true) == 4) {
      Volume out;
      out.nx = size[0], out.ny = size[1], out.nz = size[2], out.nt = size[3], out.channels = src.channels;
      const GridProblem<4> grid{src.voxels, in, size, options.node_centred, src.channels, options.presmooth, true};
      out.voxels = mesh_reconstruction<4>(grid, options, cost, stages, local);
      if (stats) *stats = local;
      return out;
    }
    std::array<int, 3> in3{1, 1, 1}, out3{1, 1, 1};
    std::array<bool, 4> node3{};
    std::array<double, 4> presmooth3{};
    std::array<int, 4> small_size{};
    std::array<bool, 4> repeat{};
    for (int a = 0, j = 0; a < 4; ++a) {
      small_size[a] = keep[a] ? size[a] : 1;
      repeat[a] = !keep[a];
      if (!keep[a]) continue;
      in3[j] = in[a], out3[j] = size[a], node3[j] = options.node_centred[a], presmooth3[j] = options.presmooth[a];
      ++j;
    }
    log("axes of one sample: enlarged as " + std::to_string(in3[0]) + "x" + std::to_string(in3[1]) + "x" +
        std::to_string(in3[2]) + " and repeated along the others");
    Volume reduced;
    reduced.nx = in3[0], reduced.ny = in3[1], reduced.nz = in3[2], reduced.channels = src.channels;
    reduced.voxels = src.voxels;
    VolumeUpscaleOptions o = options;
    o.node_centred = node3;
    o.presmooth = presmooth3;
    o.last_axis_is_time = keep[3];
    const Volume small = upscale_volume(reduced, out3[0], out3[1], out3[2], o, &local);
    Volume shaped = small;
    shaped.nx = small_size[0], shaped.ny = small_size[1], shaped.nz = small_size[2], shaped.nt = small_size[3];
    Volume out = repeat_along(shaped, size, repeat);
    if (stats) *stats = local;
    return out;
  }
  if (src.nx == 1 || src.ny == 1 || src.nz == 1) {
    if (options.last_axis.scale > 0) throw Error("an output window along the last axis needs a 3D mesh problem");
    log("a single slice: enlarged by the 2D method and repeated along the thin axis");
    const int out3[3] = {size[0], size[1], size[2]};
    Volume out = upscale_planar(src, out3, options, local);
    if (stats) *stats = local;
    return out;
  }
  Volume out;
  out.nx = size[0], out.ny = size[1], out.nz = size[2], out.channels = src.channels;
  const GridProblem<3> grid{src.voxels, {in[0], in[1], in[2]}, {size[0], size[1], size[2]},
                            {options.node_centred[0], options.node_centred[1], options.node_centred[2]}, src.channels,
                            {options.presmooth[0], options.presmooth[1], options.presmooth[2]},
                            options.last_axis_is_time};
  out.voxels = mesh_reconstruction<3>(grid, options, cost, stages, local);
  if (stats) *stats = local;
  return out;
}

}  // namespace ddt
