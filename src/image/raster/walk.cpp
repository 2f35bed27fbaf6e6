#include "image/raster/walk.hpp"

#include "util/error.hpp"

namespace ddt::raster {

void trace_walks(const Scene& scene, Walk* walks, int n, index_t stop_below) {
  index_t e[walk_batch];
  int live = 0;
  for (int i = 0; i < n; ++i) e[i] = walks[i].start, walks[i].crossed.clear(), ++live;
  const std::size_t limit = static_cast<std::size_t>(scene.triangle_count());
  while (live > 0)
    for (int i = 0; i < n; ++i) {
      if (e[i] == no_edge) continue;
      const index_t t = tri_of(e[i]);
      index_t id[3];
      scene.corners(t, id);
      const double y0 = scene.pos(id[0]).y, y1 = scene.pos(id[1]).y, y2 = scene.pos(id[2]).y;
      // The downward edge across the rows: one, since the triangle is crossed.
      const int g = walks[i].g;
      // Without branches: which edge it is varies at random from step to step.
      const int down0 = (y0 <= g) & (y1 > g), down1 = (y1 <= g) & (y2 > g);
      const int k = (1 - down0) * (2 - down1);
      walks[i].crossed.emplace_back(t, k);
      e[i] = scene.twin(3 * t + k);
      if (e[i] != no_edge && tri_of(e[i]) < stop_below) e[i] = no_edge;  // drawn by shape (lattice meshes)
      if (e[i] == no_edge) --live;
      if (walks[i].crossed.size() > limit) throw Error("render_mesh: the mesh's adjacency is inconsistent");
    }
}

}  // namespace ddt::raster
