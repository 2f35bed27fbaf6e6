#pragma once
// ddt::upscale_volume — enlarge a volume (C channels) by data-dependent
// tetrahedrization (the paper's 3D method), or by a classic resampler.
//
// Pipeline ("ddt"): samples at voxel centres -> Delaunay tetrahedrization
// (CGAL's, repeated per cube: core/grid_delaunay.hpp) -> generalized Lawson
// optimization of the weighted content with 2-3, 3-2, 4-4 (and hull 2-2)
// flips, on the dimension-generic core with its parallel slab schedule
// (core/lawson.hpp), driven by all channels at once (one mesh; the costs
// sum over channels, at most core::max_cost_channels) -> scan conversion of
// the field of every channel at the output resolution (core/scan_convert.hpp):
// by default a cubic Bézier tetrahedron per cell from the values and limited
// slopes at its vertices, or the paper's piecewise-linear field. The
// classic resamplers work channel by channel.
//
// Output voxel (X, Y, Z) samples the field at ((X + 0.5) / sx, ...), with
// s = n_out / n_in per axis (on node-centred axes at X / s + 0.5 with
// s = (n_out - 1) / (n_in - 1)); outside the samples' hull (the half-voxel rim)
// the value is that of the nearest hull point (clamping: the hull is a box).
//
// A volume with a single slice along some axis has no 3D tetrahedrization:
// it is enlarged by the 2D method (upscale.hpp) on the other two axes and
// repeated along the thin one(s), which is what the 3D field would be.
//
// Methods: "ddt" (default), "delaunay" (the initial mesh, no flips), and the
// classic "trilinear" and "tricubic" (volume_resample.hpp).
//
// Volume series (4D: nt > 1 time steps, volume.hpp). The same pipeline one
// dimension up, written once as a template on D and run with D = 4: the
// Delaunay mesh of the 4D grid (core::grid_delaunay<4>, 24 simplices per
// grid cell), the generic flips and the Lawson procedure with its slabs
// along t, the limited slopes of all four axes for the cubic render, and
// core::scan_convert<4>. The time axis is normally node-centred (steps are
// instants: n steps enlarged by s become (n - 1) s + 1 and output step s k is
// input step k). Classic methods of series: "quadrilinear" and
// "tricubic-linear" (Catmull-Rom in space, linear in time), through Teem's
// resampler with a kernel and a centring per axis; "trilinear" and
// "tricubic" are taken as their names for series too. Axes of one sample
// are dropped before the reconstruction (a 2D + t series is a 3D problem)
// and the result repeated along them; a 3D input enlarged to several time
// steps is repeated along t.
//
// Errors: throws ddt::Error (empty volume, bad size, unknown method or cost).

#include "core/lawson.hpp"
#include "ddtscale/options.hpp"
#include "pipeline/stages.hpp"
#include "volume/volume.hpp"

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace ddt {

// The reconstructions: the mesh methods (ddt, and delaunay: the initial
// mesh, no flips) and the classic resamplers (trilinear and tricubic;
// for series also quadrilinear and tricubic-linear).
enum class VolumeMethod { ddt, delaunay, trilinear, tricubic, quadrilinear, tricubic_linear };
// By the names the command line takes ("tricubic-linear"); throws
// ddt::Error listing them.
VolumeMethod volume_method_by_name(const std::string& name);
const char* to_string(VolumeMethod method);
inline bool is_mesh_method(VolumeMethod method) {
  return method == VolumeMethod::ddt || method == VolumeMethod::delaunay;
}

struct VolumeUpscaleOptions {
  VolumeMethod method = VolumeMethod::ddt;  // of 3D volumes: one of volume_upscale_methods()
  std::string cost = "variance";      // a name from costs.hpp (the paper's 3D experiments use variance)
  double relative_tolerance = 1e-9;   // a flip must lower the local cost by more than this fraction
  int max_iterations = 10000;         // safety bound on Lawson sweeps
  // Input slices per slab of the parallel schedule; 0: volume_region_slices.
  // The output depends on it, never on the number of threads.
  int region_slices = 0;
  // "ddt" and "delaunay": the field drawn, cubic (core/scan_convert.hpp: a
  // cubic Bézier tetrahedron from the values and limited grid slopes at its
  // vertices, as images' cubic render) or linear per tetrahedron (the
  // paper's).
  Render render = Render::cubic;
  SlopeLimiter slopes = SlopeLimiter::mc4;
  // Axes (x, y, z) whose samples are instants rather than cells (NRRD's
  // node centring; the frames of a sequence on z): the output's first and
  // last samples sit on the input's first and last, so n samples enlarged
  // to (n - 1) * s + 1 keep every input sample at every s-th output sample.
  // Four flags, x, y, z, t (the t flag matters for series only).
  std::array<bool, 4> node_centred{};
  // Graduated optimization: when a sigma is > 0, the Lawson procedure runs
  // first on the samples smoothed by a Gaussian of that sigma (in samples)
  // along each axis (x, y, z, t; presmooth.hpp), then on the samples
  // themselves from the mesh it reached. The smoothed cost has fewer local
  // minima, so flip sequences that an unsmoothed step would refuse get
  // under way: on moving edges in space-time it is worth up to 11.5 dB
  // (docs/sequences.md).
  std::array<double, 4> presmooth{};
  // Image sequences (a series whose mesh is x, y, t; not 4D series):
  // samples where fine texture moves by at most a pixel a frame
  // (slow_texture.hpp) stay paired along time. No flip removes the edge
  // along time from such a sample, nor a simplex inside one frame whose
  // vertices all are such samples. On by default for sequences
  // (sequence_volume_defaults; docs/sequences.md, "Slow texture").
  bool keep_slow_texture = false;
  // Series whose mesh is x, y, t (image sequences): when not (0, 0), the
  // initial mesh is the Delaunay triangulation of the samples sheared by
  // this translation, pixels a frame along x and y (x - dx t, y - dy t, t),
  // instead of that of the lattice, which pairs each sample with the same
  // pixel in the next frame. upscale_sequence sets it to the frames'
  // dominant motion (dominant_motion.hpp; docs/sequences.md, "Dominant
  // motion").
  std::array<double, 2> time_shear{};
  // With it, a zoom about the frame's centre: x + time_zoom (x - c) +
  // time_shear in the next frame is where x goes (the zoom model of
  // dominant_motion.hpp); the mesh is that of the samples carried back to
  // the first frame. 0: the shear alone.
  double time_zoom = 0;
  // The frames before this part's first in the whole sequence (tiles):
  // the zoom's positions are computed from the whole sequence's frame
  // numbers, so that tiles triangulate as the whole does.
  int time_origin = 0;
  // Set by upscale_volume when it reduces a series to a 3D problem: that
  // problem's last axis is time.
  bool last_axis_is_time = false;
  // The output's samples along the mesh's last axis (z of a volume, t of a
  // series) as a window of another grid: when scale > 0, output sample j
  // there is sample first + j of the grid of that scale aligned with the
  // input as above (first may be fractional). What tiles along that axis
  // render (volume_tiles.hpp), and fractional frame rates. ddt and
  // delaunay on 3D (and 4D) mesh problems only.
  struct {
    double scale = 0;
    double first = 0;
  } last_axis;
  std::function<void(const std::string&)> log;  // verbose lines; may be empty
};

// The stage seconds and the optimizer's summary (flips by kind;
// pipeline/stages.hpp), and what is the volumes' own.
struct VolumeUpscaleStats : StageSeconds, OptimizerSummary<core::FlipCounts> {
  long long tetrahedra = 0;     // simplices of the mesh (tetrahedra; 4-simplices for series)
  bool planar = false;          // handled by the 2D method (a single slice)
  long long planar_flips = 0;   // its 2D edge flips
  long long presmooth_flips = 0;  // of the graduated optimization's first pass
  int presmooth_iterations = 0;   // and its iterations (phases of the slab schedule)
};

// The graduated optimization the command line and the Python module use
// when no --presmooth is given: sigma 1 sample in space for series (on the
// moving sphere: +0.4 dB and a cleaner isosurface, docs/volumes.md), or
// `sigma` (>= 0) in space; none for 3D volumes unless asked for (the
// sphere and the hydrogen orbital lose 0.06 and 0.16 dB with it).
std::array<double, 4> presmooth_in_space(bool series, double sigma = -1);

// Outputs larger than this many voxels are refused by the command line and
// the Python module unless raised (--max-voxels, max_voxels=).
inline constexpr long long default_max_voxels = 1LL << 29;

const std::vector<std::string>& volume_upscale_methods();  // ddt, delaunay, trilinear, tricubic
// Every method a series takes: ddt, delaunay, quadrilinear, tricubic-linear (and trilinear, tricubic).
const std::vector<std::string>& volume_series_upscale_methods();

// The simplices per grid cell of the Delaunay mesh: 6 in 3D, 24 in 4D
// (for sizing the memory of a job).
inline constexpr int simplices_per_grid_cell(int dimension) { return dimension == 4 ? 24 : dimension == 3 ? 6 : 2; }

// The default slab of the schedule for an nx x ny x nz volume: about
// core::default_region_cells tetrahedra, at least 16 slices (a flip reaches
// one slice on either side, so thinner slabs defer too much); the whole
// volume (one region, the sequential procedure) up to twice that.
int volume_region_slices(int nx, int ny, int nz);
// The same for a series: slabs of time steps (nt > 1), or of slices.
int volume_region_slices(const std::array<int, 4>& size);

// Enlarges `src` to nx x ny x nz (each >= 1).
Volume upscale_volume(const Volume& src, int nx, int ny, int nz, const VolumeUpscaleOptions& options = {},
                      VolumeUpscaleStats* stats = nullptr);
// Enlarges `src` (3D or a series) to size = {nx, ny, nz, nt} (each >= 1).
Volume upscale_volume(const Volume& src, const std::array<int, 4>& size, const VolumeUpscaleOptions& options = {},
                      VolumeUpscaleStats* stats = nullptr);

// The axes (x, y, z, t) of a series' mesh problem: every axis of more than
// one sample and, when they are fewer than three, the first others (thin
// axes, which the 3D path gives to the 2D method).
std::array<bool, 4> mesh_problem_axes(const std::array<int, 4>& in);

// The initial mesh of an image sequence (x, y, t; size = W, H, T) along a
// motion: the Delaunay triangulation of the samples carried back along it,
// over their own positions. A shear (zoom 0): (x - dx t, y - dy t, t),
// affine with determinant 1, so every cell keeps its orientation and the
// cells tile the box; the shear is taken to 1/8 pixel, so the positions
// are exact in doubles and a tile's mesh, whose frames count from its own
// first one, is the whole sequence's translated (exact tiles). With a zoom
// z a frame about the frame's centre c (VolumeUpscaleOptions::time_zoom),
// frame t's sample x is carried to u, x = c + g^t (u - c) + d (g^t - 1) /
// (g - 1), g = 1 + z, t counted from the sequence's first frame
// (time_origin + the frame in this part). That map is not affine: the
// frames are triangulated in pairs and glued (core::layered_delaunay), so
// a tetrahedron's vertices lie on two consecutive frames, where the map is
// a similarity without rotation on each; its orientation (3 + 1 vertices: a triangle's; 2 + 2: the
// sign of the cross product of its two edges) keeps its sign under the
// same linear map on both frames up to a positive scale, and the cells
// tile the box. Where the frames do not
// glue, the lattice's mesh (the Delaunay of all the samples for a shear);
// also where the zoom reaches a factor of 1024 either way. Both then take
// one in-plane shear x + y / 256, the same on every frame (which keeps the
// orientation argument), so that the lattice's cocircular squares become
// parallelograms that CGAL's filters decide without exact arithmetic.
// The largest zoom a sequence's mesh follows, first to last frame, either way.
inline constexpr double max_sequence_zoom = 1024;
core::SimplexMesh<3> motion_delaunay(const std::array<int, 3>& size, const std::array<double, 2>& shear, double zoom,
                                     int time_origin);

// The output size along an axis of n samples enlarged by s: round(n s)
// (at least 1), or (n - 1) s + 1 rounded on a node-centred axis (n > 1).
int enlarged_size(int n, double s, bool node_centred);

// The output steps of a series' time axis enlarged by time_scale, counted
// as image sequences count frames (sequence_upscale.hpp): node-centred (time
// steps are instants), floor((n - 1) s) + 1 steps at the instants g / s,
// so a fractional s sets options.last_axis (every method samples them
// there); a whole s gives (n - 1) s + 1 as enlarged_size; cell-centred,
// enlarged_size's round(n s).
int scale_time_axis(int steps, double time_scale, VolumeUpscaleOptions& options);

}  // namespace ddt
