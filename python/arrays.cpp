#include "arrays.hpp"

#include "util/error.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace ddtpy {
namespace {

std::string dtype_name(const py::dtype& dtype) { return py::str(py::handle(dtype)); }

// A C-contiguous copy of `array` as T when it is not one already.
template <class T>
py::array_t<T, py::array::c_style> contiguous(const py::array& array) {
  return py::array_t<T, py::array::c_style>::ensure(array);
}

OIIO::TypeDesc oiio_type(const py::dtype& dtype) {
  if (dtype.is(py::dtype::of<std::uint8_t>())) return OIIO::TypeDesc::UINT8;
  if (dtype.is(py::dtype::of<std::uint16_t>())) return OIIO::TypeDesc::UINT16;
  return OIIO::TypeDesc::FLOAT;
}

template <class T>
void copy_volume(const py::array& array, std::vector<float>& out) {
  const auto a = contiguous<T>(array);
  const T* p = a.data();
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = static_cast<float>(p[i]);
}

template <class T>
py::array volume_as(const ddt::Volume& v) {
  // Several channels: a last axis of them (NRRD's leading axis, interleaved).
  std::vector<py::ssize_t> shape = {v.nz, v.ny, v.nx};
  if (v.nt > 1) shape.insert(shape.begin(), v.nt);  // a series: T x Z x Y x X
  if (v.channels > 1) shape.push_back(v.channels);
  py::array_t<T> out(shape);
  T* p = out.mutable_data();
  const std::size_t n = v.voxels.size();
  if constexpr (std::is_floating_point_v<T>) {
    std::copy(v.voxels.begin(), v.voxels.end(), p);
  } else {
    const double lo = static_cast<double>(std::numeric_limits<T>::min());
    const double hi = static_cast<double>(std::numeric_limits<T>::max());
    for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<T>(std::clamp(std::round(double(v.voxels[i])), lo, hi));
  }
  return out;
}

}  // namespace

void check_finite(const float* values, std::size_t n, const char* what) {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(values[i])) throw ddt::Error(std::string(what) + " holds NaN or infinite values");
}

ImageArray image_from_array(const py::array& array) {
  ImageArray r;
  r.dtype = array.dtype();
  const bool u8 = r.dtype.is(py::dtype::of<std::uint8_t>()), u16 = r.dtype.is(py::dtype::of<std::uint16_t>());
  const bool f32 = r.dtype.is(py::dtype::of<float>()), f64 = r.dtype.is(py::dtype::of<double>());
  if (!u8 && !u16 && !f32 && !f64)
    throw ddt::Error("an image array must be uint8, uint16, float32 or float64, not " + dtype_name(r.dtype));
  if (array.ndim() != 2 && array.ndim() != 3)
    throw ddt::Error("an image array is H x W or H x W x C; this one has " + std::to_string(array.ndim()) +
                     " dimensions (volumes: upscale_volume)");
  if (array.size() == 0) throw ddt::Error("the input image is empty");
  const auto limit = static_cast<py::ssize_t>(std::numeric_limits<int>::max());
  if (array.shape(0) > limit || array.shape(1) > limit || (array.ndim() == 3 && array.shape(2) > limit))
    throw ddt::Error("the input image is too large");
  r.planar = array.ndim() == 2;
  const int h = static_cast<int>(array.shape(0)), w = static_cast<int>(array.shape(1));
  const int c = r.planar ? 1 : static_cast<int>(array.shape(2));
  r.image = ddt::Image(w, h, c);
  const std::size_t n = r.image.pixels.size();
  float* dst = r.image.pixels.data();
  if (f64) {
    const auto a = contiguous<double>(array);
    std::copy(a.data(), a.data() + n, dst);
  } else if (f32) {
    const auto a = contiguous<float>(array);
    std::copy(a.data(), a.data() + n, dst);
  } else if (u8) {
    const auto a = contiguous<std::uint8_t>(array);
    OIIO::convert_pixel_values(OIIO::TypeDesc::UINT8, a.data(), OIIO::TypeDesc::FLOAT, dst, static_cast<int>(n));
  } else {
    const auto a = contiguous<std::uint16_t>(array);
    OIIO::convert_pixel_values(OIIO::TypeDesc::UINT16, a.data(), OIIO::TypeDesc::FLOAT, dst, static_cast<int>(n));
  }
  if (f32 || f64) check_finite(dst, n, "the input image");
  return r;
}

py::array array_from_image(const ddt::Image& image, const py::dtype& dtype, bool planar) {
  std::vector<py::ssize_t> shape = {image.height, image.width};
  if (!planar) shape.push_back(image.channels);
  py::array out(dtype, shape);
  const std::size_t n = image.pixels.size();
  if (dtype.is(py::dtype::of<double>())) {
    std::copy(image.pixels.begin(), image.pixels.end(), static_cast<double*>(out.mutable_data()));
  } else {
    OIIO::convert_pixel_values(OIIO::TypeDesc::FLOAT, image.pixels.data(), oiio_type(dtype), out.mutable_data(),
                               static_cast<int>(n));
  }
  return out;
}

VolumeArray volume_from_array(const py::array& array) {
  VolumeArray r;
  r.dtype = array.dtype();
  if (array.ndim() != 3 && array.ndim() != 4)
    throw ddt::Error("a volume array is Z x Y x X, a series T x Z x Y x X; this one has " +
                     std::to_string(array.ndim()) + " dimensions");
  if (array.size() == 0) throw ddt::Error("the input volume is empty");
  for (py::ssize_t a = 0; a < array.ndim(); ++a)
    if (array.shape(a) > 65536) throw ddt::Error("the input volume is too large (at most 65536 voxels on an axis)");
  const py::ssize_t d = array.ndim();
  r.volume = ddt::Volume({static_cast<int>(array.shape(d - 1)), static_cast<int>(array.shape(d - 2)),
                          static_cast<int>(array.shape(d - 3)), d == 4 ? static_cast<int>(array.shape(0)) : 1},
                         1, 0.0f);
  std::vector<float>& v = r.volume.voxels;
  const char kind = r.dtype.kind();
  const auto size = r.dtype.itemsize();
  if (kind == 'f' && size == 4) copy_volume<float>(array, v);
  else if (kind == 'f' && size == 8) copy_volume<double>(array, v);
  else if (kind == 'u' && size == 1) copy_volume<std::uint8_t>(array, v);
  else if (kind == 'u' && size == 2) copy_volume<std::uint16_t>(array, v);
  else if (kind == 'u' && size == 4) copy_volume<std::uint32_t>(array, v);
  else if (kind == 'i' && size == 1) copy_volume<std::int8_t>(array, v);
  else if (kind == 'i' && size == 2) copy_volume<std::int16_t>(array, v);
  else if (kind == 'i' && size == 4) copy_volume<std::int32_t>(array, v);
  else
    throw ddt::Error("a volume array must be an integer type of up to 32 bits, float32 or float64, not " +
                     dtype_name(r.dtype));
  if (kind == 'f') check_finite(v.data(), v.size(), "the input volume");
  return r;
}

py::array array_from_volume(const ddt::Volume& volume, const py::dtype& dtype) {
  const char kind = dtype.kind();
  const auto size = dtype.itemsize();
  if (kind == 'f' && size == 4) return volume_as<float>(volume);
  if (kind == 'f' && size == 8) return volume_as<double>(volume);
  if (kind == 'u' && size == 1) return volume_as<std::uint8_t>(volume);
  if (kind == 'u' && size == 2) return volume_as<std::uint16_t>(volume);
  if (kind == 'u' && size == 4) return volume_as<std::uint32_t>(volume);
  if (kind == 'i' && size == 1) return volume_as<std::int8_t>(volume);
  if (kind == 'i' && size == 2) return volume_as<std::int16_t>(volume);
  return volume_as<std::int32_t>(volume);
}

}  // namespace ddtpy
