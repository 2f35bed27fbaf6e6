#pragma once
// Scanline rasterizer for piecewise-linear surfaces on triangle meshes.
//
// Output pixel (X, Y) samples the input plane at
//     (origin_x + (X + 0.5) / scale_x,  origin_y + (Y + 0.5) / scale_y).
// Inside the convex hull of the mesh the value is the linear interpolant of
// the triangle containing that point; outside it, the value at the nearest
// point of the hull (nearest in input coordinates). The rim outside the hull
// is rendered as extra triangles: a slab per hull edge (value linear along
// the edge, constant along its outward normal) and a fan per hull corner
// (constant), so one code path covers both.
//
// Fill rule: every pixel centre is owned by exactly one triangle. Coverage
// uses exact orientation (plain double arithmetic where it is provably
// exact: coordinates on a 2^-10 grid, as at integer scales; else a filtered
// evaluation backed by CGAL's exact predicate); a centre exactly on an edge
// or vertex belongs to the triangle that contains the centre moved by an
// infinitesimal (eps, eps^2), the top-left rule made exact.
// Values: the plane through the triangle's vertex values (linear) or its
// Bézier patch (cubic), evaluated in double; samples that coincide with
// output pixel centres are then written as stored, bit for bit.
//
// Order: rows are drawn in groups with no vertex strictly between their
// rows, so the same triangles cross each row of a group in the same order;
// a walk across the mesh's adjacency visits them left to right, computing
// each edge's crossing once for the two triangles beside it. Every pixel is
// drawn once, by construction; groups are drawn in parallel (TBB). Per
// pixel one multiply-add per channel (linear). See docs/performance.md.
// Lattice meshes (pixel centres at integer scales: every vertex at the same
// fractional position in output pixels) repeat a few triangle shapes by
// whole pixels: each shape's pixels are found once with the walk's exact
// crossings and every copy draws from that list, the same pixels and bits
// with no walk (RenderGrid::by_shapes; the rim is still walked).
//
// Windows of rows: a RenderPlan keeps what every call would find over the
// whole mesh, so that a call on a few rows costs about what they hold;
// windows cut where RenderPlan::window_boundary() says have the bits of
// the whole render.
//
// A mesh with no triangles (collinear points) is rendered by linear
// interpolation along the line, clamped at its ends; a single point gives a
// constant image.

#include "util/image.hpp"
#include "image/mesh.hpp"
#include "util/progress.hpp"

#include <memory>
#include <vector>

namespace ddt {

struct RenderGrid {
  int width = 0, height = 0;        // output size in pixels
  double scale_x = 1, scale_y = 1;  // output pixels per input unit
  double origin_x = 0, origin_y = 0;  // input position of the output's top-left corner
  // Rows [first_row, first_row + rows) of the grid only (rows < 0: all):
  // the image returned has that many rows, its row 0 being grid row
  // first_row, and every pixel the value it has in the whole grid, bit for
  // bit, where the rows start and end on RenderPlan::window_boundary()
  // rows (tiled rendering, upscale.hpp).
  int first_row = 0, rows = -1;
  // Lattice meshes (every vertex at the same fractional position in output
  // pixels, as pixel centres at integer scales): draw the mesh's triangles
  // from the pixel lists of their shapes instead of walking them; same
  // pixels, same bits, faster at small scales; with the rim, convex hulls
  // only. false: always walk (tests, the benchmark's comparison).
  bool by_shapes = true;
};

struct RenderStats {
  long long triangles = 0;       // mesh triangles drawn
  long long rim_triangles = 0;   // slab and fan triangles outside the hull
  // Pixels no triangle drew: outside the hull without the rim, else 0. Each
  // row's pieces are disjoint by construction (tests check every pixel is
  // drawn once), so this is the image's pixels minus those drawn.
  long long uncovered = 0;
  // Cubic mode: pieces (a triangle's part of a group of rows) drawn from the
  // patch's power form and from its Bernstein form.
  long long power_pieces = 0;
  long long bernstein_pieces = 0;
  // Lattice meshes drawn by shape: the mesh triangles so drawn (those with
  // pixels in the rows), and the distinct shapes kept (triangles of other
  // shapes, with offsets over 64 pixels, find their rows each).
  long long shaped_triangles = 0;
  long long shapes = 0;
};

// Cubic mode (gradients given): each triangle carries the cubic Bézier
// patch of cubic_surface.hpp built from its vertices' values and gradients;
// the rim slabs carry the hull edge's cubic, constant along the normal, so
// the surface stays continuous across the hull. Samples are still
// reproduced exactly (the patch equals the vertex value at a vertex).
//
// Inputs:
//   mesh     valid Mesh2 (points in input coordinates)
//   values   #V by C vertex values, row-major
//   C        channels
//   grid     output size and sampling
//   fill_outside  render the rim outside the hull (false: those pixels keep `outside_value`)
//   gradients     nullptr: piecewise linear; else #V by C by 2 vertex gradients
//                 (d/dx, d/dy in input units) for the cubic mode; C <= 16
//   progress      if given, a stage "render" counting groups of rows (and,
//                 drawn by shape, chunks of 4096 triangles)
// Output: width x height x C image.
Image render_mesh(const Mesh2& mesh, const std::vector<float>& values, int C, const RenderGrid& grid,
                  RenderStats* stats = nullptr, bool fill_outside = true, float outside_value = 0.0f,
                  const std::vector<float>* gradients = nullptr, Progress* progress = nullptr);

// As render_mesh, drawn into `out` (grid.width wide, C channels): grid row
// first_row + i goes to out row out_row + i; other rows are left alone, and
// so are pixels no triangle owns when !fill_outside. Throws ddt::Error when
// out cannot hold the rows.
void render_mesh_into(Image& out, int out_row, const Mesh2& mesh, const std::vector<float>& values, int C,
                      const RenderGrid& grid, RenderStats* stats = nullptr, bool fill_outside = true,
                      const std::vector<float>* gradients = nullptr, Progress* progress = nullptr);

// As render_mesh_into for the linear surface (the rim drawn), but each
// pixel's value is added to the one already in `out`: the same bits as
// drawing into an image of its own and adding that, without the image
// (a correction to an output held in memory).
void add_mesh_render_into(Image& out, int out_row, const Mesh2& mesh, const std::vector<float>& values, int C,
                          const RenderGrid& grid, RenderStats* stats = nullptr);

// A mesh prepared for drawing windows of rows of one grid many times (the
// bands of a streamed output, the steps of the consistent reconstruction):
// the hull and its rim, the exactness and lattice tests, the vertices by
// output row and the rows of runs of triangles are found once, instead of
// on every call; the lattice shapes met are kept across calls. The calls
// below draw the same pixels and bits as those taking the mesh. It refers
// to `mesh`, which must outlive it unchanged; one call at a time.
class RenderPlan {
 public:
  // grid: size, scale and origin (its rows are each call's); fill_outside
  // as render_mesh's (the added render needs it).
  RenderPlan(const Mesh2& mesh, const RenderGrid& grid, bool fill_outside = true);
  ~RenderPlan();
  RenderPlan(RenderPlan&&) noexcept;
  RenderPlan& operator=(RenderPlan&&) noexcept;

  // The first row at or after `row` (clamped to the grid) where a group of
  // rows starts in the whole grid (row 0, a row r with a vertex in (r - 1,
  // r]), or the grid's height. Windows that start and end on such rows
  // draw every pixel to the bits of the whole render; a window cutting a
  // group may draw a cubic patch cut by it in its other form (power or
  // Bernstein: the form follows the pixels a piece draws), a rounding
  // apart.
  int window_boundary(int row) const;
  // The last such row at or before `row`.
  int window_start(int row) const;
  // Whether an added render can read a window of values (VertexValues):
  // triangles and a convex hull (a lattice's mesh).
  bool adds_windows_of_values() const;

  struct Prepared;
  const Prepared& prepared() const { return *prepared_; }

 private:
  std::unique_ptr<Prepared> prepared_;
};

// render_mesh_into and add_mesh_render_into on rows [first_row, first_row +
// rows) of the plan's grid (rows < 0: all of them).
void render_mesh_into(Image& out, int out_row, const RenderPlan& plan, const std::vector<float>& values, int C,
                      int first_row, int rows, RenderStats* stats = nullptr,
                      const std::vector<float>* gradients = nullptr, Progress* progress = nullptr);
void add_mesh_render_into(Image& out, int out_row, const RenderPlan& plan, const std::vector<float>& values, int C,
                          int first_row, int rows, RenderStats* stats = nullptr);

// The values of vertices [first, end) only, vertex v's C (or, as gradients,
// 2 C) at data[(v - first) * C] (2 C): a window of rows of a lattice's
// values, which slides with the rows drawn.
struct VertexValues {
  const float* data = nullptr;
  index_t first = 0, end = 0;
};
// add_mesh_render_into reading only those values. Errors: ddt::Error when
// a triangle drawn has a vertex outside [first, end), or the hull is not
// convex (a mesh a window of values cannot draw).
void add_mesh_render_into(Image& out, int out_row, const RenderPlan& plan, const VertexValues& values, int C,
                          int first_row, int rows, RenderStats* stats = nullptr);
// render_mesh_into's cubic surface with the gradients of vertices [first,
// end) only, 2 C each (x and y of every channel). Errors: ddt::Error when
// a triangle drawn (or a rim patch) needs a vertex outside them.
void render_mesh_into(Image& out, int out_row, const RenderPlan& plan, const std::vector<float>& values, int C,
                      int first_row, int rows, const VertexValues& gradients, RenderStats* stats = nullptr);

}  // namespace ddt
