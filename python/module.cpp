// ddtscale._ddtscale — the compiled half of the Python module: numpy arrays
// in and out of the library's upscale, upscale_volume and grid_points. The
// Python package (python/ddtscale/__init__.py) wraps these with docstrings
// and keyword options; the options are parsed in python/options.cpp.
// The GIL is released while the library works; Ctrl-C stops the image
// calls (run_interruptibly).

#include "arrays.hpp"
#include "options.hpp"

#include "consistency/consistent_reconstruction.hpp"
#include "consistency/input_statistics.hpp"
#include "eval/classic_resize.hpp"
#include "eval/comparison.hpp"
#include "util/allocator_tuning.hpp"
#include "util/error.hpp"
#include "util/thread_limit.hpp"
#include "io/image_io.hpp"
#include "image/image_mesh.hpp"
#include "image/mesh_view.hpp"
#include "pipeline/file_upscale.hpp"
#include "pipeline/output_size.hpp"
#include "scattered/point_table.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <functional>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

namespace py = pybind11;
using namespace ddtpy;

namespace {

// Runs `work`, the library's computation reporting to `progress`, with the
// GIL released, in a way Ctrl-C stops: Python runs signal handlers only in
// the main thread and with the GIL, so the computation runs on a thread of
// its own while the calling thread checks for signals every 20 ms, taking
// the GIL back for each check. When a handler raises (SIGINT:
// KeyboardInterrupt), `progress` is cancelled, the computation stops at its
// next report (ddt::Cancelled, progress.hpp), and the handler's exception
// is raised here. Called with the GIL held; the exceptions of `work` are
// rethrown as they are.
void run_interruptibly(ddt::Progress& progress, const std::function<void()>& work) {
  std::exception_ptr failure;
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    std::mutex mutex;
    std::condition_variable finished;
    bool done = false;
    std::thread worker([&] {
      try {
        work();
      } catch (...) {
        failure = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(mutex);
      done = true;
      finished.notify_one();
    });
    std::unique_lock<std::mutex> lock(mutex);
    while (!finished.wait_for(lock, std::chrono::milliseconds(20), [&] { return done; })) {
      if (interrupted) continue;
      lock.unlock();
      {
        py::gil_scoped_acquire gil;
        interrupted = PyErr_CheckSignals() != 0;  // the handler's exception stays set
      }
      if (interrupted) progress.cancel();
      lock.lock();
    }
    lock.unlock();
    worker.join();
  }
  if (interrupted) throw py::error_already_set();
  if (failure) std::rethrow_exception(failure);
}

std::function<void(const std::string&)> stderr_log(bool verbose) {
  if (!verbose) return {};
  return [](const std::string& line) { std::cerr << line << "\n"; };
}

template <class T>
std::optional<T> optional_arg(const py::object& value, const char* name) {
  if (value.is_none()) return std::nullopt;
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    throw py::type_error(std::string(name) + ": expected a number (or numbers), got " +
                         std::string(py::str(py::type::of(value).attr("__name__"))));
  }
}

// A size: one integer for every axis, or a sequence of n (numpy integers too).
std::vector<int> size_values(const py::object& size, std::size_t n, const char* form) {
  if (!py::isinstance<py::sequence>(size) || py::isinstance<py::str>(size))
    return std::vector<int>(n, *optional_arg<int>(size, "size"));
  const auto values = optional_arg<std::vector<int>>(size, "size");
  if (values->size() != n) throw ddt::Error(form);
  return *values;
}

// size=(height, width) or an int for both; width=/height= as on the command line.
ddt::SizeRequest size_request(const py::object& scale, const py::object& size, const py::dict& kwargs,
                              long long max_pixels) {
  ddt::SizeRequest r;
  r.scale = optional_arg<double>(scale, "scale");
  r.max_pixels = max_pixels;
  if (!size.is_none()) {
    if (kwargs.contains("width") || kwargs.contains("height"))
      throw ddt::Error("give either size or width/height, not both");
    const std::vector<int> hw = size_values(size, 2, "size is (height, width) or one number for both");
    r.height = hw[0];
    r.width = hw[1];
  }
  if (kwargs.contains("width")) r.width = optional_arg<int>(kwargs["width"], "width");
  if (kwargs.contains("height")) r.height = optional_arg<int>(kwargs["height"], "height");
  return r;
}

// Writes the --mesh view of the call: OSError on any failure of the file.
void write_mesh(const ImageCall& call, const ddt::Image& image) {
  try {
    const std::string& path = *call.mesh;
    const bool svg = path.size() > 4 && path.substr(path.size() - 4) == ".svg";
    ddt::check_output_path(path, "", !svg);
    ddt::PixelRegion roi;
    const int w = image.width, h = image.height;
    if (call.mesh_roi) roi = ddt::parse_region(*call.mesh_roi);
    else if (w > 256 || h > 256) roi = {std::max(0, w / 2 - 64), std::max(0, h / 2 - 64), std::min(w, 128), std::min(h, 128)};
    ddt::check_region(roi, w, h);
    ddt::UpscaleOptions plain = call.options, options = call.options;
    plain.optimize = false;
    plain.log = options.log = nullptr;
    const ddt::Mesh2 initial = ddt::image_mesh(image, plain);
    const ddt::Mesh2 optimized = ddt::image_mesh(image, options);
    ddt::write_mesh_view(path, optimized, &initial, image, roi);
  } catch (const ddt::Error& e) {
    throw std::system_error(std::make_error_code(std::errc::io_error), e.what());
  }
}

py::array upscale(const py::array& array, const py::object& scale, const py::object& size, const py::dict& kwargs) {
  ImageCall call = image_call(kwargs);
  ImageArray in = image_from_array(array);
  const ddt::Image& image = in.image;
  if (call.options.alpha_channel >= image.channels)
    throw ddt::Error("alpha_channel " + std::to_string(call.options.alpha_channel) + " is not a channel of a " +
                     std::to_string(image.channels) + "-channel image");
  if (call.compare) {
    const auto methods = ddt::classic_methods();
    if (std::find(methods.begin(), methods.end(), *call.compare) == methods.end())
      throw ddt::Error("--compare: '" + *call.compare + "' is not a classic method");
  }
  int out_w = 0, out_h = 0;
  ddt::output_size(size_request(scale, size, kwargs, call.max_pixels), image.width, image.height, out_w, out_h);
  call.options.log = stderr_log(call.verbose);
  ddt::UpscaleStats stats;
  ddt::Image out;
  ddt::Progress progress;
  call.options.progress = &progress;
  run_interruptibly(progress, [&] {
    const auto limit = ddt::limit_threads(call.threads);
    out = ddt::upscale(image, out_w, out_h, call.options, &stats);
    if (call.compare) {
      const ddt::Image classic = ddt::classic_resize(image, out_w, out_h, *call.compare);
      out = ddt::side_by_side(classic, out, std::max(2, out_w / 256), 0.0f, call.options.alpha_channel);
    }
    if (call.mesh && !progress.cancelled()) write_mesh(call, image);
  });
  return array_from_image(out, in.dtype, in.planar);
}

py::tuple output_size(int in_width, int in_height, const py::object& scale, const py::object& size,
                      const py::dict& kwargs) {
  const ImageCall call = image_call(kwargs);
  int out_w = 0, out_h = 0;
  ddt::output_size(size_request(scale, size, kwargs, call.max_pixels), in_width, in_height, out_w, out_h);
  return py::make_tuple(out_h, out_w);
}

// The command line's job for one file (pipeline/file_upscale.hpp) without its
// extras (--compare, --mesh, the bar): the same bits, streamed or by bands;
// a file that cannot be read or written raises OSError.
py::tuple upscale_file(const std::string& input, const std::string& output, const py::object& scale,
                       const py::object& size, const py::dict& kwargs) {
  FileCall file = file_call(kwargs);
  ImageCall& call = file.image;
  const ddt::SizeRequest request = size_request(scale, size, kwargs, call.max_pixels);
  call.options.log = stderr_log(call.verbose);
  ddt::Progress progress;
  call.options.progress = &progress;
  ddt::FileUpscaleJob job{input,        output,         request, call.options, file.encode, !file.no_stream,
                          file.max_input_pixels, {}};
  if (!call.quiet) job.warn = [](const std::string& line) { std::cerr << "ddtscale: warning: " << line << "\n"; };
  ddt::FileUpscaleResult result;
  run_interruptibly(progress, [&] {
    const auto limit = ddt::limit_threads(call.threads);
    result = ddt::upscale_file(std::move(job));
  });
  return py::make_tuple(result.height, result.width);
}

ddt::InputStatistics statistics_from(const py::object& value) {
  const auto t = value.cast<std::tuple<std::vector<float>, std::vector<float>, double>>();
  ddt::InputStatistics s;
  s.min = std::get<0>(t), s.max = std::get<1>(t), s.quantum = std::get<2>(t);
  if (s.min.size() != s.max.size() || s.min.empty()) throw ddt::Error("statistics: min and max of the same channels");
  return s;
}

py::tuple input_statistics(const py::array& array) {
  const ddt::InputStatistics s = ddt::input_statistics(image_from_array(array).image);
  return py::make_tuple(s.min, s.max, s.quantum);
}

py::tuple merge_statistics(const py::object& a, const py::object& b) {
  const ddt::InputStatistics s = ddt::merge(statistics_from(a), statistics_from(b));
  return py::make_tuple(s.min, s.max, s.quantum);
}

int consistency_margin_needed(int triangle_rows, int width, int height, int out_width, int out_height,
                              const py::dict& kwargs) {
  const ImageCall call = image_call(kwargs);
  if (width < 1 || height < 1 || out_width < 1 || out_height < 1) throw ddt::Error("sizes must be at least 1");
  if (out_width < width || out_height < height) return 0;  // a reduction: the point model
  return ddt::consistency_margin_needed(triangle_rows, call.options.model, width, height, out_width, out_height);
}

py::array upscale_rows(const py::array& rows, int top, int image_height, int first, int end, int out_width,
                       int out_height, const py::dict& kwargs, const py::object& statistics) {
  ImageCall call = image_call(kwargs);
  ImageArray in = image_from_array(rows);
  std::optional<ddt::InputStatistics> whole;
  if (!statistics.is_none()) whole = statistics_from(statistics);
  call.options.log = stderr_log(call.verbose);
  ddt::Image out;
  ddt::Progress progress;
  call.options.progress = &progress;
  run_interruptibly(progress, [&] {
    const auto limit = ddt::limit_threads(call.threads);
    out = ddt::upscale_rows(in.image, top, image_height, first, end, out_width, out_height, call.options, nullptr,
                            whole ? &*whole : nullptr);
  });
  return array_from_image(out, in.dtype, in.planar);
}

int region_rows(int width, int height, const py::dict& kwargs) {
  return ddt::optimizer_region_rows(width, height, image_call(kwargs).options);
}

py::array upscale_volume(const py::array& array, const py::object& scale, const py::object& size,
                         const py::dict& kwargs) {
  VolumeCall call = volume_call(kwargs);
  VolumeArray in = volume_from_array(array);
  const ddt::Volume& v = in.volume;
  const bool series = v.nt > 1;
  std::array<int, 4> out{0, 0, 0, 1};  // x, y, z, t
  const auto factor = optional_arg<double>(scale, "scale");
  if (factor && !size.is_none()) throw ddt::Error("give either --scale or --size, not both");
  if (!factor && size.is_none() && !call.time_scale)
    throw ddt::Error("give the magnification: --scale S, or --size N or XxYxZ");
  if (call.time_scale && !series) throw ddt::Error("time_scale applies to series (T x Z x Y x X arrays)");
  if (factor && (!(*factor > 0) || !std::isfinite(*factor))) throw ddt::Error("--scale must be a positive number");
  // Space: scale (1 when only time_scale is given) or size; time: time_scale
  // (default: scale), or the size's T, else kept.
  const double space = factor ? *factor : 1.0;
  const double time = call.time_scale ? *call.time_scale : space;
  const int in_size[4] = {v.nx, v.ny, v.nz, v.nt};
  for (int a = 0; a < 4; ++a) {
    // Time as image sequences count and sample it (a fractional time_scale: the instants g / T).
    const double n = a < 3 ? ddt::enlarged_size(in_size[a], space, call.options.node_centred[a])
                           : ddt::scale_time_axis(in_size[a], time, call.options);
    if (n > 65536) throw ddt::Error("--scale gives an output larger than --max-voxels");
    out[a] = static_cast<int>(n);
  }
  if (!series) out[3] = 1;
  if (!size.is_none()) {
    const bool four = py::isinstance<py::sequence>(size) && !py::isinstance<py::str>(size) && py::len(size) == 4;
    if (four && !series) throw ddt::Error("size is (z, y, x) or one number for all three");
    if (four && call.time_scale) throw ddt::Error("give the steps either in size or by time_scale");
    const std::vector<int> sizes =
        size_values(size, four ? 4 : 3,
                    series ? "size is (t, z, y, x), (z, y, x) or one number for z, y and x"
                           : "size is (z, y, x) or one number for all three");
    const std::size_t k = sizes.size();
    out[0] = sizes[k - 1];
    out[1] = sizes[k - 2];
    out[2] = sizes[k - 3];
    if (four) out[3] = sizes[0];
  }
  for (int a = 0; a < 4; ++a)
    if (out[a] < 1 || out[a] > 65536) throw ddt::Error("--size wants sizes between 1 and 65536");
  const long long voxels = static_cast<long long>(out[0]) * out[1] * out[2] * out[3];
  if (voxels > call.max_voxels)
    throw ddt::Error("output " + std::to_string(out[0]) + "x" + std::to_string(out[1]) + "x" +
                     std::to_string(out[2]) + (series ? "x" + std::to_string(out[3]) : std::string()) +
                     " exceeds --max-voxels " + std::to_string(call.max_voxels));
  call.options.log = stderr_log(call.verbose);
  ddt::Volume result;
  {
    py::gil_scoped_release release;
    const auto limit = ddt::limit_threads(call.threads);
    call.options.presmooth = ddt::presmooth_in_space(series, call.presmooth);
    result = ddt::upscale_volume(v, out, call.options);
  }
  return array_from_volume(result, in.dtype);
}

py::list upscale_sequence(const py::array& frames, double time_scale, const py::object& scale, const py::object& size,
                          const py::dict& kwargs) {
  SequenceCall call = sequence_call(kwargs);
  if (frames.ndim() != 3 && frames.ndim() != 4)
    throw ddt::Error("frames is a T x H x W or T x H x W x C array, not one of " + std::to_string(frames.ndim()) +
                     " dimensions");
  if (frames.shape(0) < 1) throw ddt::Error("the sequence has no frames");
  if (!(time_scale > 0) || !(time_scale <= 1024)) throw ddt::Error("--time-scale must be a number in (0, 1024]");
  std::vector<ddt::Image> in;
  ImageArray first;
  for (py::ssize_t t = 0; t < frames.shape(0); ++t) {
    ImageArray a = image_from_array(frames[py::int_(t)]);
    if (t == 0) first.dtype = a.dtype, first.planar = a.planar;
    in.push_back(std::move(a.image));
  }
  const ddt::Image& f = in.front();
  const auto factor = optional_arg<double>(scale, "scale");
  if (factor && !size.is_none()) throw ddt::Error("give either --scale or --size, not both");
  int out_w = f.width, out_h = f.height;
  if (factor) {
    if (!(*factor > 0) || !std::isfinite(*factor) || f.width * *factor > 65536 || f.height * *factor > 65536)
      throw ddt::Error("--scale must be a positive number (outputs up to 65536 pixels a side)");
    out_w = static_cast<int>(std::max(1.0, std::round(f.width * *factor)));
    out_h = static_cast<int>(std::max(1.0, std::round(f.height * *factor)));
  } else if (!size.is_none()) {
    const std::vector<int> hw = size_values(size, 2, "size is (height, width) or one number for both");
    out_h = hw[0], out_w = hw[1];
    if (out_w < 1 || out_h < 1 || out_w > 65536 || out_h > 65536)
      throw ddt::Error("--size wants sizes between 1 and 65536");
  }
  const int frames_out = ddt::sequence_output_frames(static_cast<int>(in.size()), time_scale);
  if (static_cast<long long>(frames_out) * out_w * out_h > call.max_pixels)
    throw ddt::Error("output " + std::to_string(frames_out) + " frames of " + std::to_string(out_w) + "x" +
                     std::to_string(out_h) + " exceeds --max-pixels " + std::to_string(call.max_pixels));
  call.options.volume.log = stderr_log(call.verbose);
  std::vector<ddt::Image> out;
  ddt::Progress progress;
  call.options.progress = &progress;
  run_interruptibly(progress, [&] {
    const auto limit = ddt::limit_threads(call.threads);
    ddt::upscale_sequence(
        static_cast<int>(in.size()), f.width, f.height, f.channels, [&](int k) { return in[k]; }, out_w, out_h,
        time_scale, call.options, [&](ddt::Image frame, int) { out.push_back(std::move(frame)); });
  });
  py::list result;
  for (const ddt::Image& frame : out) result.append(array_from_image(frame, first.dtype, first.planar));
  return result;
}

py::array grid(const py::array& points, const py::array& values, const py::object& size, const py::dict& kwargs) {
  const auto xy = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(points);
  if (!xy || xy.ndim() != 2 || xy.shape(1) != 2)
    throw ddt::Error("points is an N x 2 array of x, y positions");
  const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
  if (!v || (v.ndim() != 1 && v.ndim() != 2) || v.shape(0) != xy.shape(0))
    throw ddt::Error("values is an N or N x C array, one row per point");
  if (xy.shape(0) == 0) throw ddt::Error("no points");
  const int channels = v.ndim() == 1 ? 1 : static_cast<int>(v.shape(1));
  if (channels < 1) throw ddt::Error("values has no channels");
  GridCall call = grid_call(kwargs, channels);
  ddt::GridOptions& o = call.options;
  if (size.is_none()) throw ddt::Error("give the grid's size: size=N or (height, width)");
  const std::vector<int> hw = size_values(size, 2, "size is (height, width) or one number for both");
  o.height = hw[0];
  o.width = hw[1];
  if (o.width < 1 || o.height < 1) throw ddt::Error("--size: the width and height must be positive");
  if (static_cast<long long>(o.width) * o.height > call.max_pixels)
    throw ddt::Error("grid " + std::to_string(o.width) + "x" + std::to_string(o.height) + " exceeds --max-pixels " +
                     std::to_string(call.max_pixels));
  ddt::PointTable table;
  table.channels = channels;
  const std::size_t n = xy.shape(0);
  table.points.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    table.points[i] = {xy.data()[2 * i], xy.data()[2 * i + 1]};
    if (!std::isfinite(table.points[i].x) || !std::isfinite(table.points[i].y))
      throw ddt::Error("the points hold NaN or infinite coordinates");
  }
  table.values.assign(v.data(), v.data() + n * channels);
  for (const double value : table.values)
    if (!std::isfinite(value) || std::abs(value) > 3.4e38) throw ddt::Error("the values hold NaN or infinite values");
  o.log = stderr_log(call.verbose);
  ddt::Image image;
  {
    py::gil_scoped_release release;
    const auto limit = ddt::limit_threads(call.threads);
    ddt::merge_duplicate_points(table);
    const std::vector<float> floats(table.values.begin(), table.values.end());
    image = ddt::grid_points(table.points, floats, channels, o);
  }
  const bool planar = v.ndim() == 1 && !o.alpha;
  const py::dtype dtype = values.dtype().is(py::dtype::of<double>()) ? py::dtype::of<double>() : py::dtype::of<float>();
  return array_from_image(image, dtype, planar);
}

}  // namespace

PYBIND11_MODULE(_ddtscale, m) {
  m.doc() = "The compiled half of ddtscale; use the functions of the ddtscale package.";
  m.attr("version") = DDTSCALE_VERSION;
  // Freed bands reused, but large buffers still returned to the system:
  // the interpreter's process is shared.
  ddt::tune_allocator(ddt::AllocatorUse::general);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ddt::FileError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const ddt::Error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const std::system_error& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    }
  });
  m.def("upscale_defaults", &image_defaults);
  m.def("upscale_file_defaults", &file_defaults);
  m.def("volume_defaults", &volume_defaults);
  m.def("grid_defaults", &grid_defaults);
  m.def("upscale", &upscale, py::arg("array"), py::arg("scale"), py::arg("size"), py::arg("options"));
  m.def("output_size", &output_size, py::arg("in_width"), py::arg("in_height"), py::arg("scale"), py::arg("size"),
        py::arg("options"));
  m.def("upscale_file", &upscale_file, py::arg("input"), py::arg("output"), py::arg("scale"), py::arg("size"),
        py::arg("options"));
  m.def("upscale_rows", &upscale_rows, py::arg("rows"), py::arg("top"), py::arg("image_height"), py::arg("first"),
        py::arg("end"), py::arg("out_width"), py::arg("out_height"), py::arg("options"),
        py::arg("statistics") = py::none());
  m.def("input_statistics", &input_statistics, py::arg("array"));
  m.def("merge_statistics", &merge_statistics, py::arg("a"), py::arg("b"));
  m.def("consistency_margin_needed", &consistency_margin_needed, py::arg("triangle_rows"), py::arg("width"),
        py::arg("height"), py::arg("out_width"), py::arg("out_height"), py::arg("options"));
  m.def("output_row_of", &ddt::output_row_of, py::arg("y"), py::arg("in_height"), py::arg("out_height"));
  m.def("band_margin_needed", &ddt::band_margin_needed, py::arg("phases"), py::arg("region_rows"));
  m.def("region_rows", &region_rows, py::arg("width"), py::arg("height"), py::arg("options"));
  m.def("upscale_volume", &upscale_volume, py::arg("array"), py::arg("scale"), py::arg("size"), py::arg("options"));
  m.def("sequence_defaults", &sequence_defaults);
  m.def("upscale_sequence", &upscale_sequence, py::arg("frames"), py::arg("time_scale"), py::arg("scale"),
        py::arg("size"), py::arg("options"));
  m.def("grid", &grid, py::arg("points"), py::arg("values"), py::arg("size"), py::arg("options"));
}
