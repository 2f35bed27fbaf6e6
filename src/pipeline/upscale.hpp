#pragma once
// ddt::upscale — enlarge an image by data-dependent triangulation (DDT):
// the library's forms on ddt::Image (the public ImageBuf forms,
// ddtscale/ddtscale.hpp, call these), the mesh stage, and bands.
//
// Pipeline: samples at pixel centres -> Delaunay triangulation (CGAL) ->
// generalized Lawson optimization of the cost -> rendering of the surface
// (options.render: cubic patches or the piecewise-linear surface) at the
// output resolution -> the consistent reconstruction (options.model).
//
// Output pixel (X, Y) samples the surface at ((X + 0.5) / sx, (Y + 0.5) / sy)
// with sx = out_width / in_width, sy = out_height / in_height. Outside the
// convex hull of the samples (the half-pixel rim) the value is that of the
// nearest hull point.
//
// Errors: throws ddt::Error (bad options, empty image).

#include "consistency/acquisition_model.hpp"
#include "consistency/input_statistics.hpp"
#include "ddtscale/ddtscale.hpp"
#include "image/annealing.hpp"
#include "image/mesh.hpp"
#include "pipeline/stages.hpp"
#include "util/image.hpp"
#include "util/progress.hpp"

#include <functional>
#include <string>
#include <vector>

namespace ddt {

// Enlarges `src` to out_width x out_height (each >= 1).
Image upscale(const Image& src, int out_width, int out_height, const UpscaleOptions& options = {},
              UpscaleStats* stats = nullptr);

// Whether upscale_by_rows takes the enlargement of a width x height x
// channels image to out_width x out_height, streamed: under the box model
// at an integer scale, from meshes made by bands (wavefront_mesh_band_rows
// > 0), not cut into tiles.
bool upscale_reads_by_rows(int width, int height, int channels, int out_width, int out_height,
                           const UpscaleOptions& options);
// As upscale() streamed, the input read from `source` a window of rows at
// a time (after a pass for its statistics), so that what is held of it
// depends on the width, not on the height (util/input_rows.hpp). The rows
// handed to options.output_rows are upscale()'s, bit for bit.
// Throws ddt::Error where upscale_reads_by_rows is false, and the source's.
UpscaleStats upscale_by_rows(const RowSource& source, int out_width, int out_height, const UpscaleOptions& options);

// The mesh stage of upscale(), untiled: the Delaunay triangulation of the
// pixel centres (vertex y * width + x at (x + 0.5, y + 0.5)) after the flips
// `options` asks for; what upscale() renders when it does not tile. Logs
// and tells the progress as upscale() does. Throws ddt::Error as upscale().
Mesh2 upscale_mesh(const Image& src, const UpscaleOptions& options = {}, UpscaleStats* stats = nullptr);

// One band of the enlargement, for callers that split an image themselves
// (Dask blocks, python/ddtscale/dask.py): output rows
// [output_row_of(first), output_row_of(end)) of upscale(image, out_width,
// out_height, options), computed from input rows [top, top + rows.height)
// of the image (image_height rows in all) that hold [first, end) with
// margins. Equal to those rows of upscale() bit for bit when the band is the
// whole image, or under Lawson's region schedule (options.region_rows > 0,
// or automatic on a large image) with margins of band_margin_needed(phases,
// region_rows) rows where the band is cut, plus, under a consistent model,
// consistency_margin_needed() rows (consistent_reconstruction.hpp); a band
// of a consistent model also needs the whole input's `statistics`.
// Throws ddt::Error otherwise (too narrow a margin: after the work, with the
// width needed; or, when margin_needed is given, sets it and returns an
// empty image).
Image upscale_rows(const Image& rows, int top, int image_height, int first, int end, int out_width, int out_height,
                   const UpscaleOptions& options = {}, UpscaleStats* stats = nullptr,
                   const InputStatistics* statistics = nullptr, int* margin_needed = nullptr);
// Adds a band's stage seconds, triangles and optimizer summary to those of
// the bands before it (phases: the most any band ran; regions: the first
// band's).
void add_band_stats(UpscaleStats& total, const UpscaleStats& band, bool first_band);
// The first output row sampled at or below input row y.
int output_row_of(int y, int in_height, int out_height);
// Input rows per mesh band when the whole image's streamed consistent
// reconstruction draws from meshes made by bands (BandedMeshes; the
// wavefront of make_consistent_streamed), 0 where it draws from one mesh;
// and the bytes such a job holds: a band's mesh with its margins and its
// rows of the input, and the wavefront's output rows (docs/performance.md).
int wavefront_mesh_band_rows(int width, int height, int out_width, int out_height, const UpscaleOptions& options);
double wavefront_mesh_bytes(int width, int height, int channels, int out_width, int out_height, int band_rows,
                            const UpscaleOptions& options);
// Rows of margin a band needs on a cut side for `phases` phases of the
// region schedule (docs/performance.md).
int band_margin_needed(int phases, int region_rows);
// Whether an image of width x height enlarged to out_width x out_height
// gets the consistent reconstruction: a model other than point, and no
// axis reduced (a reduction cannot reproduce the input).
bool is_consistent(int width, int height, int out_width, int out_height, const AcquisitionModel& model);
// The margin the bands (upscale_banded, also upscale()'s tiles) start with: two
// regions and the consistent reconstruction's planned reach (when
// `consistent`); and the wider one a band is redone with when its mesh
// needed `needed` rows.
int planned_band_margin(int region_rows, bool consistent, const AcquisitionModel& model, int width, int height,
                        int out_width, int out_height);
int widened_band_margin(int margin, int needed, int region_rows);

}  // namespace ddt
