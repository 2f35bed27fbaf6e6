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

struct VolumeUpscaleOptions {
  std::string method = "ddt";         // one of volume_upscale_methods()
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
  std::array<bool, 3> node_centred{};
  // Graduated optimization: when a sigma is > 0, the Lawson procedure runs
  // first on the samples smoothed by a Gaussian of that sigma (in samples)
  // along each axis (presmooth.hpp), then on the samples themselves from
  // the mesh it reached. The smoothed cost has fewer local minima, so flip
  // sequences that an unsmoothed step would refuse get under way: on
  // moving edges in space-time it is worth up to 12 dB (docs/sequences.md).
  std::array<double, 3> presmooth{};
  std::function<void(const std::string&)> log;  // verbose lines; may be empty
};

// The stage seconds and the optimizer's summary (flips by kind;
// pipeline/stages.hpp), and what is the volumes' own.
struct VolumeUpscaleStats : StageSeconds, OptimizerSummary<core::FlipCounts> {
  long long tetrahedra = 0;
  bool planar = false;          // handled by the 2D method (a single slice)
  long long planar_flips = 0;   // its 2D edge flips
  long long presmooth_flips = 0;  // of the graduated optimization's first pass
};

// Outputs larger than this many voxels are refused by the command line and
// the Python module unless raised (--max-voxels, max_voxels=).
inline constexpr long long default_max_voxels = 1LL << 29;

const std::vector<std::string>& volume_upscale_methods();  // ddt, delaunay, trilinear, tricubic

// The default slab of the schedule for an nx x ny x nz volume: about
// core::default_region_cells tetrahedra, at least 16 slices (a flip reaches
// one slice on either side, so thinner slabs defer too much); the whole
// volume (one region, the sequential procedure) up to twice that.
int volume_region_slices(int nx, int ny, int nz);

// Enlarges `src` to nx x ny x nz (each >= 1).
Volume upscale_volume(const Volume& src, int nx, int ny, int nz, const VolumeUpscaleOptions& options = {},
                      VolumeUpscaleStats* stats = nullptr);

}  // namespace ddt
