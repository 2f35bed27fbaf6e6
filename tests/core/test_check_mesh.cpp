#include "core/check_mesh.hpp"
#include "core/predicates.hpp"
#include "core_test_support.hpp"

#include <doctest/doctest.h>

#include <string>

using namespace ddt;
using namespace ddt::core;
using ddt::core::test::Dim;

namespace {

// The unit simplex (cell 0) and a cell across its facet opposite the
// origin, apex (1, ..., 1) (cell 1): D + 2 points, two cells, one glued facet.
template <int D>
SimplexMesh<D> two_cells() {
  std::vector<Vec<D>> points;
  for (const auto& p : test::unit_simplex<D>()) points.push_back(p);
  Vec<D> apex;
  apex.fill(1);
  points.push_back(apex);
  CellVertices<D> first, second;
  for (int i = 0; i <= D; ++i) first[i] = i;
  for (int i = 0; i < D; ++i) second[i] = i + 1;
  second[D] = D + 1;
  return mesh_from_cells<D>(points, {first, second});
}

bool mentions(const std::string& problem, const std::string& word) { return problem.find(word) != std::string::npos; }

}  // namespace

TEST_CASE_TEMPLATE("core check_mesh: two cells glued across a facet are valid", T, Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  const SimplexMesh<D> mesh = two_cells<D>();
  CHECK(check_mesh<D>(mesh) == "");
  CHECK(mesh.cell_count() == 2);
  // Exactly one glued pair: facet 0 of cell 0 (opposite the origin).
  int glued = 0;
  for (index_t f = 0; f < 2 * (D + 1); ++f) glued += mesh.opp[f] != no_facet;
  CHECK(glued == 2);
  CHECK(cell_of<D>(mesh.opp[0]) == 1);
  // Content: 1/D! and (D - 1)/D! (the apexes lie at distances 1 and D - 1
  // times 1/sqrt(D) from the facet's hyperplane, x1 + ... + xD = 1).
  double factorial = 1;
  for (int i = 2; i <= D; ++i) factorial *= i;
  CHECK(total_content(mesh) == doctest::Approx(D / factorial));
}

TEST_CASE_TEMPLATE("core check_mesh: names a broken twin, orientation, facet, side, free list, hull and Euler", T,
                   Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  const SimplexMesh<D> valid = two_cells<D>();
  const index_t f = 0, g = valid.opp[0];

  SimplexMesh<D> m = valid;
  m.opp[g] = 1;  // g points elsewhere
  CHECK(mentions(check_mesh<D>(m), "not glued symmetrically"));

  m = valid;
  std::swap(m.cell[1], m.cell[2]);  // cell 0 reversed
  CHECK(mentions(check_mesh<D>(m), "not strictly positively oriented"));

  m = valid;
  const index_t other = (g == D + 1) ? D + 2 : D + 1;  // another facet of cell 1
  m.opp[other] = f, m.opp[f] = other, m.opp[g] = no_facet;
  CHECK(mentions(check_mesh<D>(m), "different vertices"));

  // The second apex moved to the origin's side of the shared facet (the
  // cell stays positive after mesh_from_cells reorders it): overlap.
  {
    std::vector<Vec<D>> points = valid.points;
    points[D + 1].fill(0.1);
    CellVertices<D> first, second;
    for (int i = 0; i <= D; ++i) first[i] = i;
    for (int i = 0; i < D; ++i) second[i] = i + 1;
    second[D] = D + 1;
    SimplexMesh<D> overlap = mesh_from_cells<D>(points, {first, second});
    CHECK(mentions(check_mesh<D>(overlap), "same side"));
  }

  m = valid;
  m.free_slots.push_back(0);  // a live slot listed as free
  CHECK(mentions(check_mesh<D>(m), "free slot list"));

  m = valid;
  m.opp[f] = no_facet, m.opp[g] = no_facet;  // the shared facet counted twice on the hull
  CHECK(mentions(check_mesh<D>(m), "hull ridge"));

  // A second, disjoint copy: two balls, Euler characteristic 2.
  m = valid;
  const index_t shift = static_cast<index_t>(m.points.size());
  for (index_t v = 0; v < shift; ++v) {
    Vec<D> p = m.points[v];
    p[0] += 10;
    m.points.push_back(p);
  }
  for (index_t c = 0; c < 2; ++c) {
    CellVertices<D> v = valid.cell_vertices(c);
    for (index_t& id : v) id += shift;
    m.add_cell(v);
  }
  link_facets(m);
  CHECK(mentions(check_mesh<D>(m), "Euler characteristic 2"));
}

TEST_CASE_TEMPLATE("core link_facets: refuses three cells on one facet", T, Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  SimplexMesh<D> m = two_cells<D>();
  Vec<D> apex;
  apex.fill(2);
  m.points.push_back(apex);
  CellVertices<D> third;
  for (int i = 0; i < D; ++i) third[i] = i + 1;
  third[D] = D + 2;
  m.add_cell(third);
  CHECK_FALSE(link_facets(m));
}
