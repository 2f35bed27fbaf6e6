#pragma once
// What a run reports: the seconds of its stages and the optimizer's
// summary, the parts every pipeline's statistics (images, scattered
// points, volumes) are made of, and the image enlargement's own.

namespace ddt {

// Seconds spent in the stages of a run (summed over tiles).
struct StageSeconds {
  double seconds_triangulate = 0, seconds_optimize = 0, seconds_render = 0;
  StageSeconds& operator+=(const StageSeconds& other) {
    seconds_triangulate += other.seconds_triangulate;
    seconds_optimize += other.seconds_optimize;
    seconds_render += other.seconds_render;
    return *this;
  }
};

// What the optimizer reports, whatever the dimension: `Flips` is a count
// (2D) or the counts by kind (core::FlipCounts).
template <class Flips>
struct OptimizerSummary {
  int iterations = 0;  // iterations, or phases of the region schedule
  Flips flips{};
  double cost_before = 0, cost_after = 0;

  // Takes the summary of a LawsonStats (2D or core): the same fields.
  template <class Lawson>
  void take(const Lawson& ls) {
    iterations = ls.iterations;
    flips = ls.flips;
    cost_before = ls.cost_before;
    cost_after = ls.cost_after;
  }
};

// An image enlargement's: the stage seconds and the optimizer's summary
// (total cost of the mesh before and after the flips; summed over tiles),
// and the image pipeline's own.
struct UpscaleStats : StageSeconds, OptimizerSummary<long long> {
  long long triangles = 0;
  long long tests = 0;   // edge tests of the optimizer
  int regions = 1;       // optimizer regions (of the first tile)
  int tiles = 1;         // bands the image was processed in
  int tile_margin = 0;   // rows of overlap on each side of a tile
  // The consistent reconstruction (model other than point).
  int consistency_mesh_steps = 0;    // back-projection steps on the data-dependent mesh
  double consistency_residual = 0;  // max |input - acquire(output)| at input resolution, before rounding
  double seconds_consistency = 0;
};

}  // namespace ddt
