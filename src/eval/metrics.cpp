#include "eval/metrics.hpp"

#include "util/error.hpp"

#include <cmath>
#include <limits>
#include <string>

namespace ddt {
namespace {

std::string size_text(const Eigen::ArrayXXd& p) {
  return std::to_string(p.cols()) + "x" + std::to_string(p.rows());
}

void check_same_size(const Eigen::ArrayXXd& a, const Eigen::ArrayXXd& b, const char* what) {
  if (a.rows() != b.rows() || a.cols() != b.cols())
    throw Error(std::string(what) + ": planes differ in size (" + size_text(a) + " vs " + size_text(b) + ")");
  if (a.size() == 0) throw Error(std::string(what) + ": the planes are empty");
}

// The normalized 1-D factor of MATLAB's fspecial('gaussian', 11, 1.5); the
// 2-D window is its outer product, so filtering is done separably.
Eigen::ArrayXd gaussian_window(int size, double sigma) {
  Eigen::ArrayXd g(size);
  const double centre = (size - 1) / 2.0;
  for (int i = 0; i < size; ++i) g(i) = std::exp(-(i - centre) * (i - centre) / (2 * sigma * sigma));
  return g / g.sum();
}

// MATLAB filter2(w, p, 'valid') for the separable window w = g g^T.
Eigen::ArrayXXd filter_valid(const Eigen::ArrayXXd& p, const Eigen::ArrayXd& g) {
  const Eigen::Index n = g.size();
  const Eigen::Index rows = p.rows() - n + 1, cols = p.cols() - n + 1;
  Eigen::ArrayXXd across(p.rows(), cols);  // filtered along each row
  for (Eigen::Index c = 0; c < cols; ++c) {
    across.col(c).setZero();
    for (Eigen::Index k = 0; k < n; ++k) across.col(c) += g(k) * p.col(c + k);
  }
  Eigen::ArrayXXd out(rows, cols);
  for (Eigen::Index r = 0; r < rows; ++r) {
    out.row(r).setZero();
    for (Eigen::Index k = 0; k < n; ++k) out.row(r) += g(k) * across.row(r + k);
  }
  return out;
}

void check_images(const Image& result, const Image& reference, const char* what) {
  if (result.empty() || reference.empty()) throw Error(std::string(what) + ": an image is empty");
  if (result.width != reference.width || result.height != reference.height)
    throw Error(std::string(what) + ": images differ in size (" + std::to_string(result.width) + "x" +
                std::to_string(result.height) + " vs " + std::to_string(reference.width) + "x" +
                std::to_string(reference.height) + ")");
  if ((result.channels >= 3) != (reference.channels >= 3))
    throw Error(std::string(what) + ": one image is colour and the other grey");
}

}  // namespace

Eigen::ArrayXXd luma_bt601(const Image& img) {
  if (img.empty() || img.channels <= 0) throw Error("luma_bt601: the image is empty");
  Eigen::ArrayXXd y(img.height, img.width);
  const bool colour = img.channels >= 3;
  for (int r = 0; r < img.height; ++r) {
    for (int c = 0; c < img.width; ++c) {
      const double red = 255.0 * img.at(c, r, 0);
      const double green = colour ? 255.0 * img.at(c, r, 1) : red;
      const double blue = colour ? 255.0 * img.at(c, r, 2) : red;
      y(r, c) = 16.0 + (65.481 * red + 128.553 * green + 24.966 * blue) / 255.0;
    }
  }
  return y;
}

Eigen::ArrayXXd shave(const Eigen::ArrayXXd& plane, int border) {
  if (border < 0) throw Error("shave: negative border " + std::to_string(border));
  if (2LL * border >= plane.rows() || 2LL * border >= plane.cols())
    throw Error("shave: a border of " + std::to_string(border) + " leaves nothing of a " + size_text(plane) +
                " plane");
  return plane.block(border, border, plane.rows() - 2 * border, plane.cols() - 2 * border);
}

double psnr(const Eigen::ArrayXXd& a, const Eigen::ArrayXXd& b, double peak) {
  check_same_size(a, b, "psnr");
  const double mse = (a - b).square().mean();
  if (mse == 0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(peak * peak / mse);
}

double ssim(const Eigen::ArrayXXd& a, const Eigen::ArrayXXd& b, double dynamic_range) {
  check_same_size(a, b, "ssim");
  constexpr int window = 11;
  if (a.rows() < window || a.cols() < window)
    throw Error("ssim: a " + size_text(a) + " plane is smaller than the 11x11 window");
  const double c1 = (0.01 * dynamic_range) * (0.01 * dynamic_range);
  const double c2 = (0.03 * dynamic_range) * (0.03 * dynamic_range);
  const Eigen::ArrayXd g = gaussian_window(window, 1.5);

  const Eigen::ArrayXXd mu1 = filter_valid(a, g);
  const Eigen::ArrayXXd mu2 = filter_valid(b, g);
  const Eigen::ArrayXXd mu1_sq = mu1.square(), mu2_sq = mu2.square(), mu1_mu2 = mu1 * mu2;
  const Eigen::ArrayXXd sigma1_sq = filter_valid(a.square(), g) - mu1_sq;
  const Eigen::ArrayXXd sigma2_sq = filter_valid(b.square(), g) - mu2_sq;
  const Eigen::ArrayXXd sigma12 = filter_valid(a * b, g) - mu1_mu2;

  const Eigen::ArrayXXd map = ((2 * mu1_mu2 + c1) * (2 * sigma12 + c2)) /
                              ((mu1_sq + mu2_sq + c1) * (sigma1_sq + sigma2_sq + c2));
  return map.mean();
}

double psnr_y(const Image& result, const Image& reference, int border) {
  check_images(result, reference, "psnr_y");
  return psnr(shave(luma_bt601(result), border), shave(luma_bt601(reference), border), 255.0);
}

double ssim_y(const Image& result, const Image& reference, int border) {
  check_images(result, reference, "ssim_y");
  return ssim(shave(luma_bt601(result), border), shave(luma_bt601(reference), border), 255.0);
}

}  // namespace ddt
