#include "pipeline/file_upscale.hpp"

#include "consistency/consistent_reconstruction.hpp"
#include "image/image_mesh.hpp"
#include "io/image_formats.hpp"
#include "pipeline/banded_upscale.hpp"
#include "pipeline/upscale.hpp"
#include "util/prefaulted_image.hpp"
#include "util/size_limits.hpp"
#include "util/timing.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>

namespace ddt {

namespace {

// Runs `io`, an I/O step, turning its errors into FileError.
template <class Step>
auto file_step(Step&& io) {
  try {
    return io();
  } catch (const FileError&) {
    throw;
  } catch (const NeedsOpenImageIO&) {
    throw;
  } catch (const Error& e) {
    throw FileError(e.what());
  }
}

void log_line(const UpscaleOptions& options, const std::string& line) {
  if (options.log) options.log(line);
}

// The writer the enlargement hands its bands of rows to (image_formats.hpp).
std::unique_ptr<OutputImage> stream_into(const FileUpscaleJob& job, const FileUpscaleResult& result,
                                         UpscaleOptions& options, InputImage& input) {
  auto writer = file_step([&] { return input.create_output(job.output, result.width, result.height, job.encode); });
  options.output_rows = [w = writer.get()](Image rows, int first_row) {
    file_step([&] { w->write(std::move(rows), first_row); });
  };
  return writer;
}

void warn_of_pages(const FileUpscaleJob& job, int pages) {
  if (pages > 1 && job.warn) job.warn(pages_warning(job.input, pages));
}

}  // namespace

std::string pages_warning(const std::string& input, int pages) {
  if (pages <= 1) return {};
  return "'" + input + "' holds " + (pages > 2 ? std::to_string(pages) : "2 or more") +
         " pages or parts; only the first is enlarged";
}

double upscale_job_bytes(int width, int height, int channels, int out_width, int out_height,
                         const UpscaleOptions& options, bool streamed, int output_images) {
  const double in_pixels = double(width) * height;
  // Streamed under the point model, a few bands of the output are held;
  // under the box model at integer scales, the wavefront's output rows of
  // a few hundred input rows (make_consistent_streamed).
  const bool bands = streamed && options.model.kind == AcquisitionModel::Kind::point;
  const bool wavefront = streamed && make_consistent_streams(options.model, width, height, out_width, out_height);
  const double held_rows = bands ? 2048.0 : wavefront ? 256.0 * out_height / height : double(out_height);
  const double out_pixels = std::min(double(out_width) * out_height, held_rows * out_width);
  const bool tiled = options.optimizer == Optimizer::lawson && options.tile_rows >= 0;
  const int mesh_bands =
      wavefront ? wavefront_mesh_band_rows(width, height, out_width, out_height, options) : 0;
  // Read by rows, the input held is a band's rows (in wavefront_mesh_bytes).
  const double held_input =
      streamed && upscale_reads_by_rows(width, height, channels, out_width, out_height, options) ? 0 : in_pixels;
  const double images = 4.0 * channels * (held_input + out_pixels * output_images);
  const double mesh = mesh_bands > 0 ? wavefront_mesh_bytes(width, height, channels, out_width, out_height,
                                                            mesh_bands, options)
                                     : 200.0 * in_pixels;
  return images + (tiled ? std::min(mesh, 0.5 * double(physical_memory())) : mesh);
}

namespace {

// Under --max-memory the bands are sized for this share of the limit: the
// band model is a fit, and the allocator's and the encoder's peaks vary
// (docs/performance.md).
constexpr double band_share = 0.85;

// The bytes bands may be sized for under --max-memory (> 0): the share of
// what the limit leaves beside the pages the process holds.
double limited_band_budget(long long max_memory, double resident) {
  return band_share * (double(max_memory) - resident);
}

std::string megabytes(double bytes) {
  return std::to_string(static_cast<long long>(std::ceil(bytes / 1048576.0))) + "M";
}

// Why a job is not read by bands (can_upscale_by_bands is false, or the
// output is not streamed).
std::string why_not_banded(const UpscaleOptions& options, bool streamed) {
  if (!streamed) return "--no-stream holds the whole output";
  if (options.optimizer != Optimizer::lawson) return "bands need --optimizer lawson";
  if (options.tile_rows < 0) return "--tile-rows -1";
  return "the image is a single region of the optimizer";
}

}  // namespace

bool can_upscale_by_bands(int width, int height, const UpscaleOptions& options) {
  return options.optimizer == Optimizer::lawson && options.tile_rows >= 0 &&
         optimizer_region_rows(width, height, options) > 0;
}

FileUpscaleResult upscale_file(FileUpscaleJob job) {
  file_step([&] { check_output_path(job.output, job.input); });
  const auto t0 = std::chrono::steady_clock::now();
  UpscaleOptions& options = job.options;
  if (options.progress) options.progress->begin("read");
  FileUpscaleResult result;
  bool banded = false;
  std::optional<Error> job_error;  // the header's refusals stay ddt::Error, not FileError
  ImageReadLimits limits;
  if (job.max_input_pixels > 0) limits.max_pixels = job.max_input_pixels;
  limits.check = [&](const ImageHeader& header) {
    try {
      output_size(job.size, header.width, header.height, result.width, result.height);
      check_output_image(job.output, result.width, result.height, header, job.encode);
      const double whole = upscale_job_bytes(header.width, header.height, header.channels, result.width,
                                             result.height, options, job.stream);
      const bool can_band = job.stream && can_upscale_by_bands(header.width, header.height, options);
      if (options.max_memory > 0) {
        const double resident = double(resident_memory());
        const double limit = limited_band_budget(options.max_memory, resident);
        double least = whole;  // the least the job can hold: whole, or in the smallest bands
        if (can_band) {
          const int margin = band_margin(header.width, header.height, result.width, result.height, options);
          least = std::min(least, banded_bytes(header.width, header.height, header.channels, result.width,
                                               result.height, std::min(header.height, min_band_rows), margin));
        }
        banded = can_band && (options.tile_rows > 0 || whole > std::min(limit, 0.9 * double(available_memory())));
        if (options.tile_rows <= 0 && least > limit) {
          const std::string needed = megabytes(least / band_share + resident);  // the limit whose budget holds it
          throw Error("this job needs about " + needed +
                      (can_band ? "" : " (it cannot run in bands: " + why_not_banded(options, job.stream) + ")") +
                      "; give --max-memory " + needed + " or more");
        }
      } else {
        banded = can_band && (options.tile_rows > 0 || whole > 0.9 * double(available_memory()));
      }
      if (!banded) check_memory_fits("this job", whole);
    } catch (const NeedsOpenImageIO&) {
      throw;
    } catch (const Error& e) {
      job_error = e;
      throw;
    }
  };
  auto read_step = [&](auto&& read) {
    try {
      return file_step(read);
    } catch (const NeedsOpenImageIO&) {
      throw;
    } catch (const Error&) {
      if (job_error) throw Error(job_error->what());
      throw;
    }
  };
  const std::unique_ptr<InputImage> input = read_step([&] { return open_input_image(job.input, limits); });
  const ImageHeader header = input->header();
  warn_of_pages(job, input->pages());
  options.alpha_channel = header.alpha_channel;
  const bool by_rows = !banded && job.stream &&
                       upscale_reads_by_rows(header.width, header.height, header.channels, result.width,
                                             result.height, options);
  const std::string size =
      std::to_string(header.width) + "x" + std::to_string(header.height) + "x" + std::to_string(header.channels);
  std::unique_ptr<OutputImage> writer;
  if (banded || by_rows) {
    writer = stream_into(job, result, options, *input);
    InputImage& rows = *input;
    const RowSource source{header.width, header.height, header.channels,
                           [&rows](int first, int end, float* p) { file_step([&] { rows.read(first, end, p); }); }};
    if (by_rows) {
      // One pass down the image, its input read a window of rows at a time.
      log_line(options, "read by rows: " + job.input + ", " + size);
      result.stats = upscale_by_rows(source, result.width, result.height, options);
    } else {
      const double budget = options.max_memory > 0
                                ? limited_band_budget(options.max_memory, double(resident_memory()))
                                : 0.5 * double(available_memory());
      const int band_rows = options.tile_rows > 0 ? options.tile_rows
                                                  : banded_rows(header.width, header.height, header.channels,
                                                                result.width, result.height, options, budget);
      log_line(options, "read by bands of " + std::to_string(band_rows) + " rows: " + job.input + ", " + size);
      result.stats = upscale_banded(source, result.width, result.height, options, band_rows);
      result.bands = result.stats.tiles;
      log_line(options, "bands: " + std::to_string(result.stats.tiles) + ", margin " +
                            std::to_string(result.stats.tile_margin) + " rows, " +
                            std::to_string(seconds_since(t0)) + " s");
    }
  } else {
    check_memory_fits("this job", upscale_job_bytes(header.width, header.height, header.channels, result.width,
                                                    result.height, options, job.stream));
    Image image = prefaulted_image(header.width, header.height, header.channels);
    read_step([&] {
      input->read(0, header.height, image.pixels.data());
      return 0;
    });
    log_line(options, "read: " + job.input + ", " + size + ", " + std::to_string(seconds_since(t0)) + " s");
    if (job.stream) writer = stream_into(job, result, options, *input);
    Image out = upscale(image, result.width, result.height, options, &result.stats);
    if (!writer) {
      if (options.progress) options.progress->begin("write");
      const auto t1 = std::chrono::steady_clock::now();
      file_step([&] {
        auto whole = input->create_output(job.output, result.width, result.height, job.encode);
        whole->write(std::move(out), 0);
        whole->finish();
        return 0;
      });
      log_line(options, "write: " + job.output + ", " + std::to_string(seconds_since(t1)) + " s");
      return result;
    }
  }
  if (options.progress) options.progress->begin("write");
  const auto t1 = std::chrono::steady_clock::now();
  file_step([&] { writer->finish(); });
  log_line(options, "write: " + job.output + ", " + std::to_string(seconds_since(t1)) + " s");
  return result;
}

}  // namespace ddt
