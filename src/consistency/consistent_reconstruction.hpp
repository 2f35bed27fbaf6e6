#pragma once
// ddt::make_consistent — the consistent reconstruction: the output,
// mapped back to the input grid by the acquisition model
// (acquisition_model.hpp), reproduces the input.
//
// The rendered surface O0 (cubic or linear, on the optimized mesh) is
// corrected in two parts, both solved at input resolution:
//   1. on the data-dependent mesh: a few back-projection steps
//      delta1 += r - A delta1 (A v: the acquisition of the linear render of
//      vertex values v on the mesh, applied by rendering), kept while they
//      lower the residual. The correction follows the edges the flips
//      found instead of ringing across them; but a mesh with long thin
//      triangles makes A ill-conditioned (a vertex of thin triangles has
//      little weight in its own footprint), so it is not solved exactly.
//   2. on the bilinear surface of the pixel grid (grid_surface.hpp), whose
//      operator G is well-conditioned and separable: G delta2 = the rest,
//      solved exactly, axis by axis.
//   O = O0 + render_linear(mesh, delta1) + bilinear(delta2),
// so that acquire(O) = src up to rounding, whatever the scale.
//   3. step edges (box model): a footprint whose 3x3 input pixels one
//      straight edge between two levels explains is drawn as that edge
//      (step_edges.hpp), sharp to the output pixel;
//   4. halos: each footprint's values are clamped to the range of the 3x3
//      input pixels around it (open below at a strict local minimum, above
//      at a strict maximum: a thin dark line may go darker than any input
//      pixel) after a common shift that keeps the footprint's mean; where
//      that moves the acquisition (other models, non-integer scales), one
//      more exact grid correction.
// docs/consistency.md has the measurements behind these choices.
//
// Bands: every step is local (the grid solve by canonical blocks,
// grid_surface.hpp), so a band of rows (a tile, a Dask block) with
// consistency_margin_needed() rows of margin on each cut side, beyond the
// rows its mesh needs, computes its inner rows to the same bits as the
// whole image, given the whole input's statistics (input_statistics.hpp).
//
// Inputs:
//   out        the rendered surface, out_width x out_height x C, C <= 16
//              (corrected in place); or the output rows of a band's input
//              rows (options.band)
//   mesh       the mesh it was rendered from; its points the pixel centres
//              of src, in the whole image's coordinates
//   src        the input image (or the band's rows), width x height x C
// Errors: throws ddt::Error when a mesh is not src's pixel grid.

#include "consistency/acquisition_model.hpp"
#include "consistency/footprints.hpp"
#include "consistency/input_statistics.hpp"
#include "util/image.hpp"
#include "util/input_rows.hpp"
#include "image/mesh.hpp"
#include "image/rasterizer.hpp"
#include "util/progress.hpp"

#include <functional>

namespace ddt {

struct ConsistencyOptions {
  AcquisitionModel model;       // not point
  int mesh_steps = 2;           // back-projection steps on the data-dependent mesh
  double tolerance = 1e-6;      // a final grid correction where limiting left more than 10x this
  bool limit_halos = true;      // clamp overshoots beside edges, keeping each footprint's mean
  bool step_edges = true;       // box model: footprints on one straight edge drawn as that edge
  // When set, the corrected output is also handed to this in bands of
  // about output_band_rows rows, top to bottom, each row once. Where the
  // last steps are local to each footprint (box at integer scales) a band
  // is handed out as soon as it is finished, so that its encoding overlaps
  // the work on the next; elsewhere once the whole output is.
  std::function<void(Image rows, int first_row)> output_rows;
  int output_band_rows = 256;
  // When set, called once the mesh is read no more (before the last
  // steps), so that the caller can free it.
  std::function<void()> mesh_done;
  // Where src and out lie in the whole image (default: they are it), and
  // the whole input's statistics (default: src's own).
  RowBand band;
  const InputStatistics* statistics = nullptr;
  // make_consistent_streamed's wavefront: its finished input rows, as a
  // stage "consistency".
  Progress* progress = nullptr;
};

struct ConsistencyStats {
  int mesh_steps = 0;           // back-projection steps kept
  double residual_mesh = 0;     // max residual after the mesh steps
  double residual_before = 0;   // max |src - acquire(O0)| over pixels and channels
  double residual_after = 0;    // the same for the solved delta, at input resolution
  long long halo_footprints = 0;  // footprints and channels whose overshoot was limited
  long long step_edge_footprints = 0;  // footprints drawn as one straight edge
  double seconds_operator = 0, seconds_solve = 0, seconds_render = 0;
  double seconds_surface = 0;  // make_consistent_streamed: drawing the rendered surface
  int held_rows = 0;            // make_consistent_streamed: output rows held at a time (0: the whole output)
};

void make_consistent(Image& out, const Mesh2& mesh, const Image& src, const ConsistencyOptions& options,
                     ConsistencyStats* stats = nullptr);

// The cubic render's vertex gradients of input rows [first, end): 2 C
// floats a vertex (rasterizer.hpp), the lattice's vertices row by row.
using GradientRows = std::function<std::vector<float>(int first, int end)>;

// The meshes make_consistent_streamed draws from, by output rows: one
// mesh (the overload below), or bands of rows each with a mesh of its own,
// made when the wavefront reaches them and freed once it has passed
// (pipeline/banded_meshes.hpp). Every draw gives the one mesh's bits.
// Vertex ids are the whole image's pixels, row by row.
class WavefrontMeshes {
 public:
  virtual ~WavefrontMeshes() = default;
  // Makes ready the mesh that draws output row `row` (and the rows before
  // it that are still to be drawn); returns the end of the output rows
  // drawn by meshes ready from `row` on (more than `row`).
  virtual int prepare(int row) = 0;
  // The most input rows a triangle of the meshes made so far spans.
  virtual int triangle_rows() const = 0;
  // Whether draws read windows of rows of values (rasterizer.hpp:
  // RenderPlan::adds_windows_of_values); else whole arrays of them.
  virtual bool slides() const = 0;
  // The first row at or after `row` (at most prepare's end) where a draw
  // of the surface may end at the least cost (RenderPlan::window_boundary).
  virtual int window_boundary(int row) const = 0;
  // The rendered surface of output rows [first, end) (prepared), cubic
  // where `gradients` is set, into `into`'s rows from `at`.
  virtual void draw(Image& into, int at, int first, int end, const VertexValues* gradients, RenderStats* stats) = 0;
  // The linear surface of vertex values added into output rows [first,
  // end): `rows` holds those of vertices [first_vertex, end_vertex) (C a
  // vertex, from rows[0]); where the meshes do not slide, every vertex's,
  // from vertex 0.
  virtual void add(Image& into, int at, int first, int end, const std::vector<float>& rows, index_t first_vertex,
                   index_t end_vertex) = 0;
  // Output rows before `row` are drawn no more.
  virtual void release(int row) = 0;
  // The first input row the meshes still to be made read (the height when
  // they read none), so that the input's rows before it can be dropped.
  virtual int first_input_row() const = 0;
};

// As make_consistent on the whole image, with the rendered surface (mesh
// drawn from `values`, cubic where `gradients` is set: rasterizer.hpp)
// drawn here instead of held, and the result handed to
// options.output_rows (required). Where make_consistent_streams() (box at
// integer scales) the steps run as a wavefront down the rows: each on the
// rows whose inputs the steps before have finished, so that only the
// output rows between the first unfinished and the last drawn are held
// (the steps' reach: a few hundred output rows), not the whole output, and
// the gradients and the mesh steps' values of the rows the render still
// reads; same bits. Elsewhere the surface is drawn whole and corrected by
// make_consistent. `values` and `gradients` are not read after
// options.mesh_done.
void make_consistent_streamed(int out_width, int out_height, const std::vector<float>& values,
                              const GradientRows& gradients, const Mesh2& mesh, const Image& src,
                              const ConsistencyOptions& options, ConsistencyStats* stats = nullptr,
                              RenderStats* render_stats = nullptr);
bool make_consistent_streams(const AcquisitionModel& model, int width, int height, int out_width, int out_height);
// The wavefront on meshes of the caller's, where make_consistent_streams()
// (else a ddt::Error). Growing meshes.triangle_rows() as bands are made
// only widens the rows held. The input is read through `input` a window of
// rows at a time, released behind the last steps (and before the next
// mesh band's rows); unless it is held whole, options.statistics is
// required.
void make_consistent_streamed(int out_width, int out_height, WavefrontMeshes& meshes, const GradientRows& gradients,
                              InputRows& input, const ConsistencyOptions& options, ConsistencyStats* stats = nullptr,
                              RenderStats* render_stats = nullptr);

// Input rows of margin a band needs on a cut side, beyond those its mesh
// needs, for the consistent reconstruction of an image of width x height
// to out_width x out_height to equal the whole image's there, when the
// band mesh's triangles span at most triangle_rows rows (triangle_rows()).
int consistency_margin_needed(int triangle_rows, const AcquisitionModel& model, int width, int height, int out_width,
                              int out_height, int mesh_steps = ConsistencyOptions{}.mesh_steps);
// The most rows a triangle of the mesh spans; with a range, of the
// triangles that reach input rows [first, end] (vertex y is its row + 0.5).
int triangle_rows(const Mesh2& mesh);
int triangle_rows(const Mesh2& mesh, int first, int end);
// What to plan a band's margin for before its mesh is made: optimized
// meshes of Set14's photographs spanned 5 to 13 rows (docs/consistency.md);
// a band whose mesh spans more is redone or refused with the width needed.
constexpr int planned_triangle_rows = 16;

}  // namespace ddt
