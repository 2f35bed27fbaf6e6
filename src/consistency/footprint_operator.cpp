#include "consistency/footprint_operator.hpp"

#include "util/error.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace ddt {
namespace {

// Side of p relative to u->v, exact, the (eps, eps^2) perturbation of p
// deciding ties: +1 left, -1 right, never 0 (as the rasterizer's).
// On a lattice of 2^-10 below 2^15 (pixel centres at integer and dyadic
// scales) the determinant in double is exact: differences below 2^16 on
// that lattice have 26 bits, products 52, their difference fits 53.
bool on_exact_lattice(double c) {
  const double scaled = c * 1024;
  return scaled == std::floor(scaled) && std::abs(c) < 32768;
}

int perturbed_side(const Point2& u, const Point2& v, const Point2& p) {
  const double det = signed_area2(u, v, p);
  const double bound = 1e-14 * (std::abs((v.x - u.x) * (p.y - u.y)) + std::abs((v.y - u.y) * (p.x - u.x)));
  int s = det > bound ? 1 : det < -bound ? -1 : 0;
  if (s == 0 && !(det == 0 && on_exact_lattice(p.x) && on_exact_lattice(p.y) && on_exact_lattice(u.x) &&
                  on_exact_lattice(u.y) && on_exact_lattice(v.x) && on_exact_lattice(v.y)))
    s = orientation(u, v, p);
  if (s != 0) return s;
  if (u.y != v.y) return u.y > v.y ? 1 : -1;
  return v.x > u.x ? 1 : -1;
}

bool owns(const Point2& a, const Point2& b, const Point2& c, const Point2& p) {
  return perturbed_side(a, b, p) > 0 && perturbed_side(b, c, p) > 0 && perturbed_side(c, a, p) > 0;
}

}  // namespace

std::vector<index_t> pixel_owners(const Mesh2& mesh, int W, int H, int out_w, int out_h) {
  const double sx = static_cast<double>(out_w) / W, sy = static_cast<double>(out_h) / H;
  std::vector<index_t> owner(static_cast<std::size_t>(out_w) * out_h, -1);
  tbb::parallel_for(index_t(0), mesh.triangle_count(), [&](index_t t) {
    const Point2& a = mesh.points[mesh.tri[3 * t]];
    const Point2& b = mesh.points[mesh.tri[3 * t + 1]];
    const Point2& c = mesh.points[mesh.tri[3 * t + 2]];
    const double ymin = std::min({a.y, b.y, c.y}), ymax = std::max({a.y, b.y, c.y});
    const int Y0 = std::max(0, static_cast<int>(std::floor(ymin * sy - 0.5)));
    const int Y1 = std::min(out_h - 1, static_cast<int>(std::ceil(ymax * sy - 0.5)));
    const std::array<const Point2*, 3> v{&a, &b, &c};
    for (int Y = Y0; Y <= Y1; ++Y) {
      const double cy = (Y + 0.5) / sy;
      if (!(cy > 0.5 && cy < H - 0.5) || cy < ymin || cy > ymax) continue;
      double xl = INFINITY, xr = -INFINITY;
      for (int k = 0; k < 3; ++k) {
        const Point2& p = *v[k];
        const Point2& q = *v[(k + 1) % 3];
        if ((p.y <= cy && cy <= q.y) || (q.y <= cy && cy <= p.y)) {
          const double x = p.y == q.y ? p.x : p.x + (cy - p.y) * (q.x - p.x) / (q.y - p.y);
          if (p.y == q.y) xl = std::min({xl, p.x, q.x}), xr = std::max({xr, p.x, q.x});
          else xl = std::min(xl, x), xr = std::max(xr, x);
        }
      }
      if (xl > xr) continue;
      const int X0 = std::max(0, static_cast<int>(std::floor(xl * sx - 0.5)) - 1);
      const int X1 = std::min(out_w - 1, static_cast<int>(std::ceil(xr * sx - 0.5)) + 1);
      // The span's ends carry rounding far below `clear`: a centre further
      // inside is the triangle's, one near an end is decided exactly.
      const double clear = 1e-7 * (1 + std::abs(xl) + std::abs(xr));
      for (int X = X0; X <= X1; ++X) {
        const double cx = (X + 0.5) / sx;
        if (!(cx > 0.5 && cx < W - 0.5) || cx < xl - clear || cx > xr + clear) continue;
        if ((cx > xl + clear && cx < xr - clear) || owns(a, b, c, Point2{cx, cy}))
          owner[static_cast<std::size_t>(Y) * out_w + X] = t;
      }
    }
  });
  return owner;
}

namespace {

struct Entry {
  index_t col;
  double weight;
};

struct Triplet {
  int x;  // footprint in the row
  index_t col;
  double w;
};

// Per-thread buffers of the row assembly.
struct Scratch {
  std::vector<Triplet> triplets, overflow;
  std::vector<Entry> entries;
  std::vector<int> count;
};

// The barycentric coordinates of p in triangle t.
std::array<double, 3> barycentric(const Mesh2& mesh, index_t t, const Point2& p) {
  const index_t* v = &mesh.tri[3 * t];
  const Point2 &a = mesh.points[v[0]], &b = mesh.points[v[1]], &c = mesh.points[v[2]];
  const double area = signed_area2(a, b, c);
  const double l0 = signed_area2(p, b, c) / area, l1 = signed_area2(a, p, c) / area;
  return {l0, l1, 1 - l0 - l1};
}

// The rim: the clamped centre, linear between grid neighbours along the
// hull's unit edges. Returns the number of entries (1 or 2).
int rim_weights(int W, int H, double cx, double cy, std::array<Entry, 2>& e) {
  const double px = std::clamp(cx, 0.5, W - 0.5) - 0.5, py = std::clamp(cy, 0.5, H - 0.5) - 0.5;
  const int ix = std::min(W - 1, static_cast<int>(px)), iy = std::min(H - 1, static_cast<int>(py));
  const double fx = px - ix, fy = py - iy;
  if (fx > 0) {
    e = {Entry{iy * W + ix, 1 - fx}, Entry{iy * W + ix + 1, fx}};
    return 2;
  }
  if (fy > 0) {
    e = {Entry{iy * W + ix, 1 - fy}, Entry{(iy + 1) * W + ix, fy}};
    return 2;
  }
  e[0] = {iy * W + ix, 1};
  return 1;
}

}  // namespace

void add_linear_surface(Image& out, const Mesh2& mesh, const std::vector<index_t>& owners, int W, int H,
                        const std::vector<double>& values) {
  const int C = out.channels;
  const double sx = static_cast<double>(out.width) / W, sy = static_cast<double>(out.height) / H;
  tbb::parallel_for(0, out.height, [&](int Y) {
    const double cy = (Y + 0.5) / sy;
    for (int X = 0; X < out.width; ++X) {
      const double cx = (X + 0.5) / sx;
      float* o = &out.pixels[out.index(X, Y)];
      const index_t t = owners[static_cast<std::size_t>(Y) * out.width + X];
      if (t >= 0) {
        const index_t* v = &mesh.tri[3 * t];
        const auto [l0, l1, l2] = barycentric(mesh, t, Point2{cx, cy});
        const double *z0 = &values[std::size_t(v[0]) * C], *z1 = &values[std::size_t(v[1]) * C],
                     *z2 = &values[std::size_t(v[2]) * C];
        for (int ch = 0; ch < C; ++ch) o[ch] += static_cast<float>(l0 * z0[ch] + l1 * z1[ch] + l2 * z2[ch]);
      } else {
        std::array<Entry, 2> e{};
        const int ne = rim_weights(W, H, cx, cy, e);
        for (int ch = 0; ch < C; ++ch) {
          double z = 0;
          for (int i = 0; i < ne; ++i) z += e[i].weight * values[std::size_t(e[i].col) * C + ch];
          o[ch] += static_cast<float>(z);
        }
      }
    }
  });
}

void SparseRows::multiply(const std::vector<double>& x, std::vector<double>& y, int channels) const {
  y.assign(static_cast<std::size_t>(rows) * channels, 0.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, 4096), [&](const tbb::blocked_range<int>& r) {
    for (int i = r.begin(); i < r.end(); ++i) {
      double* out = &y[static_cast<std::size_t>(i) * channels];
      for (std::int64_t k = start[i]; k < start[i + 1]; ++k) {
        const double* in = &x[static_cast<std::size_t>(col[k]) * channels];
        for (int c = 0; c < channels; ++c) out[c] += weight[k] * in[c];
      }
    }
  });
}

SparseRows footprint_operator(const Mesh2& mesh, int W, int H, int out_w, int out_h, const AcquisitionModel& model) {
  return footprint_operator(mesh, pixel_owners(mesh, W, H, out_w, out_h), W, H, out_w, out_h, model);
}

SparseRows footprint_operator(const Mesh2& mesh, const std::vector<index_t>& owner, int W, int H, int out_w, int out_h,
                              const AcquisitionModel& model) {
  if (mesh.points.size() != static_cast<std::size_t>(W) * H)
    throw Error("footprint_operator: the mesh is not the pixel grid");
  if (owner.size() != static_cast<std::size_t>(out_w) * out_h) throw Error("footprint_operator: owners of another grid");
  const AxisWeights wx = axis_weights(model, W, out_w), wy = axis_weights(model, H, out_h);
  const double sx = static_cast<double>(out_w) / W, sy = static_cast<double>(out_h) / H;

  const auto by_row = by_input_pixel(wy, H);  // input row -> (output row, weight)

  tbb::enumerable_thread_specific<Scratch> scratch_of;
  // One input row of A at a time: (footprint x, vertex, weight) triplets,
  // sorted and merged.
  std::vector<std::vector<Entry>> row_entries(H);
  std::vector<int> row_counts(static_cast<std::size_t>(W) * H, 0);
  tbb::parallel_for(0, H, [&](int jy) {
    std::vector<Triplet>& trip = scratch_of.local().triplets;
    trip.clear();
    // Pixels of one triangle in one footprint come in runs along a row: the
    // barycentric coordinates are affine, so a run's sum of w * lambda is
    // its total weight times lambda at its weighted mean centre.
    struct Run {
      int x = -1;
      index_t t = -1;
      double w = 0, wcx = 0;
    };
    std::vector<Run> open;
    double cy = 0;
    auto flush = [&](Run& r) {
      if (r.t >= 0 && r.w != 0) {
        const index_t* v = &mesh.tri[3 * r.t];
        const auto [l0, l1, l2] = barycentric(mesh, r.t, Point2{r.wcx / r.w, cy});
        trip.push_back({r.x, v[0], r.w * l0});
        trip.push_back({r.x, v[1], r.w * l1});
        trip.push_back({r.x, v[2], r.w * l2});
      }
      r = Run{};
    };
    for (const auto& [Y, wrow] : by_row[jy]) {
      cy = (Y + 0.5) / sy;
      const bool rim_row = !(cy > 0.5 && cy < H - 0.5);
      for (int X = 0; X < out_w; ++X) {
        const double cx = (X + 0.5) / sx;
        const index_t t = rim_row ? -1 : owner[static_cast<std::size_t>(Y) * out_w + X];
        if (t >= 0) {
          for (int k = wx.first[X]; k < wx.first[X + 1]; ++k) {
            const double w = wrow * wx.weight[k];
            auto it = std::find_if(open.begin(), open.end(), [&](const Run& r) { return r.x == wx.pixel[k]; });
            if (it == open.end()) it = open.insert(open.end(), Run{});
            if (it->t != t) {
              flush(*it);
              it->x = wx.pixel[k];
              it->t = t;
            }
            it->w += w;
            it->wcx += w * cx;
          }
          // Runs of footprints this pixel no longer reaches are complete.
          if (open.size() > static_cast<std::size_t>(wx.first[X + 1] - wx.first[X])) {
            for (Run& r : open)
              if (r.x < wx.pixel[wx.first[X]]) flush(r);
            open.erase(std::remove_if(open.begin(), open.end(), [](const Run& r) { return r.t < 0; }), open.end());
          }
          continue;
        }
        std::array<Entry, 2> e{};
        const int ne = rim_weights(W, H, cx, cy, e);
        for (int k = wx.first[X]; k < wx.first[X + 1]; ++k) {
          const double w = wrow * wx.weight[k];
          for (int i = 0; i < ne; ++i) trip.push_back({wx.pixel[k], e[i].col, w * e[i].weight});
        }
      }
      for (Run& r : open) flush(r);
      open.clear();
    }
    // Merge by footprint and vertex: a few entries per footprint, searched
    // in place; the rare footprint with more spills to `overflow`.
    constexpr int capacity = 32;
    Scratch& scratch = scratch_of.local();
    scratch.entries.resize(static_cast<std::size_t>(W) * capacity);
    scratch.count.assign(W, 0);
    scratch.overflow.clear();
    for (const Triplet& t : trip) {
      Entry* list = &scratch.entries[static_cast<std::size_t>(t.x) * capacity];
      int& n = scratch.count[t.x];
      int i = 0;
      while (i < n && list[i].col != t.col) ++i;
      if (i < n) list[i].weight += t.w;
      else if (n < capacity) list[n++] = {t.col, t.w};
      else scratch.overflow.push_back({t.x, t.col, t.w});
    }
    std::sort(scratch.overflow.begin(), scratch.overflow.end(),
              [](const Triplet& p, const Triplet& q) { return p.x < q.x; });
    std::size_t next_overflow = 0;
    std::vector<Entry>& out = row_entries[jy];
    out.clear();
    for (int x = 0; x < W; ++x) {
      Entry* list = &scratch.entries[static_cast<std::size_t>(x) * capacity];
      const std::size_t begin = out.size();
      out.insert(out.end(), list, list + scratch.count[x]);
      for (; next_overflow < scratch.overflow.size() && scratch.overflow[next_overflow].x == x; ++next_overflow) {
        const auto& [ox, col, w] = scratch.overflow[next_overflow];
        auto it = std::find_if(out.begin() + static_cast<std::ptrdiff_t>(begin), out.end(),
                               [col = col](const Entry& e) { return e.col == col; });  // clang 14: no binding captured
        if (it == out.end()) out.push_back({col, w});
        else it->weight += w;
      }
      std::sort(out.begin() + static_cast<std::ptrdiff_t>(begin), out.end(),
                [](const Entry& p, const Entry& q) { return p.col < q.col; });
      row_counts[static_cast<std::size_t>(jy) * W + x] = static_cast<int>(out.size() - begin);
    }
  });

  SparseRows A;
  A.rows = A.cols = W * H;
  A.start.assign(static_cast<std::size_t>(W) * H + 1, 0);
  for (std::size_t i = 0; i < row_counts.size(); ++i) A.start[i + 1] = A.start[i] + row_counts[i];
  A.col.resize(A.start.back());
  A.weight.resize(A.start.back());
  tbb::parallel_for(0, H, [&](int jy) {
    std::int64_t k = A.start[static_cast<std::size_t>(jy) * W];
    for (const Entry& e : row_entries[jy]) {
      A.col[k] = e.col;
      A.weight[k++] = static_cast<float>(e.weight);
    }
  });
  return A;
}

}  // namespace ddt
