#pragma once
// Keyword options of the Python module (python/module.cpp) -> the library's
// option structs. Names and defaults are the command line's (`ddtscale
// --help`, with '-' as '_'); the defaults are read from default-constructed
// library structs, so they cannot drift from the C++ side.
//
// Errors: a bad value throws ddt::Error with the command line's one-line
// message (ValueError in Python); an unknown name throws ddt::Error naming
// the accepted ones; a value of the wrong Python type throws
// pybind11::type_error (TypeError).

#include "io/encode_options.hpp"
#include "scattered/gridding.hpp"
#include "pipeline/upscale.hpp"
#include "volume/sequence_upscale.hpp"
#include "util/size_limits.hpp"
#include "volume/volume_upscale.hpp"

#include <pybind11/pybind11.h>

#include <optional>
#include <string>

namespace ddtpy {

namespace py = pybind11;

// What the command line does around ddt::upscale, beyond its options.
struct ImageCall {
  ddt::UpscaleOptions options;
  long long max_pixels = ddt::default_max_pixels;
  int threads = 0;  // 0: all cores
  bool verbose = false, quiet = false;
  std::string cost_channel = "sum";
  std::string model = "box";
  std::optional<std::string> compare, mesh, mesh_roi;
};

// upscale_file's: the image options but compare and mesh, and the output
// file's (--compression, --quality, --half, --float, --tile-size,
// --no-stream, --max-input-pixels).
struct FileCall {
  ImageCall image;
  ddt::EncodeOptions encode;
  bool no_stream = false;
  long long max_input_pixels = ddt::default_max_input_pixels();
};

struct VolumeCall {
  ddt::VolumeUpscaleOptions options;  // node_centred: time (axis t) by default
  std::optional<double> time_scale;   // series: the time axis' magnification (default: scale)
  double presmooth = -1;              // the graduated optimization's sigma in space; < 0: presmooth_in_space's
  long long max_voxels = ddt::default_max_voxels;
  int threads = 0;
  bool verbose = false;
};

struct SequenceCall {
  ddt::SequenceUpscaleOptions options;
  long long max_pixels = ddt::default_max_voxels;  // frames x width x height of the output
  int threads = 0;
  bool verbose = false;
};

struct GridCall {
  ddt::GridOptions options;
  long long max_pixels = ddt::default_max_pixels;
  int threads = 0;
  bool verbose = false;
};

// The options and their defaults, as the Python keywords.
py::dict image_defaults();
py::dict volume_defaults();
py::dict grid_defaults();
py::dict sequence_defaults();

ImageCall image_call(const py::dict& kwargs);
py::dict file_defaults();
FileCall file_call(const py::dict& kwargs);
VolumeCall volume_call(const py::dict& kwargs);
GridCall grid_call(const py::dict& kwargs, int channels);
SequenceCall sequence_call(const py::dict& kwargs);

}  // namespace ddtpy
