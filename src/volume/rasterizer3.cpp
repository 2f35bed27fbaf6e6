#include "volume/rasterizer3.hpp"

#include "util/error.hpp"
#include "core/predicates.hpp"
#include "image/rasterizer.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <map>

namespace ddt {
namespace {

using core::no_facet;
using Point3 = core::Vec<3>;

// Face i of a cell read as (cell[face_vertex[i][0..2]]) has vertex i on its
// positive side (the normals below point inwards).
constexpr int face_vertex[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};

// Error-free transformations (Knuth's TwoSum, FMA TwoProduct): true when
// x op y was computed without rounding.
bool exact_sum(double x, double y, double sum) {
  const double yv = sum - x, xv = sum - yv;
  return (x - xv) + (y - yv) == 0;
}
bool exact_product(double x, double y, double product) { return std::fma(x, y, -product) == 0; }

// u x v in floating point; `exact` tells whether no step rounded.
void cross(const double u[3], const double v[3], double out[3], bool& exact) {
  exact = true;
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const double p = u[i] * v[j], q = u[j] * v[i];
    out[k] = p - q;
    exact = exact && exact_product(u[i], v[j], p) && exact_product(u[j], v[i], q) && exact_sum(p, -q, out[k]);
  }
}

// The sign of n . (q - a) when every step is exact (then +1, -1 or a true
// 0); returns false when some step rounded.
bool exact_dot_sign(const double n[3], const Point3& q, const Point3& a, int& sign) {
  const double d[3] = {q[0] - a[0], q[1] - a[1], q[2] - a[2]};
  if (!exact_sum(q[0], -a[0], d[0]) || !exact_sum(q[1], -a[1], d[1]) || !exact_sum(q[2], -a[2], d[2])) return false;
  double sum = 0;
  for (int k = 0; k < 3; ++k) {
    const double prod = n[k] * d[k];
    const double next = sum + prod;
    if (!exact_product(n[k], d[k], prod) || !exact_sum(sum, prod, next)) return false;
    sum = next;
  }
  sign = sum > 0 ? 1 : sum < 0 ? -1 : 0;
  return true;
}

// The six faces of the hull box: axis (0 x, 1 y, 2 z) and side (0 min, 1 max).
struct Box {
  double lo[3], hi[3];
};

double coord(const Point3& p, int axis) { return p[axis]; }

// In-plane axes of a box face perpendicular to `axis`.
constexpr int plane_axes[3][2] = {{1, 2}, {0, 2}, {0, 1}};

// Renders the hull triangles of each box face as a 2D field over the output
// grid's in-plane samples (with the 2D rim rule: clamping).
std::array<Image, 6> render_box_faces(const core::SimplexMesh<3>& mesh, const std::vector<float>& values, const VolumeGrid& grid,
                                      const Box& box) {
  std::array<std::vector<std::array<index_t, 3>>, 6> faces;
  for (index_t t = 0; t < mesh.slot_count(); ++t) {
    if (!mesh.is_live(t)) continue;
    for (int i = 0; i < 4; ++i) {
      if (mesh.opp[4 * t + i] != no_facet) continue;
      std::array<index_t, 3> f;
      for (int k = 0; k < 3; ++k) f[k] = mesh.cell[4 * t + face_vertex[i][k]];
      int which = -1;
      for (int axis = 0; axis < 3 && which < 0; ++axis)
        for (int s = 0; s < 2 && which < 0; ++s) {
          const double plane = s ? box.hi[axis] : box.lo[axis];
          bool on = true;
          for (index_t v : f) on = on && coord(mesh.points[v], axis) == plane;
          if (on) which = 2 * axis + s;
        }
      if (which < 0) throw Error("render_tetrahedra: the mesh's hull is not an axis-aligned box");
      faces[which].push_back(f);
    }
  }
  const int size[3] = {grid.nx, grid.ny, grid.nz};
  const double scale[3] = {grid.scale_x, grid.scale_y, grid.scale_z};
  std::array<Image, 6> images;
  for (int which = 0; which < 6; ++which) {
    const int axis = which / 2, u = plane_axes[axis][0], v = plane_axes[axis][1];
    if (faces[which].empty()) throw Error("render_tetrahedra: the mesh's hull is not an axis-aligned box");
    Mesh2 m2;
    std::vector<float> values2;
    std::map<index_t, index_t> local;
    std::map<std::pair<index_t, index_t>, index_t> directed;
    for (auto f : faces[which]) {
      for (index_t& id : f) {
        auto [it, fresh] = local.emplace(id, static_cast<index_t>(m2.points.size()));
        if (fresh) {
          m2.points.push_back({coord(mesh.points[id], u), coord(mesh.points[id], v)});
          values2.push_back(values[id]);
        }
        id = it->second;
      }
      if (orientation(m2.points[f[0]], m2.points[f[1]], m2.points[f[2]]) < 0) std::swap(f[1], f[2]);
      for (int k = 0; k < 3; ++k) {
        directed[{f[k], f[(k + 1) % 3]}] = static_cast<index_t>(m2.tri.size());
        m2.tri.push_back(f[k]);
      }
    }
    m2.opp.assign(m2.tri.size(), no_edge);
    for (const auto& [edge, e] : directed) {
      auto twin = directed.find({edge.second, edge.first});
      if (twin != directed.end()) m2.opp[e] = twin->second;
    }
    RenderGrid g2;
    g2.width = size[u];
    g2.height = size[v];
    g2.scale_x = scale[u];
    g2.scale_y = scale[v];
    images[which] = render_mesh(m2, values2, 1, g2);
  }
  return images;
}

// Per-tetrahedron data for coverage and interpolation.
struct TetSetup {
  Point3 p[4];
  double raw[4][3];  // (b - a) x (c - a) of face i read in face_vertex order
  bool raw_exact[4]; // ... computed without rounding
  double n[4][3];    // inward unit normals of the faces (face i opposite vertex i)
  double off[4];     // n . x + off >= 0 inside
  double lam[3][3];  // barycentric numerators' normals (for vertices 1..3)
  double den[3];
  double z0, dz[3];
};

}  // namespace

Volume render_tetrahedra(const core::SimplexMesh<3>& mesh, const std::vector<float>& values, const VolumeGrid& grid,
                         Render3Stats* stats) {
  if (mesh.cell_count() == 0) throw Error("render_tetrahedra: the mesh has no tetrahedra");
  Render3Stats local;
  Box box{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  for (index_t t = 0; t < mesh.slot_count(); ++t) {
    if (!mesh.is_live(t)) continue;
    ++local.tetrahedra;
    for (int i = 0; i < 4; ++i)
      for (int axis = 0; axis < 3; ++axis) {
        const double c = coord(mesh.points[mesh.cell[4 * t + i]], axis);
        box.lo[axis] = std::min(box.lo[axis], c);
        box.hi[axis] = std::max(box.hi[axis], c);
      }
  }
  const std::array<Image, 6> faces = render_box_faces(mesh, values, grid, box);

  // Sample positions, computed once so every test sees the same doubles.
  std::vector<double> xs(grid.nx), ys(grid.ny), zs(grid.nz);
  for (int X = 0; X < grid.nx; ++X) xs[X] = (X + 0.5) / grid.scale_x;
  for (int Y = 0; Y < grid.ny; ++Y) ys[Y] = (Y + 0.5) / grid.scale_y;
  for (int Z = 0; Z < grid.nz; ++Z) zs[Z] = (Z + 0.5) / grid.scale_z;
  const double extent = std::max({box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2], 1.0});
  const double tol = 1e-9 * (extent + std::abs(box.lo[0]) + std::abs(box.lo[1]) + std::abs(box.lo[2]));

  Volume out(grid.nx, grid.ny, grid.nz);
  std::vector<unsigned char> hits(out.voxel_count(), 0);
  // Index range of samples whose coordinate may lie in [lo, hi].
  auto index_range = [&](double lo, double hi, double scale, int n, int& first, int& last) {
    first = std::max(0, static_cast<int>(std::ceil((lo - tol) * scale - 0.5)));
    last = std::min(n - 1, static_cast<int>(std::floor((hi + tol) * scale - 0.5)));
  };

  tbb::parallel_for(tbb::blocked_range<index_t>(0, mesh.slot_count(), 256), [&](const tbb::blocked_range<index_t>& r) {
    for (index_t t = r.begin(); t != r.end(); ++t) {
      if (!mesh.is_live(t)) continue;
      TetSetup s;
      const index_t* ids = &mesh.cell[4 * t];
      for (int i = 0; i < 4; ++i) s.p[i] = mesh.points[ids[i]];
      double lo[3], hi[3];
      for (int axis = 0; axis < 3; ++axis) {
        lo[axis] = hi[axis] = coord(s.p[0], axis);
        for (int i = 1; i < 4; ++i) {
          lo[axis] = std::min(lo[axis], coord(s.p[i], axis));
          hi[axis] = std::max(hi[axis], coord(s.p[i], axis));
        }
      }
      int y0, y1, z0, z1, xb0, xb1;
      index_range(lo[1], hi[1], grid.scale_y, grid.ny, y0, y1);
      index_range(lo[2], hi[2], grid.scale_z, grid.nz, z0, z1);
      index_range(lo[0], hi[0], grid.scale_x, grid.nx, xb0, xb1);
      if (y0 > y1 || z0 > z1 || xb0 > xb1) continue;
      for (int i = 0; i < 4; ++i) {
        const Point3 &a = s.p[face_vertex[i][0]], &b = s.p[face_vertex[i][1]], &c = s.p[face_vertex[i][2]];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        cross(u, v, s.raw[i], s.raw_exact[i]);
        const double* n = s.raw[i];
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; ++k) s.n[i][k] = n[k] / len;
        s.off[i] = -(s.n[i][0] * a[0] + s.n[i][1] * a[1] + s.n[i][2] * a[2]);
      }
      // lambda_i(p) = lam_i . (p - p0) / den_i, lam_1 = e2 x e3 etc., so
      // lambda_i(p_i) is exactly 1 and lambda_i(p0) exactly 0.
      const Point3& p0 = s.p[0];
      double e[3][3];
      for (int i = 0; i < 3; ++i) {
        e[i][0] = s.p[i + 1][0] - p0[0], e[i][1] = s.p[i + 1][1] - p0[1], e[i][2] = s.p[i + 1][2] - p0[2];
      }
      for (int i = 0; i < 3; ++i) {
        const double* a = e[(i + 1) % 3];
        const double* b = e[(i + 2) % 3];
        s.lam[i][0] = a[1] * b[2] - a[2] * b[1];
        s.lam[i][1] = a[2] * b[0] - a[0] * b[2];
        s.lam[i][2] = a[0] * b[1] - a[1] * b[0];
        s.den[i] = s.lam[i][0] * e[i][0] + s.lam[i][1] * e[i][1] + s.lam[i][2] * e[i][2];
      }
      s.z0 = values[ids[0]];
      for (int i = 0; i < 3; ++i) s.dz[i] = double(values[ids[i + 1]]) - s.z0;

      // Ownership of a sample, face by face: the floating-point distance
      // when it clears its rounding error by far (tol); else the exact sign
      // of (b - a) x (c - a) . (q - a) when no step of it rounds (voxel
      // grids at power-of-two scales), with perturbed_orient's tie-break read
      // off the exact normal; else core::perturbed_orient<3> (exact).
      auto face_side = [&](int i, const Point3& q) {
        const double d = s.n[i][0] * q[0] + s.n[i][1] * q[1] + s.n[i][2] * q[2] + s.off[i];
        if (d > tol) return 1;
        if (d < -tol) return -1;
        int sign = 0;
        if (s.raw_exact[i] && exact_dot_sign(s.raw[i], q, s.p[face_vertex[i][0]], sign)) {
          if (sign != 0) return sign;
          for (int k = 0; k < 3; ++k)
            if (s.raw[i][k] != 0) return s.raw[i][k] > 0 ? 1 : -1;
        }
        return core::perturbed_orient<3>({s.p[face_vertex[i][0]], s.p[face_vertex[i][1]], s.p[face_vertex[i][2]], q});
      };
      auto inside = [&](const Point3& q) {
        for (int i = 0; i < 4; ++i)
          if (face_side(i, q) <= 0) return false;
        return true;
      };
      for (int Z = z0; Z <= z1; ++Z) {
        const double z = zs[Z];
        // The rows the section at z can reach: the y extent of the points
        // where the six edges cross the plane (an optimized mesh has long
        // thin tetrahedra whose bounding box holds many empty rows).
        double section_lo = INFINITY, section_hi = -INFINITY;
        for (int i = 0; i < 4; ++i)
          for (int j = i + 1; j < 4; ++j) {
            const double zi = s.p[i][2], zj = s.p[j][2];
            if ((zi - z) * (zj - z) > 0) continue;
            const double y = zi == zj ? s.p[i][1] : s.p[i][1] + (z - zi) / (zj - zi) * (s.p[j][1] - s.p[i][1]);
            section_lo = std::min({section_lo, y, zi == zj ? s.p[j][1] : y});
            section_hi = std::max({section_hi, y, zi == zj ? s.p[j][1] : y});
          }
        int ys0 = y0, ys1 = y1;
        if (section_lo <= section_hi) {
          index_range(section_lo, section_hi, grid.scale_y, grid.ny, ys0, ys1);
          ys0 = std::max(ys0, y0);
          ys1 = std::min(ys1, y1);
        }
        for (int Y = ys0; Y <= ys1; ++Y) {
          const double y = ys[Y];
          // The segment of the row inside the tetrahedron, in floating point.
          double x_lo = lo[0], x_hi = hi[0];
          bool empty = false;
          for (int i = 0; i < 4 && !empty; ++i) {
            const double rest = s.n[i][1] * y + s.n[i][2] * z + s.off[i];
            const double nx = s.n[i][0];
            if (std::abs(nx) < 1e-12) {
              empty = rest < -tol;
            } else if (nx > 0) {
              x_lo = std::max(x_lo, -rest / nx);
            } else {
              x_hi = std::min(x_hi, -rest / nx);
            }
          }
          if (empty || x_lo > x_hi + 2 * tol) continue;
          int X0, X1;
          index_range(x_lo, x_hi, grid.scale_x, grid.nx, X0, X1);
          X0 = std::max(X0, xb0);
          X1 = std::min(X1, xb1);
          // Exact trim at both ends; the owned samples of a row are contiguous.
          while (X0 <= X1 && !inside({xs[X0], y, z})) ++X0;
          while (X1 >= X0 && !inside({xs[X1], y, z})) --X1;
          if (X0 > X1) continue;
          const double py = y - p0[1], pz = z - p0[2];
          for (int X = X0; X <= X1; ++X) {
            const double px = xs[X] - p0[0];
            double v = s.z0;
            for (int i = 0; i < 3; ++i)
              v += (s.lam[i][0] * px + s.lam[i][1] * py + s.lam[i][2] * pz) / s.den[i] * s.dz[i];
            const std::size_t idx = out.index(X, Y, Z);
            out.voxels[idx] = static_cast<float>(v);
            std::atomic_ref<unsigned char>(hits[idx]).fetch_add(1, std::memory_order_relaxed);
          }
        }
      }
    }
  });

  // Samples no tetrahedron owns: outside the hull (or on it) -> the face
  // value at the clamped position.
  std::atomic<long long> owned{0}, rim{0}, uncovered{0}, overcovered{0};
  tbb::parallel_for(0, grid.nz, [&](int Z) {
    long long n_owned = 0, n_rim = 0, n_uncovered = 0, n_over = 0;
    for (int Y = 0; Y < grid.ny; ++Y)
      for (int X = 0; X < grid.nx; ++X) {
        const std::size_t idx = out.index(X, Y, Z);
        if (hits[idx] == 1) {
          ++n_owned;
          continue;
        }
        if (hits[idx] > 1) {
          ++n_over;
          continue;
        }
        const double q[3] = {xs[X], ys[Y], zs[Z]};
        const int index[3] = {X, Y, Z};
        int which = -1;
        for (int axis = 0; axis < 3 && which < 0; ++axis) {
          if (q[axis] <= box.lo[axis]) which = 2 * axis;
          else if (q[axis] >= box.hi[axis]) which = 2 * axis + 1;
        }
        if (which < 0) {
          ++n_uncovered;
          continue;
        }
        const int axis = which / 2;
        out.voxels[idx] = faces[which].at(index[plane_axes[axis][0]], index[plane_axes[axis][1]]);
        ++n_rim;
      }
    owned += n_owned, rim += n_rim, uncovered += n_uncovered, overcovered += n_over;
  });
  local.owned = owned;
  local.rim = rim;
  local.uncovered = uncovered;
  local.overcovered = overcovered;
  if (local.uncovered > 0) {
    // Only slivers collapsed by rounding could leave a hole; copy a neighbour.
    for (int Z = 0; Z < grid.nz; ++Z)
      for (int Y = 0; Y < grid.ny; ++Y)
        for (int X = 0; X < grid.nx; ++X) {
          const std::size_t idx = out.index(X, Y, Z);
          if (hits[idx] != 0) continue;
          const double q[3] = {xs[X], ys[Y], zs[Z]};
          bool in = true;
          for (int axis = 0; axis < 3; ++axis) in = in && q[axis] > box.lo[axis] && q[axis] < box.hi[axis];
          if (in) out.voxels[idx] = out.voxels[out.index(X > 0 ? X - 1 : std::min(X + 1, grid.nx - 1), Y, Z)];
        }
  }
  if (stats) *stats = local;
  return out;
}

}  // namespace ddt
