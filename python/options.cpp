#include "options.hpp"

#include "consistency/acquisition_model.hpp"
#include "core/costs.hpp"
#include "image/cubic_surface.hpp"
#include "util/error.hpp"
#include "util/size_limits.hpp"
#include "image/optimizer_choice.hpp"

#include <pybind11/stl.h>

#include <algorithm>
#include <type_traits>

namespace ddtpy {
namespace {

// Reads one keyword: `get(name, field)` converts it when given.
class Keywords {
 public:
  Keywords(const py::dict& kwargs, const py::dict& defaults) : kwargs_(kwargs) {
    for (const auto& item : kwargs) {
      const std::string name = py::str(item.first);
      if (!defaults.contains(name)) {
        std::string names;
        for (const auto& d : defaults) names += (names.empty() ? "" : ", ") + std::string(py::str(d.first));
        throw ddt::Error("unknown option '" + name + "' (options: " + names + ")");
      }
    }
  }
  template <class T>
  bool get(const char* name, T& field) const {
    if (!kwargs_.contains(name)) return false;
    const py::handle value = kwargs_[name];
    if (value.is_none()) return false;
    try {
      field = value.cast<T>();
    } catch (const py::cast_error&) {
      throw py::type_error(std::string(name) + ": expected " + type_name<T>() + ", got " +
                           std::string(py::str(py::type::of(value).attr("__name__"))));
    }
    return true;
  }

 private:
  template <class T>
  static const char* type_name() {
    if constexpr (std::is_same_v<T, bool>) return "a bool";
    else if constexpr (std::is_integral_v<T>) return "an int";
    else if constexpr (std::is_floating_point_v<T>) return "a number";
    else return "a str";
  }
  const py::dict& kwargs_;
};

void check_unit_range(double value, const char* option) {
  if (!(value >= 0.0 && value <= 1.0)) throw ddt::Error(std::string(option) + " must be a number in [0, 1]");
}

// What volumes and sequences share: the cost, the render, the slopes and
// the tolerance of the tetrahedral reconstruction.
void get_mesh_options(const Keywords& k, ddt::VolumeUpscaleOptions& o) {
  k.get("cost", o.cost);
  ddt::find_cost(o.cost);
  std::string name;
  if (k.get("render", name)) o.render = ddt::render_by_name(name);
  if (k.get("slopes", name)) o.slopes = ddt::slope_limiter_by_name(name);
  k.get("tolerance", o.relative_tolerance);
  check_unit_range(o.relative_tolerance, "--tolerance");
}

void check_threads(int threads) {
  if (threads < 0 || threads > 4096) throw ddt::Error("--threads must be in [0, 4096]");
}

// --optimizer, --seed and the --anneal-* schedule (cli/optimizer_options.cpp).
void read_optimizer(const Keywords& k, ddt::Optimizer& optimizer, ddt::AnnealOptions& anneal) {
  std::string name = ddt::to_string(optimizer);
  if (k.get("optimizer", name)) optimizer = ddt::optimizer_by_name(name);
  k.get("seed", anneal.seed);
  k.get("anneal_t0", anneal.initial_temperature);
  k.get("anneal_accept", anneal.initial_acceptance);
  k.get("anneal_cooling", anneal.cooling);
  k.get("anneal_steps", anneal.temperature_steps);
  k.get("anneal_moves", anneal.moves_per_edge);
  ddt::check_optimizer(optimizer, anneal);
}

void add_optimizer_defaults(py::dict& d, ddt::Optimizer optimizer, const ddt::AnnealOptions& anneal) {
  d["optimizer"] = ddt::to_string(optimizer);
  d["seed"] = anneal.seed;
  d["anneal_t0"] = anneal.initial_temperature;
  d["anneal_accept"] = anneal.initial_acceptance;
  d["anneal_cooling"] = anneal.cooling;
  d["anneal_steps"] = anneal.temperature_steps;
  d["anneal_moves"] = anneal.moves_per_edge;
}

}  // namespace

py::dict image_defaults() {
  const ImageCall c;
  py::dict d;
  d["width"] = py::none();
  d["height"] = py::none();
  d["cost"] = c.options.cost;
  d["cost_channel"] = c.options.luma_cost ? "luma" : "sum";
  d["render"] = ddt::to_string(c.options.render);
  d["slopes"] = ddt::to_string(c.options.slopes);
  d["model"] = ddt::to_string(c.options.model);
  d["no_step_edges"] = !c.options.step_edges;
  d["no_optimize"] = !c.options.optimize;
  d["tolerance"] = c.options.relative_tolerance;
  d["max_pixels"] = c.max_pixels;
  d["compare"] = py::none();
  d["mesh"] = py::none();
  d["mesh_roi"] = py::none();
  add_optimizer_defaults(d, c.options.optimizer, c.options.anneal);
  d["verbose"] = c.verbose;
  d["quiet"] = c.quiet;
  d["threads"] = c.threads;
  d["tile_rows"] = c.options.tile_rows;
  d["mesh_band_rows"] = c.options.mesh_band_rows;
  d["max_memory"] = py::none();  // bytes (int) or a size ("2G"); None: automatic
  // The library's, beyond the command line: an array has no alpha flag.
  d["alpha_channel"] = c.options.alpha_channel;
  d["region_rows"] = c.options.region_rows;
  return d;
}

ImageCall image_call(const py::dict& kwargs) {
  const Keywords k(kwargs, image_defaults());
  ImageCall c;
  ddt::UpscaleOptions& o = c.options;
  k.get("cost", o.cost);
  ddt::find_cost(o.cost);
  k.get("cost_channel", c.cost_channel);
  if (c.cost_channel != "sum" && c.cost_channel != "luma")
    throw ddt::Error("--cost-channel must be sum or luma, not '" + c.cost_channel + "'");
  o.luma_cost = c.cost_channel == "luma";
  std::string name;
  if (k.get("render", name)) o.render = ddt::render_by_name(name);
  if (k.get("slopes", name)) o.slopes = ddt::slope_limiter_by_name(name);
  c.model = ddt::to_string(o.model);
  k.get("model", c.model);
  o.model = ddt::parse_acquisition_model(c.model);
  bool no_step_edges = !o.step_edges;
  k.get("no_step_edges", no_step_edges);
  o.step_edges = !no_step_edges;
  bool no_optimize = !o.optimize;
  k.get("no_optimize", no_optimize);
  o.optimize = !no_optimize;
  k.get("tolerance", o.relative_tolerance);
  check_unit_range(o.relative_tolerance, "--tolerance");
  k.get("max_pixels", c.max_pixels);
  if (c.max_pixels <= 0) throw ddt::Error("--max-pixels must be positive");
  std::string text;
  if (k.get("compare", text)) c.compare = text;
  if (k.get("mesh", text)) c.mesh = text;
  if (k.get("mesh_roi", text)) c.mesh_roi = text;
  read_optimizer(k, o.optimizer, o.anneal);
  k.get("verbose", c.verbose);
  k.get("quiet", c.quiet);
  k.get("threads", c.threads);
  check_threads(c.threads);
  k.get("tile_rows", o.tile_rows);
  k.get("mesh_band_rows", o.mesh_band_rows);
  if (kwargs.contains("max_memory") && !kwargs["max_memory"].is_none()) {
    const py::handle size = kwargs["max_memory"];
    if (py::isinstance<py::str>(size)) {
      o.max_memory = ddt::parse_memory_size(size.cast<std::string>());
    } else {
      k.get("max_memory", o.max_memory);
      if (o.max_memory <= 0) throw ddt::Error("--max-memory must be positive");
    }
  }
  k.get("alpha_channel", o.alpha_channel);
  k.get("region_rows", o.region_rows);
  return c;
}

py::dict volume_defaults() {
  const VolumeCall c;
  py::dict d;
  d["method"] = ddt::to_string(c.options.method);
  d["cost"] = c.options.cost;
  d["render"] = ddt::to_string(c.options.render);
  d["slopes"] = ddt::to_string(c.options.slopes);
  d["tolerance"] = c.options.relative_tolerance;
  d["presmooth"] = py::none();
  d["time_scale"] = py::none();
  d["node_centred_time"] = true;
  d["max_voxels"] = c.max_voxels;
  d["verbose"] = c.verbose;
  d["threads"] = c.threads;
  return d;
}

py::dict file_defaults() {
  py::dict d = image_defaults();
  for (const char* name : {"compare", "mesh", "mesh_roi"}) d.attr("pop")(name);
  const FileCall c;
  d["compression"] = py::none();  // the format's default (--help)
  d["quality"] = py::none();
  d["half"] = c.encode.half;
  d["float"] = c.encode.full_float;
  d["tile_size"] = py::none();
  d["no_stream"] = c.no_stream;
  d["max_input_pixels"] = c.max_input_pixels;
  return d;
}

FileCall file_call(const py::dict& kwargs) {
  const Keywords k(kwargs, file_defaults());  // names checked against all of upscale_file's
  py::dict image;
  const py::dict image_names = image_defaults();
  for (const auto& item : kwargs)
    if (image_names.contains(item.first)) image[item.first] = item.second;
  FileCall c;
  c.image = image_call(image);
  k.get("compression", c.encode.compression);
  // 0 means the format's default in EncodeOptions; given, it is a bad value (the rest is checked by the library).
  if (k.get("quality", c.encode.quality) && c.encode.quality < 1)
    throw ddt::Error("--quality must be a whole number from 1 to 100");
  k.get("half", c.encode.half);
  k.get("float", c.encode.full_float);
  if (k.get("tile_size", c.encode.tile) && c.encode.tile < 16)
    throw ddt::Error("--tile-size must be a multiple of 16 from 16 to 65536");
  k.get("no_stream", c.no_stream);
  k.get("max_input_pixels", c.max_input_pixels);
  if (c.max_input_pixels <= 0) throw ddt::Error("--max-input-pixels must be positive");
  return c;
}

VolumeCall volume_call(const py::dict& kwargs) {
  const Keywords k(kwargs, volume_defaults());
  VolumeCall c;
  std::string method = ddt::to_string(c.options.method);
  k.get("method", method);
  try {  // the 3D ones and the series' (checked on the array)
    c.options.method = ddt::volume_method_by_name(method);
  } catch (const ddt::Error&) {
    throw ddt::Error("--method must be one of ddt, delaunay, trilinear, tricubic (series: quadrilinear, "
                     "tricubic-linear), not '" + method + "'");
  }
  c.options.node_centred = {false, false, false, true};
  bool node_time = true;
  k.get("node_centred_time", node_time);
  c.options.node_centred[3] = node_time;
  double time_scale = 0;
  if (k.get("time_scale", time_scale)) {
    if (!(time_scale > 0) || !std::isfinite(time_scale)) throw ddt::Error("--time-scale must be a positive number");
    c.time_scale = time_scale;
  }
  get_mesh_options(k, c.options);
  if (k.get("presmooth", c.presmooth) && !(c.presmooth >= 0 && c.presmooth <= 16))
    throw ddt::Error("--presmooth must be a sigma in [0, 16] voxels");
  k.get("max_voxels", c.max_voxels);
  if (c.max_voxels <= 0) throw ddt::Error("--max-voxels must be positive");
  k.get("verbose", c.verbose);
  k.get("threads", c.threads);
  check_threads(c.threads);
  return c;
}

py::dict sequence_defaults() {
  const SequenceCall c;
  py::dict d;
  d["method"] = ddt::to_string(c.options.volume.method);
  d["cost"] = c.options.volume.cost;
  d["render"] = ddt::to_string(c.options.volume.render);
  d["slopes"] = ddt::to_string(c.options.volume.slopes);
  d["presmooth"] = py::none();  // presmooth_along_motion where the mesh starts along a motion, else volume.presmooth
  d["tolerance"] = c.options.volume.relative_tolerance;
  d["flip_slow_texture"] = !c.options.volume.keep_slow_texture;
  d["motion"] = ddt::motion_text(c.options);
  d["time_tile"] = c.options.tile_frames;
  d["time_margin"] = c.options.margin_frames;
  d["exact_tiles"] = c.options.exact_tiles;
  d["max_pixels"] = c.max_pixels;
  d["verbose"] = c.verbose;
  d["threads"] = c.threads;
  return d;
}

SequenceCall sequence_call(const py::dict& kwargs) {
  const Keywords k(kwargs, sequence_defaults());
  SequenceCall c;
  ddt::VolumeUpscaleOptions& o = c.options.volume;
  std::string method = ddt::to_string(o.method);
  k.get("method", method);
  if (method != "ddt" && method != "delaunay") throw ddt::Error("--method must be one of ddt, delaunay, not '" + method + "'");
  o.method = ddt::volume_method_by_name(method);
  get_mesh_options(k, o);
  double sigma = o.presmooth[0];
  if (k.get("presmooth", sigma)) c.options.presmooth_along_motion = -1;  // given: whatever the mesh
  if (!(sigma >= 0 && sigma <= 16)) throw ddt::Error("--presmooth must be a sigma in [0, 16] pixels");
  o.presmooth = {sigma, sigma, 0.0};
  bool flip_slow_texture = !o.keep_slow_texture;
  k.get("flip_slow_texture", flip_slow_texture);
  o.keep_slow_texture = !flip_slow_texture;
  std::string motion = ddt::motion_text(c.options);
  k.get("motion", motion);
  ddt::set_motion(c.options, motion);
  k.get("time_tile", c.options.tile_frames);
  if (c.options.tile_frames < 0) throw ddt::Error("--time-tile must be at least 1 (0: automatic)");
  k.get("time_margin", c.options.margin_frames);
  if (c.options.margin_frames < 0 || c.options.margin_frames > 1000)
    throw ddt::Error("--time-margin must be between 0 and 1000 frames");
  k.get("exact_tiles", c.options.exact_tiles);
  k.get("max_pixels", c.max_pixels);
  if (c.max_pixels <= 0) throw ddt::Error("--max-pixels must be positive");
  k.get("verbose", c.verbose);
  k.get("threads", c.threads);
  check_threads(c.threads);
  return c;
}

py::dict grid_defaults() {
  const GridCall c;
  py::dict d;
  d["bounds"] = py::none();
  d["cost"] = c.options.cost;
  d["cost_channel"] = "sum";
  d["no_optimize"] = !c.options.optimize;
  add_optimizer_defaults(d, c.options.optimizer, c.options.anneal);
  d["tolerance"] = c.options.relative_tolerance;
  d["nodata"] = c.options.nodata;
  d["alpha"] = c.options.alpha;
  d["max_pixels"] = c.max_pixels;
  d["verbose"] = c.verbose;
  d["threads"] = c.threads;
  return d;
}

GridCall grid_call(const py::dict& kwargs, int channels) {
  const Keywords k(kwargs, grid_defaults());
  GridCall c;
  ddt::GridOptions& o = c.options;
  if (kwargs.contains("bounds") && !kwargs["bounds"].is_none()) {
    std::vector<double> b;
    k.get("bounds", b);
    if (b.size() != 4) throw ddt::Error("--bounds: give xmin,ymin,xmax,ymax (four numbers)");
    o.bounds = ddt::GridBounds{b[0], b[1], b[2], b[3]};
    if (!(b[0] < b[2]) || !(b[1] < b[3])) throw ddt::Error("--bounds: need xmin < xmax and ymin < ymax");
  }
  k.get("cost", o.cost);
  ddt::find_cost(o.cost);
  const py::object channel =
      kwargs.contains("cost_channel") ? py::reinterpret_borrow<py::object>(kwargs["cost_channel"]) : py::str("sum");
  if (py::isinstance<py::str>(channel)) {
    const std::string name = channel.cast<std::string>();
    if (name == "sum") o.cost_channel = ddt::cost_channel_sum;
    else if (name == "luma") o.cost_channel = ddt::cost_channel_luma;
    else throw ddt::Error("--cost-channel: '" + name + "' is not sum, luma or a channel number");
  } else {
    int index = 0;
    k.get("cost_channel", index);
    if (index < 0 || index >= channels)
      throw ddt::Error("--cost-channel " + std::to_string(index) + ": the points have value channels 0.." +
                       std::to_string(channels - 1));
    o.cost_channel = index;
  }
  bool no_optimize = !o.optimize;
  k.get("no_optimize", no_optimize);
  o.optimize = !no_optimize;
  read_optimizer(k, o.optimizer, o.anneal);
  k.get("tolerance", o.relative_tolerance);
  check_unit_range(o.relative_tolerance, "--tolerance");
  k.get("nodata", o.nodata);
  k.get("alpha", o.alpha);
  k.get("max_pixels", c.max_pixels);
  if (c.max_pixels <= 0) throw ddt::Error("--max-pixels must be positive");
  k.get("verbose", c.verbose);
  k.get("threads", c.threads);
  check_threads(c.threads);
  return c;
}

}  // namespace ddtpy
