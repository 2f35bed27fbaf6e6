#pragma once
// ddt::core::scan_convert<D> — scan conversion of a piecewise-linear (or,
// with vertex gradients, piecewise-cubic) field on a SimplexMesh<D> into a D-dimensional grid of samples, K channels
// (D = 3: volumes, D = 4: volume series; D = 1, 2 serve the rim, below).
//
// Output sample X = (X0, ..., X(D-1)) of the window samples the input space
// at ((first[k] + X[k] + phase[k]) / scale[k])_k: phase 0.5 is the
// pixel/voxel convention of image.hpp and volume.hpp (samples are cells),
// phase scale / 2 puts output sample 0 on input sample 0 (samples are
// instants: the frames of a sequence, node-centred axes). Inside the convex hull of the mesh the value is
// the linear interpolant of the simplex containing that point; outside it
// (the half-sample rim), the value at the nearest point of the hull.
//
// Fill rule: every sample point is owned by at most one simplex. A point
// exactly on a facet belongs to the simplex that contains it moved by an
// infinitesimal (e, e^2, ..., e^D) (predicates.hpp's perturbed_orient, the
// one symbolic tie-break), so two simplices sharing a facet never both own
// a point on it. On grids at integer and half-integer scales (points on a
// 2^-f lattice, 2 * scale integral: the "integer frame" of scan_convert.cpp)
// every side is an integer dot product and each row's samples are bounded
// exactly, tie-break included. Elsewhere the sign of a facet's side is
// taken in floating point when it clears its rounding error by far; else
// exactly, by plain arithmetic when the points satisfy lattice_exact and no
// step rounds, else by CGAL's exact predicates.
// Interpolation uses barycentric weights whose numerators and denominators
// are cofactors of the edge vectors: on lattice points (voxel centres) they
// are exact, so the weights are exactly 1 and 0 at the vertices and input
// samples are reproduced bit for bit where output samples coincide with
// them (odd integer scales).
//
// Rim: the hull must be an axis-aligned box (true of every grid's
// triangulation: [0.5, n - 0.5] per axis). The nearest hull point is then
// the sample clamped into the box; its value is the (D-1)-dimensional field
// of the hull facets in that box face, scan-converted by scan_convert<D-1>
// over the window's in-plane samples (with its own rim: clamping again).
// Samples on the hull that no simplex owns (the perturbation pushes them
// out) take that face value, which equals the interpolant there.
//
// Rows: for each simplex only the samples its sections can reach are
// visited (the section by the hyperplanes of the fixed coordinates is the
// convex hull of the crossings of the vertex pairs), in rows along the axis
// where its bounding box holds the most samples, so long thin simplices of
// an optimized mesh cost what their samples cost.
//
// Inputs:
//   mesh    valid SimplexMesh<D> (points in input coordinates), hull a box
//   values  #V by K vertex values (row-major), K >= 1
//   grid    window size, first sample and scale per axis
// Output: grid.count() * K floats, channel fastest, then axis 0, 1, ...
// Errors: throws ddt::Error when the mesh has no cells, its hull is not an
//   axis-aligned box, K < 1, or values has the wrong size.
// Complexity: O(cells + samples) (plus the rim's lower-dimensional
//   conversions); parallel over cells (TBB), each sample written by its one
//   owner; one byte per sample for the ownership count.

#include "core/cubic_patch.hpp"
#include "core/simplex_mesh.hpp"

#include <array>
#include <cstddef>
#include <vector>

namespace ddt::core {

template <int D>
struct ScanGrid {
  std::array<int, D> size{};      // samples of the window per axis
  std::array<double, D> scale{};  // output samples per input unit, per axis
  std::array<int, D> first{};     // index of the window's first sample in the whole output
  std::array<double, D> phase = filled(0.5);  // see above; 2 * phase integral keeps the exact integer frame

  std::size_t count() const {
    std::size_t n = 1;
    for (int s : size) n *= static_cast<std::size_t>(s);
    return n;
  }
  // The whole output of a grid of `input` samples enlarged to `output`;
  // on the axes flagged `node_centred`, n samples span the n - 1 intervals
  // between the first and the last (output sample 0 on input sample 0, the
  // last on the last: scale (output - 1) / (input - 1)).
  static ScanGrid whole(const std::array<int, D>& input, const std::array<int, D>& output,
                        const std::array<bool, D>& node_centred = {}) {
    ScanGrid g;
    for (int k = 0; k < D; ++k) {
      g.size[k] = output[k];
      if (node_centred[k] && input[k] > 1 && output[k] > 1) {
        g.scale[k] = double(output[k] - 1) / (input[k] - 1);
        g.phase[k] = g.scale[k] / 2;
      } else {
        g.scale[k] = double(output[k]) / input[k];
      }
    }
    return g;
  }

 private:
  static std::array<double, D> filled(double v) {
    std::array<double, D> a;
    a.fill(v);
    return a;
  }
};

struct ScanStats {
  long long cells = 0;        // simplices drawn
  long long owned = 0;        // samples owned by a simplex
  long long rim = 0;          // samples given their nearest hull point's value
  long long uncovered = 0;    // samples inside the hull no simplex owned (0 unless degenerate)
  long long overcovered = 0;  // samples owned twice (always 0; checked)
};


// gradients (optional, #V by K by D): the cubic render, one cubic Bézier
// simplex per cell from the values and gradients at its vertices (the
// D-dimensional form of image/cubic_surface.hpp's patch; continuous across
// facets, linear and quadratic fields reproduced when the gradients are
// exact); the rim's faces take the gradients' in-plane components.
template <int D>
std::vector<float> scan_convert(const SimplexMesh<D>& mesh, const std::vector<float>& values, int K,
                                const ScanGrid<D>& grid, ScanStats* stats = nullptr,
                                const std::vector<float>* gradients = nullptr);

}  // namespace ddt::core
