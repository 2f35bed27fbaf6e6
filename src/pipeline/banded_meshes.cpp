#include "pipeline/banded_meshes.hpp"

#include "pipeline/upscale.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <optional>
#include <string>

namespace ddt {

struct BandedMeshes::Band {
  int first = 0, end = 0;          // input rows it draws
  int out_first = 0, out_end = 0;  // their output rows
  int top = 0;                     // its mesh's first input row
  index_t vertices = 0;
  Mesh2 mesh;
  std::vector<float> values;       // its rows of the input, by its vertex ids
  std::optional<RenderPlan> plan;  // reads `mesh`: a Band does not move
};

namespace {

// Rows [first, end) lie in the bands held: a draw never leaves rows unset.
template <class Bands>
void check_held(const Bands& bands, int first, int end) {
  long long covered = 0;
  for (const auto& band : bands) covered += std::max(0, std::min(end, band->out_end) - std::max(first, band->out_first));
  if (covered != end - first)
    throw Error("the consistent reconstruction: output rows " + std::to_string(first) + ".." + std::to_string(end) +
                " are not all in the mesh bands held");
}

// The window of `w` (vertices of the whole image, `per_vertex` floats each)
// that the band's vertex ids [0, vertices) hold, in those ids.
VertexValues in_band(const VertexValues& w, index_t offset, index_t vertices, int per_vertex) {
  const index_t first = std::max(w.first, offset), end = std::min(w.end, offset + vertices);
  if (end <= first) return {};
  return {w.data + static_cast<std::size_t>(first - w.first) * per_vertex, first - offset, end - offset};
}

}  // namespace

BandedMeshes::BandedMeshes(InputRows& input, const RenderGrid& grid, int band_rows, int region_rows, int margin,
                           MakeBandMesh make)
    : input_(input), grid_(grid), band_rows_(std::max(1, band_rows)), region_rows_(region_rows),
      margin_(std::max(0, margin)), make_(std::move(make)) {}

BandedMeshes::~BandedMeshes() = default;

int BandedMeshes::next_band_first() const {
  if (bands_.empty()) return next_first_;
  // The first input row whose output rows are not all released.
  // The wavefront's mesh steps trail its surface by about K (reach + 2)
  // rows (K = 2 steps); bands take over up to twice that, or a quarter band.
  const int H = input_.height(), max_overlap = std::max(band_rows_ / 4, 4 * (reach_ + 2));
  for (int row = next_first_; row >= 0 && next_first_ - row <= max_overlap; --row)
    if (output_row_of(row, H, grid_.height) <= released_) return row;
  return next_first_;
}

void BandedMeshes::make_next() {
  const int W = input_.width(), H = input_.height();
  const std::size_t row_floats = static_cast<std::size_t>(W) * input_.channels();
  auto band = std::make_unique<Band>();
  // Where the rows the bands held still draw lie close enough before the
  // next (next_band_first), the next band takes them over and the others
  // are freed first: one band's mesh held, not two.
  band->first = next_band_first();
  if (band->first < next_first_) bands_.clear();
  band->end = std::min(H, next_first_ + band_rows_);
  if (band->first >= H) throw Error("the consistent reconstruction: no rows left for a mesh band");
  int bottom = H, span = 0;
  for (;;) {
    band->top = std::max(0, band->first - margin_);
    bottom = std::min(H, band->end + margin_);
    int held_top = 0;
    const Image& held = input_.rows(band->top, bottom, held_top);
    band->values.assign(held.pixels.begin() + static_cast<std::ptrdiff_t>(row_floats * (band->top - held_top)),
                        held.pixels.begin() + static_cast<std::ptrdiff_t>(row_floats * (bottom - held_top)));
    BandMesh made = make_(band->top, bottom, band->values);
    span = ddt::triangle_rows(made.mesh, band->first, band->end);  // those that draw the band's rows
    const int needed = band_margin_needed(made.phases, region_rows_) + span + 1;
    const bool top_holds = band->top == 0 || band->first - band->top >= needed;
    const bool bottom_holds = bottom == H || bottom - band->end >= needed;
    if (top_holds && bottom_holds) {
      band->mesh = std::move(made.mesh);
      break;
    }
    margin_ = widened_band_margin(margin_, needed, region_rows_);
    ++redone_;
  }
  band->vertices = static_cast<index_t>(band->mesh.points.size());
  if (band->vertices != static_cast<index_t>(W) * (bottom - band->top))
    throw Error("the consistent reconstruction: a band's mesh is not its rows' pixel grid");
  band->out_first = output_row_of(band->first, H, grid_.height);
  band->out_end = output_row_of(band->end, H, grid_.height);
  band->plan.emplace(band->mesh, grid_);
  reach_ = std::max(reach_, span);
  triangles_ += band->mesh.triangle_count();
  ++made_;
  next_first_ = band->end;
  bands_.push_back(std::move(band));
  most_held_ = std::max(most_held_, static_cast<int>(bands_.size()));
}

const BandedMeshes::Band& BandedMeshes::band_at(int row) const {
  for (const auto& band : bands_)
    if (row >= band->out_first && row < band->out_end) return *band;
  throw Error("the consistent reconstruction: output row " + std::to_string(row) + " has no mesh band ready");
}

int BandedMeshes::prepare(int row) {
  if (row >= grid_.height) return grid_.height;
  while (bands_.empty() || bands_.back()->out_end <= row) make_next();
  return band_at(row).out_end;
}

int BandedMeshes::window_boundary(int row) const {
  for (const auto& band : bands_)
    if (row > band->out_first && row <= band->out_end)  // a band's end is a boundary: draws are cut there
      return std::min(band->out_end, band->plan->window_boundary(row));
  return row;
}

void BandedMeshes::draw(Image& into, int at, int first, int end, const VertexValues* gradients, RenderStats* stats) {
  const int C = input_.channels();
  const std::ptrdiff_t row_floats = static_cast<std::ptrdiff_t>(grid_.width) * C;
  check_held(bands_, first, end);
  RenderStats local;
  for (const auto& owned : bands_) {
    const Band& band = *owned;
    const int f = std::max(first, band.out_first), e = std::min(end, band.out_end);
    if (f >= e) continue;
    const index_t offset = static_cast<index_t>(band.top) * input_.width();
    const std::optional<VertexValues> slopes =
        gradients ? std::optional<VertexValues>(in_band(*gradients, offset, band.vertices, 2 * C)) : std::nullopt;
    // Where [f, e) cuts a group of the band's rows, the groups around it
    // are drawn whole and the rows kept (the bits of an uncut draw).
    const int a = band.plan->window_start(f), b = std::min(grid_.height, band.plan->window_boundary(e));
    const bool aligned = a == f && b == e;
    Image groups;
    if (!aligned) groups = Image(grid_.width, b - a, C);
    Image& target = aligned ? into : groups;
    const int target_row = aligned ? at + (f - first) : 0;
    if (slopes) render_mesh_into(target, target_row, *band.plan, band.values, C, a, b - a, *slopes, &local);
    else render_mesh_into(target, target_row, *band.plan, band.values, C, a, b - a, &local);
    if (!aligned)
      std::copy(groups.pixels.begin() + row_floats * (f - a), groups.pixels.begin() + row_floats * (e - a),
                into.pixels.begin() + row_floats * (at + (f - first)));
  }
  if (stats) {
    *stats = local;
    stats->triangles = triangles_;
  }
}

void BandedMeshes::add(Image& into, int at, int first, int end, const std::vector<float>& rows,
                       index_t first_vertex, index_t end_vertex) {
  const int C = input_.channels();
  const VertexValues values{rows.data(), first_vertex, end_vertex};
  check_held(bands_, first, end);
  for (const auto& owned : bands_) {
    const Band& band = *owned;
    const int f = std::max(first, band.out_first), e = std::min(end, band.out_end);
    if (f >= e) continue;
    const index_t offset = static_cast<index_t>(band.top) * input_.width();
    add_mesh_render_into(into, at + (f - first), *band.plan, in_band(values, offset, band.vertices, C), C, f, e - f);
  }
}

void BandedMeshes::release(int row) {
  released_ = std::max(released_, row);
  while (!bands_.empty() && bands_.front()->out_end <= row) bands_.pop_front();
}

int BandedMeshes::first_input_row() const {
  const int H = input_.height();
  // A band made again wider reads a region more at least.
  return next_first_ < H ? std::max(0, next_band_first() - margin_ - region_rows_) : H;
}

}  // namespace ddt
