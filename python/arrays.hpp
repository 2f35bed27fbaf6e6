#pragma once
// numpy arrays <-> the library's float rasters, for python/module.cpp.
//
// Images: H x W or H x W x C arrays of uint8, uint16 (scaled to 0..1, as
// image files are read), float32 or float64 (kept as they are); back in the
// same dtype, integers rounded and clamped by OpenImageIO's conversion, as
// image files are written. Volumes: Z x Y x X arrays of any integer type up
// to 32 bits or float, values kept as stored (volume.hpp), integers rounded
// and clamped to their type's range on the way back.
// Any strides are accepted (non-contiguous and negative ones are copied).
//
// Errors: ddt::Error (ValueError) with a one-line message for a dtype or a
// number of dimensions the call does not take, an empty array, NaN or
// infinite samples.

#include "util/image.hpp"
#include "volume/volume.hpp"

#include <pybind11/numpy.h>

namespace ddtpy {

namespace py = pybind11;

// The dtype the output keeps, and the samples as floats.
struct ImageArray {
  ddt::Image image;
  py::dtype dtype;
  bool planar = false;  // H x W (no channel axis)
};

ImageArray image_from_array(const py::array& array);
py::array array_from_image(const ddt::Image& image, const py::dtype& dtype, bool planar);

struct VolumeArray {
  ddt::Volume volume;
  py::dtype dtype;
};

VolumeArray volume_from_array(const py::array& array);
py::array array_from_volume(const ddt::Volume& volume, const py::dtype& dtype);

// Throws ddt::Error unless every value is finite ("<what> holds NaN or infinite values").
void check_finite(const float* values, std::size_t n, const char* what);

}  // namespace ddtpy
