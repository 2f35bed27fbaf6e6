#include "pipeline/banded_upscale.hpp"

#include "consistency/consistent_reconstruction.hpp"
#include "consistency/input_statistics.hpp"
#include "image/image_mesh.hpp"
#include "pipeline/upscale.hpp"
#include "util/error.hpp"
#include "util/size_limits.hpp"

#include <algorithm>
#include <string>

namespace ddt {
namespace {

// A band's output rows to the receiver: whole, or in parts of
// options.output_band_rows rows where that is set.
void hand_out(Image rows, int first_row, const UpscaleOptions& options) {
  const int step = options.output_band_rows;
  if (step <= 0 || rows.height <= step) return options.output_rows(std::move(rows), first_row);
  const std::size_t row_floats = static_cast<std::size_t>(rows.width) * rows.channels;
  for (int first = 0; first < rows.height; first += step) {
    Image part(rows.width, std::min(step, rows.height - first), rows.channels);
    std::copy_n(rows.pixels.begin() + static_cast<std::ptrdiff_t>(row_floats * first), part.pixels.size(),
                part.pixels.begin());
    options.output_rows(std::move(part), first_row + first);
  }
}

}  // namespace

int band_margin(int width, int height, int out_width, int out_height, const UpscaleOptions& options) {
  return planned_band_margin(optimizer_region_rows(width, height, options),
                             is_consistent(width, height, out_width, out_height, options.model), options.model, width,
                             height, out_width, out_height);
}

// Measured at x2 and x4 on RGB (docs/performance.md): per input pixel of
// the band and its margins the mesh, the optimizer's arrays and the
// reconstruction's vectors (about 140 + 20 C bytes, writing EXR) and the float output
// drawn for it; per input pixel of the band's own rows that output again,
// queued for the encoder.
double banded_bytes(int width, int height, int channels, int out_width, int out_height, double rows, double margin) {
  const double output_per_pixel =
      4.0 * channels * (static_cast<double>(out_width) / width) * (static_cast<double>(out_height) / height);
  return width * ((140.0 + 20.0 * channels + output_per_pixel) * std::min<double>(height, rows + 2 * margin) +
                  output_per_pixel * rows);
}

int banded_rows(int width, int height, int channels, int out_width, int out_height, const UpscaleOptions& options,
                double budget_bytes) {
  const int margin = band_margin(width, height, out_width, out_height, options);
  // banded_bytes is linear in the rows: solve it for the budget.
  const double fixed = banded_bytes(width, height, channels, out_width, out_height, 0, margin);
  const double per_row = banded_bytes(width, height, channels, out_width, out_height, 1, margin) - fixed;
  const double rows = (budget_bytes - fixed) / per_row;
  return std::clamp(static_cast<int>(std::min<double>(rows, height)), min_band_rows, std::max(min_band_rows, height));
}

UpscaleStats upscale_banded(const RowSource& source, int out_width, int out_height, const UpscaleOptions& options,
                            int band_rows) {
  const int W = source.width, H = source.height, C = source.channels;
  if (W < 1 || H < 1 || C < 1) throw Error("the input image is empty");
  if (!options.output_rows) throw Error("upscale_banded: no receiver of the output rows");
  const int region_rows = optimizer_region_rows(W, H, options);
  if (options.optimizer != Optimizer::lawson || region_rows <= 0)
    throw Error("an image read by bands needs Lawson's region schedule (--optimizer lawson; --region-rows on a "
                "small image)");
  const bool consistent = is_consistent(W, H, out_width, out_height, options.model);
  Progress* progress = options.progress;

  // Each band runs without the caller's progress: the bar counts rows done.
  UpscaleOptions band_options = options;
  band_options.progress = nullptr;
  band_options.output_rows = nullptr;  // each band's rows come back whole, and are handed out here
  band_options.tile_rows = -1;
  band_rows = std::clamp(band_rows, 1, H);
  int margin = band_margin(W, H, out_width, out_height, options);
  check_memory_fits("a band of " + std::to_string(band_rows) + " rows with " + std::to_string(margin) +
                        " rows of margin each side",
                    banded_bytes(W, H, C, out_width, out_height, band_rows, margin));
  const InputStatistics statistics = consistent ? input_statistics(source, progress) : InputStatistics{};
  if (progress) progress->begin("bands", H);
  UpscaleStats total;
  const std::size_t row_floats = static_cast<std::size_t>(W) * C;
  // The rows held: [held_top, held_top + held.height).
  Image held(W, 0, C);
  int held_top = 0;
  const int bands = (H + band_rows - 1) / band_rows;
  for (int i = 0; i < bands; ++i) {
    const int first = i * band_rows, end = std::min(H, first + band_rows);
    for (;;) {
      const int top = std::max(0, first - margin), bottom = std::min(H, end + margin);
      // Keep the rows still needed, read the others.
      Image rows(W, bottom - top, C);
      const int keep_top = std::max(top, held_top), keep_end = std::min(bottom, held_top + held.height);
      if (keep_top < keep_end)
        std::copy(held.pixels.begin() + static_cast<std::ptrdiff_t>(row_floats * (keep_top - held_top)),
                  held.pixels.begin() + static_cast<std::ptrdiff_t>(row_floats * (keep_end - held_top)),
                  rows.pixels.begin() + static_cast<std::ptrdiff_t>(row_floats * (keep_top - top)));
      if (keep_top >= keep_end) {
        source.read(top, bottom, rows.pixels.data());
      } else {
        if (top < keep_top) source.read(top, keep_top, rows.pixels.data());
        if (keep_end < bottom)
          source.read(keep_end, bottom, rows.pixels.data() + row_floats * (keep_end - top));
      }
      held = std::move(rows);
      held_top = top;
      if (options.log)
        options.log("band " + std::to_string(i + 1) + "/" + std::to_string(bands) + ": rows " + std::to_string(first) +
                    ".." + std::to_string(end) + " with " + std::to_string(margin) + " rows of margin");
      UpscaleStats part;
      int needed = 0;
      Image out = upscale_rows(held, top, H, first, end, out_width, out_height, band_options, &part,
                               consistent ? &statistics : nullptr, &needed);
      if (out.empty()) {  // too narrow a margin for this band's mesh
        margin = widened_band_margin(margin, needed, region_rows);
        if (options.log) options.log("band " + std::to_string(i + 1) + ": margin too narrow, again with " +
                                     std::to_string(margin) + " rows");
        continue;
      }
      hand_out(std::move(out), output_row_of(first, H, out_height), options);
      add_band_stats(total, part, i == 0);
      break;
    }
    if (progress) progress->set(end);
  }
  total.tiles = bands;
  total.tile_margin = margin;
  return total;
}

}  // namespace ddt
