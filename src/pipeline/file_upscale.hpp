#pragma once
// ddt::upscale_file — one image file enlarged into another, the job of the
// command line's `ddtscale IN OUT` and of the Python module's upscale_file.
//
// The job is sized from the file's header before a pixel is decoded: the
// output size, what the output's format can store, the memory it takes.
// Then either the input is read whole and the output written by bands of
// rows as they are made (io/band_writer.hpp: encoding overlaps the work),
// or, when the whole job does not fit in memory or options.tile_rows > 0,
// the input is read, enlarged and written by bands
// (pipeline/banded_upscale.hpp). Both write the same bits; the output
// appears atomically, or not at all.
//
// Errors: ddt::FileError when a file cannot be read or written (a missing
// or unreadable input, an output that is the input or cannot be created),
// ddt::Error for the rest (options, sizes, formats, memory).

#include "ddtscale/ddtscale.hpp"
#include "io/encode_options.hpp"
#include "pipeline/output_size.hpp"

#include <functional>
#include <string>

namespace ddt {

struct FileUpscaleJob {
  std::string input, output;
  SizeRequest size;
  // The enlargement's options; output_rows and alpha_channel are the job's.
  UpscaleOptions options;
  EncodeOptions encode;             // compression, quality, half floats, tiles
  bool stream = true;               // false: the whole output, then one write (--no-stream)
  long long max_input_pixels = 0;   // > 0: refuse larger inputs (0: the reader's default)
  std::function<void(const std::string&)> warn;  // one-line warnings (extra pages); may be empty
};

struct FileUpscaleResult {
  int width = 0, height = 0;        // the output's
  int bands = 0;                    // > 0: read and written by that many bands
  UpscaleStats stats;
};

FileUpscaleResult upscale_file(FileUpscaleJob job);

// The bytes an enlargement of a width x height x channels image to
// out_width x out_height holds at its peak (an estimate that errs high):
// input and output floats (output_images whole outputs; a few bands of it
// when streamed under the point model) and the mesh, bounded by tiles.
double upscale_job_bytes(int width, int height, int channels, int out_width, int out_height,
                         const UpscaleOptions& options, bool streamed, int output_images = 1);

// The one-line warning for an input of several pages or parts (only the
// first is enlarged); empty for one.
std::string pages_warning(const std::string& input, int pages);

// Whether the job may run by bands of rows (upscale_banded's requirements).
bool can_upscale_by_bands(int width, int height, const UpscaleOptions& options);

}  // namespace ddt
