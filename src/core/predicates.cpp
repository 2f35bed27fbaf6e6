// The one place the core reaches CGAL's predicates (the dD kernel's headers
// are heavy: no header of ours includes them). Epick_d needs Eigen: CGAL
// enables it when Eigen's headers are on the include path, which
// ddtscale_lib's Eigen3::Eigen dependency provides.
#include "core/predicates.hpp"

#include <CGAL/Epick_d.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>

namespace ddt::core {
namespace {

using Kernel23 = CGAL::Exact_predicates_inexact_constructions_kernel;
template <int D>
using KernelD = CGAL::Epick_d<CGAL::Dimension_tag<D>>;

Kernel23::Point_2 point2(const Vec<2>& p) { return {p[0], p[1]}; }
Kernel23::Point_3 point3(const Vec<3>& p) { return {p[0], p[1], p[2]}; }

template <int D>
typename KernelD<D>::Point_d point_d(const Vec<D>& p) {
  return typename KernelD<D>::Point_d(p.begin(), p.end());
}

template <int D>
std::array<typename KernelD<D>::Point_d, D + 1> points_d(const std::array<Vec<D>, D + 1>& p) {
  std::array<typename KernelD<D>::Point_d, D + 1> out;
  for (int i = 0; i <= D; ++i) out[i] = point_d<D>(p[i]);
  return out;
}

}  // namespace

template <int D>
bool lattice_exact(const std::vector<Vec<D>>& points) {
  return lattice_exact<D>(points, [](const Vec<D>& p, int k) { return p[k]; });
}

template <int D>
int orient(const std::array<Vec<D>, D + 1>& p) {
  if constexpr (D == 1) {
    return (p[1][0] > p[0][0]) - (p[1][0] < p[0][0]);  // a comparison does not round
  } else if constexpr (D == 2) {
    return static_cast<int>(CGAL::orientation(point2(p[0]), point2(p[1]), point2(p[2])));
  } else if constexpr (D == 3) {
    return static_cast<int>(CGAL::orientation(point3(p[0]), point3(p[1]), point3(p[2]), point3(p[3])));
  } else {
    const auto q = points_d<D>(p);
    return static_cast<int>(KernelD<D>().orientation_d_object()(q.begin(), q.end()));
  }
}

template <int D>
int in_sphere(const std::array<Vec<D>, D + 1>& s, const Vec<D>& q) {
  if constexpr (D == 1) {
    const double lo = std::min(s[0][0], s[1][0]), hi = std::max(s[0][0], s[1][0]);
    return (q[0] > lo && q[0] < hi) ? 1 : (q[0] == lo || q[0] == hi) ? 0 : -1;
  } else if constexpr (D == 2) {
    return static_cast<int>(CGAL::side_of_bounded_circle(point2(s[0]), point2(s[1]), point2(s[2]), point2(q)));
  } else if constexpr (D == 3) {
    return static_cast<int>(
        CGAL::side_of_bounded_sphere(point3(s[0]), point3(s[1]), point3(s[2]), point3(s[3]), point3(q)));
  } else {
    const auto p = points_d<D>(s);
    return static_cast<int>(KernelD<D>().side_of_bounded_sphere_d_object()(p.begin(), p.end(), point_d<D>(q)));
  }
}

template <int D>
int perturbed_orient(const std::array<Vec<D>, D + 1>& p) {
  const int exact = orient<D>(p);
  if (exact != 0) return exact;
  std::array<Vec<D>, D> facet;
  std::copy(p.begin(), p.begin() + D, facet.begin());
  return perturbed_tie<D>(facet);
}

template <int D>
std::array<int, D + 2> radon_partition(const std::array<Vec<D>, D + 2>& s) {
  std::array<int, D + 2> sign;
  for (int i = 0; i < D + 2; ++i) {
    std::array<Vec<D>, D + 1> rest;
    for (int j = 0, n = 0; j < D + 2; ++j)
      if (j != i) rest[n++] = s[j];
    const int o = orient<D>(rest);
    sign[i] = (i % 2 == 0) ? o : -o;
  }
  return sign;
}

#define DDT_CORE_INSTANTIATE(D)                                               \
  template int orient<D>(const std::array<Vec<D>, D + 1>&);                   \
  template bool lattice_exact<D>(const std::vector<Vec<D>>&);                 \
  template int in_sphere<D>(const std::array<Vec<D>, D + 1>&, const Vec<D>&); \
  template int perturbed_orient<D>(const std::array<Vec<D>, D + 1>&);         \
  template std::array<int, D + 2> radon_partition<D>(const std::array<Vec<D>, D + 2>&);
DDT_CORE_INSTANTIATE(1)
DDT_CORE_INSTANTIATE(2)
DDT_CORE_INSTANTIATE(3)
DDT_CORE_INSTANTIATE(4)
#undef DDT_CORE_INSTANTIATE

}  // namespace ddt::core
