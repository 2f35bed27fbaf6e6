#include "eval/volume_resample.hpp"

#include "util/error.hpp"
#include "util/teem_error.hpp"

#include <teem/nrrd.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace ddt {
namespace {

// Per output index along one axis: the two input indices and the weight
// of the second, index position clamped into [0, n_in - 1].
struct Taps {
  std::vector<int> i0, i1;
  std::vector<double> w1;
};

Taps linear_taps(int n_in, int n_out) {
  Taps t;
  const double s = double(n_out) / n_in;
  for (int X = 0; X < n_out; ++X) {
    const double u = std::clamp((X + 0.5) / s - 0.5, 0.0, double(n_in - 1));
    const int a = std::min(static_cast<int>(std::floor(u)), n_in - 1);
    t.i0.push_back(a);
    t.i1.push_back(std::min(a + 1, n_in - 1));
    t.w1.push_back(u - a);
  }
  return t;
}

Volume trilinear(const Volume& src, int nx, int ny, int nz) {
  const Taps tx = linear_taps(src.nx, nx), ty = linear_taps(src.ny, ny), tz = linear_taps(src.nz, nz);
  Volume out(nx, ny, nz);
  tbb::parallel_for(0, nz, [&](int Z) {
    const double wz = tz.w1[Z];
    for (int Y = 0; Y < ny; ++Y) {
      const double wy = ty.w1[Y];
      for (int X = 0; X < nx; ++X) {
        const double wx = tx.w1[X];
        auto at = [&](int i, int j, int k) { return double(src.at(i, j, k)); };
        auto lerp = [](double a, double b, double w) { return a + w * (b - a); };
        const int x0 = tx.i0[X], x1 = tx.i1[X], y0 = ty.i0[Y], y1 = ty.i1[Y], z0 = tz.i0[Z], z1 = tz.i1[Z];
        const double c00 = lerp(at(x0, y0, z0), at(x1, y0, z0), wx), c10 = lerp(at(x0, y1, z0), at(x1, y1, z0), wx);
        const double c01 = lerp(at(x0, y0, z1), at(x1, y0, z1), wx), c11 = lerp(at(x0, y1, z1), at(x1, y1, z1), wx);
        out.at(X, Y, Z) = static_cast<float>(lerp(lerp(c00, c10, wy), lerp(c01, c11, wy), wz));
      }
    }
  });
  return out;
}

const NrrdKernel* teem_kernel(const std::string& name) {
  if (name == "tent") return nrrdKernelTent;
  if (name == "catmull-rom") return nrrdKernelCatmullRom;
  throw Error("resample: unknown Teem kernel '" + name + "' (valid: tent, catmull-rom)");
}

// One channel, up to four axes, a kernel and a centring per axis.
Volume teem_resample_axes(const Volume& src, const std::array<int, 4>& size,
                          const std::array<const NrrdKernel*, 4>& kernels, const std::array<bool, 4>& node_centred,
                          const AxisWindow& window = {}) {
  if (src.empty() || src.channels != 1) throw Error("resample: the volume is empty or has several channels");
  for (int n : size)
    if (n < 1) throw Error("resample: the output size must be at least 1 on every axis");
  double parm[NRRD_KERNEL_PARMS_NUM] = {1.0, 0.0, 0.5};  // scale 1 (input samples); B, C unused
  Nrrd* nin = nrrdNew();
  Nrrd* nout = nrrdNew();
  NrrdResampleContext* rsmc = nrrdResampleContextNew();
  auto done = [&] {
    nrrdResampleContextNix(rsmc);
    nrrdNix(nin);  // wraps src's memory: do not free it
    nrrdNuke(nout);
  };
  const std::array<int, 4> in = src.size();
  const unsigned axes = in[3] > 1 || size[3] > 1 ? 4 : 3;
  std::size_t n_in[4];
  for (unsigned a = 0; a < 4; ++a) n_in[a] = std::size_t(in[a]);
  int failed = nrrdWrap_nva(nin, const_cast<float*>(src.voxels.data()), nrrdTypeFloat, axes, n_in);
  // A node-centred axis of one sample has no interval to span: cell-centred
  // it repeats its sample, which is all a single instant can give.
  for (unsigned a = 0; a < axes && !failed; ++a)
    nin->axis[a].center = node_centred[a] && in[a] > 1 && size[a] > 1 ? nrrdCenterNode : nrrdCenterCell;
  failed = failed || nrrdResampleNrrdSet(rsmc, nin) || nrrdResampleBoundarySet(rsmc, nrrdBoundaryBleed) ||
           nrrdResampleTypeOutSet(rsmc, nrrdTypeFloat) || nrrdResampleRenormalizeSet(rsmc, AIR_TRUE);
  for (unsigned a = 0; a < axes && !failed; ++a) {
    failed = nrrdResampleKernelSet(rsmc, a, kernels[a], parm) || nrrdResampleSamplesSet(rsmc, a, std::size_t(size[a]));
    if (failed) break;
    if (window.scale > 0 && int(a) == window.axis) {
      // The range is in the input's index space: where the first and last
      // output samples sit (node), or the edges of the output's cells (cell).
      const double s = window.scale, f = window.first;
      const bool node = nin->axis[a].center == nrrdCenterNode;
      failed = node ? nrrdResampleRangeSet(rsmc, a, f / s, (f + size[a] - 1) / s)
                    : nrrdResampleRangeSet(rsmc, a, f / s - 0.5, (f + size[a]) / s - 0.5);
    } else {
      failed = nrrdResampleRangeFullSet(rsmc, a);
    }
  }
  failed = failed || nrrdResampleExecute(rsmc, nout);
  if (failed) {
    const std::string why = teem_error();
    done();
    throw Error("resample: " + why);
  }
  Volume out(size, 1, 0.0f);
  const float* data = static_cast<const float*>(nout->data);
  std::copy(data, data + out.voxel_count(), out.voxels.begin());
  done();
  return out;
}

}  // namespace

Volume teem_resample(const Volume& src, int nx, int ny, int nz, const std::string& kernel) {
  if (src.empty()) throw Error("resample: the volume is empty");
  if (nx < 1 || ny < 1 || nz < 1) throw Error("resample: the output size must be at least 1x1x1");
  const NrrdKernel* k = teem_kernel(kernel);
  return teem_resample_axes(src, {nx, ny, nz, 1}, {k, k, k, k}, {});
}

Volume classic_resize_axes(const Volume& src, const std::array<int, 4>& size, const std::string& method,
                           const std::array<bool, 4>& node_centred, const AxisWindow& window) {
  if (src.empty()) throw Error("resize: the volume is empty");
  const NrrdKernel* linear = nrrdKernelTent;
  const NrrdKernel* cubic = nrrdKernelCatmullRom;
  if (method == "quadrilinear" || method == "trilinear")
    return teem_resample_axes(src, size, {linear, linear, linear, linear}, node_centred, window);
  if (method == "tricubic-linear" || method == "tricubic")
    return teem_resample_axes(src, size, {cubic, cubic, cubic, linear}, node_centred, window);
  throw Error("unknown volume method '" + method + "' (valid: trilinear, tricubic, quadrilinear, tricubic-linear)");
}

Volume classic_resize_volume(const Volume& src, int nx, int ny, int nz, const std::string& method) {
  if (src.empty()) throw Error("resize: the volume is empty");
  if (nx < 1 || ny < 1 || nz < 1) throw Error("resize: the output size must be at least 1x1x1");
  if (method == "trilinear") return trilinear(src, nx, ny, nz);
  if (method == "tricubic") return teem_resample(src, nx, ny, nz, "catmull-rom");
  throw Error("unknown volume method '" + method + "' (valid: trilinear, tricubic)");
}

}  // namespace ddt
