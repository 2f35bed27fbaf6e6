#pragma once
// ddt::BandedMeshes — the meshes the whole image's streamed consistent
// reconstruction (make_consistent_streamed) draws from, made a band of
// rows at a time: a band's mesh when the wavefront reaches its rows, freed
// once the wavefront has passed them. One band's mesh with its margins is
// held, not the image's: the wavefront's last mesh step trails its surface
// by a few triangles' height, so when the surface reaches a band's end the
// next band starts at the first row not yet released (a few dozen rows
// back) and the band before is freed before it is made. (Where more than
// a quarter band, or four triangle heights and more, is still unreleased,
// the next band starts at the band's end and both are held.)
//
// A band draws input rows [first, end) (the output rows sampled there,
// first_output_row). Its mesh is made by the caller (MakeBandMesh:
// triangulated and optimized under the region schedule on rows [top,
// bottom), the band with `margin` rows each side where the image goes on).
// The margin is enough when, on each cut side, it holds the optimizer's
// reach for the phases it ran (band_margin_needed) plus the height of the
// triangles over the band's rows; else the band is made again with a wider
// one (widened_band_margin), which later bands keep. Then the triangles
// over its rows are the whole image's mesh's (the tiles' argument,
// docs/performance.md), and every draw gives that mesh's bits.
//
// Vertex ids are the whole image's pixels, row by row, as the wavefront
// counts them; a band's mesh numbers its own from row `top`.

#include "consistency/consistent_reconstruction.hpp"

#include <deque>
#include <functional>
#include <memory>

namespace ddt {

struct BandMesh {
  Mesh2 mesh;      // of input rows [top, bottom): vertex v is pixel (v % W, top + v / W)
  int phases = 0;  // the optimizer's phases
};
// rows: the input's rows [top, bottom), W C floats a row.
using MakeBandMesh = std::function<BandMesh(int top, int bottom, const std::vector<float>& rows)>;

class BandedMeshes final : public WavefrontMeshes {
 public:
  // input: the whole input's rows (each band keeps a copy of its own);
  // grid: the surface's output grid; band_rows: input rows a band draws;
  // margin: the margin tried first.
  BandedMeshes(InputRows& input, const RenderGrid& grid, int band_rows, int region_rows, int margin,
               MakeBandMesh make);
  ~BandedMeshes() override;

  int prepare(int row) override;
  int triangle_rows() const override { return reach_; }
  bool slides() const override { return true; }
  int window_boundary(int row) const override;
  void draw(Image& into, int at, int first, int end, const VertexValues* gradients, RenderStats* stats) override;
  void add(Image& into, int at, int first, int end, const std::vector<float>& rows, index_t first_vertex,
           index_t end_vertex) override;
  void release(int row) override;
  int first_input_row() const override;

  int bands_made() const { return made_; }
  int bands_redone() const { return redone_; }
  // The most bands held at once.
  int most_held() const { return most_held_; }
  int margin() const { return margin_; }
  long long triangles() const { return triangles_; }

 private:
  struct Band;
  void make_next();
  int next_band_first() const;
  const Band& band_at(int row) const;

  InputRows& input_;
  RenderGrid grid_;
  int band_rows_, region_rows_, margin_;
  MakeBandMesh make_;
  std::deque<std::unique_ptr<Band>> bands_;  // in row order, those not yet released
  int next_first_ = 0;                       // the first input row of the next band
  int released_ = 0;                         // output rows before it are drawn no more
  // At least the planned height: the wavefront drops rows of values by the
  // reach it knows, so a later band's taller triangles must not outrun it
  // (they would be refused, not drawn wrong).
  int reach_ = planned_triangle_rows;
  int made_ = 0, redone_ = 0, most_held_ = 0;
  long long triangles_ = 0;
};

}  // namespace ddt
