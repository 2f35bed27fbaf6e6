#include "volume/presmooth.hpp"

#include "util/error.hpp"
#include "util/teem_error.hpp"

#include <teem/nrrd.h>

#include <algorithm>
#include <string>

namespace ddt {

std::vector<float> smoothed_grid(const std::vector<float>& values, const std::vector<int>& size, int channels,
                                 const std::vector<double>& sigma) {
  if (size.empty() || size.size() > 4 || sigma.size() != size.size() || channels < 1)
    throw Error("smoothing: 1 to 4 axes, a sigma per axis, at least one channel");
  std::size_t count = static_cast<std::size_t>(channels);
  for (int n : size) count *= static_cast<std::size_t>(std::max(0, n));
  if (count == 0 || values.size() != count) throw Error("smoothing: the samples do not match the size");
  if (std::all_of(sigma.begin(), sigma.end(), [](double s) { return s <= 0; })) return values;

  // Axis 0 of the nrrd holds the channels (never resampled).
  std::size_t dims[5] = {static_cast<std::size_t>(channels)};
  for (std::size_t a = 0; a < size.size(); ++a) dims[a + 1] = static_cast<std::size_t>(size[a]);
  const unsigned dim = static_cast<unsigned>(size.size()) + 1;
  Nrrd* nin = nrrdNew();
  Nrrd* nout = nrrdNew();
  NrrdResampleContext* rsmc = nrrdResampleContextNew();
  auto done = [&] {
    nrrdResampleContextNix(rsmc);
    nrrdNix(nin);  // wraps `values`: not ours to free
    nrrdNuke(nout);
  };
  int failed = nrrdWrap_nva(nin, const_cast<float*>(values.data()), nrrdTypeFloat, dim, dims) ||
               nrrdResampleDefaultCenterSet(rsmc, nrrdCenterCell) || nrrdResampleNrrdSet(rsmc, nin) ||
               nrrdResampleBoundarySet(rsmc, nrrdBoundaryBleed) || nrrdResampleTypeOutSet(rsmc, nrrdTypeFloat) ||
               nrrdResampleRenormalizeSet(rsmc, AIR_TRUE);
  for (unsigned a = 0; a < dim && !failed; ++a) {
    const double s = a == 0 ? 0 : sigma[a - 1];
    double parm[NRRD_KERNEL_PARMS_NUM] = {s, 3.0};  // sigma, cut-off in sigmas
    failed = s > 0 ? nrrdResampleKernelSet(rsmc, a, nrrdKernelGaussian, parm) || nrrdResampleSamplesSet(rsmc, a, dims[a]) ||
                         nrrdResampleRangeFullSet(rsmc, a)
                   : nrrdResampleKernelSet(rsmc, a, nullptr, nullptr);
  }
  failed = failed || nrrdResampleExecute(rsmc, nout);
  if (failed) {
    const std::string why = teem_error();
    done();
    throw Error("smoothing: " + why);
  }
  const float* data = static_cast<const float*>(nout->data);
  std::vector<float> out(data, data + count);
  done();
  return out;
}

}  // namespace ddt
