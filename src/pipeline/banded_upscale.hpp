#pragma once
// ddt::upscale_banded — an image enlarged band by band from a source of
// rows, holding neither the whole input nor the whole output: what an
// image larger than memory takes.
//
// The source is read twice, top to bottom: once for the whole input's
// statistics (the consistent reconstruction's, input_statistics.hpp), then
// by bands of band_rows rows with margins, each enlarged by upscale_rows
// and its output rows handed to options.output_rows. A band whose margin
// proves too narrow is redone with the width it needed. The rows handed
// out are upscale()'s, bit for bit.
//
// Requires: options.output_rows set; Lawson's region schedule (options
// .optimizer lawson, and region_rows > 0 or an image large enough for
// automatic regions). Throws ddt::Error otherwise, and for the source's
// errors.

#include "ddtscale/ddtscale.hpp"
#include "util/image.hpp"
#include "util/input_rows.hpp"  // RowSource

#include <functional>

namespace ddt {

// The rows of margin a band needs each side (the optimizer's regions and
// the consistent reconstruction's reach).
int band_margin(int width, int height, int out_width, int out_height, const UpscaleOptions& options);
// The bytes a band of `rows` input rows with `margin` rows each side holds.
double banded_bytes(int width, int height, int channels, int out_width, int out_height, double rows, double margin);
// The fewest input rows banded_rows gives a band: its margins are a few
// hundred rows, so shorter bands would be mostly margin.
inline constexpr int min_band_rows = 256;
// The input rows per band that fit, with their margins, a memory budget of
// `budget_bytes` (at least min_band_rows).
int banded_rows(int width, int height, int channels, int out_width, int out_height, const UpscaleOptions& options,
                double budget_bytes);

UpscaleStats upscale_banded(const RowSource& source, int out_width, int out_height, const UpscaleOptions& options,
                            int band_rows);

}  // namespace ddt
