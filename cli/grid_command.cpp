// `ddtscale grid` — scattered points (x, y, values) to a regular north-up
// grid by data-dependent triangulation; see src/scattered/gridding.hpp for the grid
// convention and src/scattered/point_table.hpp for the input formats.

#include "command_line.hpp"
#include "commands.hpp"
#include "whole_number.hpp"

#include "core/costs.hpp"
#include "util/error.hpp"
#include "scattered/gridding.hpp"
#include "io/image_io.hpp"
#include "scattered/point_table.hpp"
#include "util/size_limits.hpp"
#include "pipeline/upscale.hpp"
#include "util/text.hpp"
#include "util/timing.hpp"

#include <CLI/CLI.hpp>

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>

namespace {

using ddt::lower;
using ddt::seconds_since;

// Messages from libraries may span lines; the command promises one line on stderr.
// A number, or nan (for no-data values); throws ddt::Error naming the option.
double parse_double(const std::string& text, const std::string& option, bool allow_nan) {
  std::string s = text;
  if (!s.empty() && s.front() == '+') s.erase(0, 1);
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size() || std::isinf(v) || (std::isnan(v) && !allow_nan))
    throw ddt::Error(option + ": '" + text + "' is not a " + (allow_nan ? "number or nan" : "finite number"));
  return v;
}

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> parts;
  std::stringstream in(s);
  std::string part;
  while (std::getline(in, part, ',')) parts.push_back(part);
  if (!s.empty() && s.back() == ',') parts.push_back("");
  return parts;
}

void parse_size(const std::string& text, int& w, int& h) {
  const auto x = lower(text).find('x');
  auto to_int = [&](const std::string& s) {
    int v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || end != s.data() + s.size() || v < 1)
      throw ddt::Error("--size: '" + text + "' is not WIDTHxHEIGHT with positive integers (e.g. 512x512)");
    return v;
  };
  if (x == std::string::npos) {
    w = h = to_int(text);
  } else {
    w = to_int(text.substr(0, x));
    h = to_int(text.substr(x + 1));
  }
}

ddt::GridBounds parse_bounds(const std::string& text) {
  const auto parts = split_commas(text);
  if (parts.size() != 4) throw ddt::Error("--bounds: give xmin,ymin,xmax,ymax (four numbers), not '" + text + "'");
  ddt::GridBounds b;
  b.xmin = parse_double(parts[0], "--bounds", false);
  b.ymin = parse_double(parts[1], "--bounds", false);
  b.xmax = parse_double(parts[2], "--bounds", false);
  b.ymax = parse_double(parts[3], "--bounds", false);
  if (!(b.xmin < b.xmax) || !(b.ymin < b.ymax)) throw ddt::Error("--bounds: need xmin < xmax and ymin < ymax");
  return b;
}

// sum, luma, a 1-based value channel number, or a value column's name.
int parse_cost_channel(const std::string& text, const ddt::PointTable& table) {
  const std::string t = lower(text);
  if (t == "sum") return ddt::cost_channel_sum;
  if (t == "luma") return ddt::cost_channel_luma;
  int n = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), n);
  if (!t.empty() && ec == std::errc() && end == t.data() + t.size()) {
    if (n < 1 || n > table.channels)
      throw ddt::Error("--cost-channel " + text + ": the points have value channels 1.." +
                       std::to_string(table.channels));
    return n - 1;
  }
  for (int k = 0; k < table.channels; ++k)
    if (lower(table.channel_names[k]) == t) return k;
  throw ddt::Error("--cost-channel: '" + text + "' is not sum, luma, a channel number or a value column name");
}

std::string format_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

}  // namespace

int run_grid_command(int argc, char** argv) {
  CLI::App app{
      "Grid scattered points by data-dependent triangulation: Delaunay triangulation of the points, edge\n"
      "flips that lower a cost so that long thin triangles follow steps and ridges, then the piecewise-\n"
      "linear surface sampled on a regular north-up grid. Pixels outside the points' convex hull are no-data."};
  app.name("ddtscale grid");
  std::string input, output, size_text, bounds_text, columns_text, input_nodata_text, nodata_text;
  std::string cost = ddt::GridOptions{}.cost, cost_channel = "sum";
  bool no_optimize = false, verbose = false, quiet = false;
  std::string optimizer = ddt::to_string(ddt::GridOptions{}.optimizer);
  ddt::AnnealOptions anneal;
  double tolerance = ddt::GridOptions{}.relative_tolerance;
  long long max_pixels = ddt::default_max_pixels;
  ddt::PointReadOptions read_options;
  read_options.float_values = true;

  app.add_option("input", input,
                 "points: one per line, x,y,value[,value...] or x y value (CSV with ',' or ';', or blank-separated\n"
                 "ASCII XYZ); an optional header line; '#' comments")
      ->required();
  app.add_option("output", output,
                 "grid image: .exr (float, no-data NaN), .tif (float + alpha), .png (16-bit + alpha, values\n"
                 "clamped to 0..1)")
      ->required();
  app.add_option("--size", size_text, "grid size WIDTHxHEIGHT in pixels (e.g. 512x512; one number: square)")
      ->required();
  app.add_option("--bounds", bounds_text,
                 "xmin,ymin,xmax,ymax: the grid's outer edges (default: the points' bounding box)");
  app.add_option("--columns", columns_text,
                 "x,y,value[,value...]: the columns to use, by header name or 1-based number (default: x, y\n"
                 "are columns 1, 2 and every further column is a value)");
  app.add_option("--input-nodata", input_nodata_text,
                 "drop input points with this value in any value column (a number, or nan)");
  app.add_option("--nodata", nodata_text,
                 "value for pixels outside the hull, in every format, instead of NaN (EXR) or 0 with alpha 0\n"
                 "(TIFF, PNG); no alpha channel is added then");
  app.add_option("--cost", cost, "flip cost: " + ddt::cost_names_joined())->capture_default_str();
  app.add_option("--cost-channel", cost_channel,
                 "what drives the flips: sum (of the per-channel costs), luma (of value channels 1-3), or one\n"
                 "value channel by number (1 = first value column) or header name")
      ->capture_default_str();
  app.add_flag("--no-optimize", no_optimize, "skip the flips: plain Delaunay linear interpolation");
  app.add_option("--tolerance", tolerance, "a flip must lower the local cost by more than this fraction")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--max-pixels", max_pixels, "refuse grids with more pixels than this")
      ->check(whole_number(1))
      ->capture_default_str();
  app.add_option("--max-input-points", read_options.max_points,
                 "refuse inputs with more points than this (default: the physical memory / 1024)")
      ->check(whole_number(1))
      ->capture_default_str();
  add_optimizer_options(app, optimizer, anneal);
  app.add_flag("-v,--verbose", verbose, "report points, flips, cost and the time of each stage");
  app.add_flag("-q,--quiet", quiet, "print nothing but errors");
  app.footer(
      "\nGrid convention (north-up, as gdal_grid): pixel (i, j), column i and row j, holds the value at\n"
      "  x = xmin + (i + 0.5) (xmax - xmin) / W,   y = ymax - (j + 0.5) (ymax - ymin) / H.\n"
      "Points at the same position are merged: one point with the mean of their values.\n"
      "Example: ddtscale grid points.csv dem.exr --size 512x512 --bounds 0,0,1000,1000");

  if (const auto status = parse_command_line(app, argc, argv, "ddtscale grid", "ddtscale grid --help"))
    return *status;

  try {
    auto log = [&](const std::string& line) {
      if (verbose) std::cerr << line << "\n";
    };
    ddt::GridOptions options;
    parse_size(size_text, options.width, options.height);
    ddt::check_size_limit("grid", std::to_string(options.width) + "x" + std::to_string(options.height),
                          ddt::checked_product({options.width, options.height}), max_pixels, "--max-pixels");
    if (!bounds_text.empty()) options.bounds = parse_bounds(bounds_text);
    ddt::find_cost(cost);  // fail fast on a typo

    const std::string ext = lower(std::filesystem::path(output).extension().string());
    const bool exr = ext == ".exr", tiff = ext == ".tif" || ext == ".tiff", png = ext == ".png";
    if (!exr && !tiff && !png)
      throw ddt::Error("output '" + output + "': the grid is written as .exr, .tif/.tiff or .png");
    ddt::check_output_path(output, input);

    if (!columns_text.empty()) read_options.columns = split_commas(columns_text);
    if (!input_nodata_text.empty()) read_options.input_nodata = parse_double(input_nodata_text, "--input-nodata", true);
    if (!nodata_text.empty()) options.nodata = static_cast<float>(parse_double(nodata_text, "--nodata", true));
    options.alpha = !exr && nodata_text.empty();
    if (!exr && nodata_text.empty()) options.nodata = 0.0f;

    auto t0 = std::chrono::steady_clock::now();
    ddt::PointTable table = ddt::read_point_table(input, read_options);
    const ddt::MergeStats merged = ddt::merge_duplicate_points(table);
    const int C = table.channels;
    // The rendered surface and the grid written (with its alpha channel),
    // as floats, and the mesh (about 200 bytes a point).
    ddt::check_memory_fits("this grid", 4.0 * (2 * C + 1) * options.width * options.height +
                                            200.0 * double(table.points.size()));
    if (png && C != 1 && C != 3)  // grey or RGB, then alpha: other counts would read as alpha or fail
      throw ddt::Error("a PNG holds 1 or 3 value channels; the points have " + std::to_string(C) +
                       ": write .tif or .exr");
    options.cost = cost;
    options.cost_channel = parse_cost_channel(cost_channel, table);
    options.optimize = !no_optimize;
    options.relative_tolerance = tolerance;
    options.optimizer = ddt::optimizer_by_name(optimizer);
    options.anneal = anneal;
    if (verbose) options.log = log;
    {
      std::string line = "read: " + input + ", " + std::to_string(table.lines_read) + " lines, " +
                         std::to_string(table.points.size()) + " distinct points, " +
                         std::to_string(C) + " value channel" + (C == 1 ? "" : "s") + " (";
      for (int k = 0; k < C; ++k) line += (k ? ", " : "") + table.channel_names[k];
      line += "), " + std::to_string(seconds_since(t0)) + " s";
      log(line);
    }

    const std::vector<float> values(table.values.begin(), table.values.end());  // in range: float_values
    ddt::GridStats stats;
    const ddt::Image grid = ddt::grid_points(table.points, values, C, options, &stats);

    long long clamped = 0;
    if (png)
      for (std::size_t i = 0; i < grid.pixel_count(); ++i)
        for (int c = 0; c < C; ++c) {
          const float v = grid.pixels[i * grid.channels + c];
          if (v < 0.0f || v > 1.0f) ++clamped;
        }

    t0 = std::chrono::steady_clock::now();
    ddt::write_image(output, grid, png ? ddt::SampleFormat::uint16 : ddt::SampleFormat::float32,
                     options.alpha ? C : -1);
    log("write: " + output + ", " + std::to_string(seconds_since(t0)) + " s");
    if (!quiet) {
      const ddt::GridBounds& b = stats.bounds;
      std::string line = output + ": " + std::to_string(options.width) + "x" + std::to_string(options.height) +
                         " over x " + format_number(b.xmin) + ".." + format_number(b.xmax) + ", y " +
                         format_number(b.ymin) + ".." + format_number(b.ymax) + "; " +
                         std::to_string(stats.points) + " points";
      if (merged.removed > 0)
        line += " (" + std::to_string(merged.removed) + " duplicate" + (merged.removed == 1 ? "" : "s") +
                " merged into " + std::to_string(merged.positions) + " position" + (merged.positions == 1 ? "" : "s") +
                ", values averaged)";
      if (table.dropped_nodata > 0) line += ", " + std::to_string(table.dropped_nodata) + " no-data points dropped";
      line += "; " + std::to_string(stats.nodata_pixels) + " no-data pixels";
      std::cerr << line << "\n";
      if (clamped > 0)
        std::cerr << "note: " << clamped << " values outside 0..1 were clamped in the PNG; .tif and .exr keep them\n";
    }
    return 0;
  } catch (const ddt::Error& e) {
    std::cerr << "ddtscale grid: " << one_line(e.what()) << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "ddtscale grid: out of memory (try a smaller grid)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "ddtscale grid: " << one_line(e.what()) << "\n";
    return 1;
  }
}
