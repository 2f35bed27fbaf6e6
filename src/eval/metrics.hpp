#pragma once
// Image quality metrics of the single-image super-resolution literature:
// PSNR and SSIM on the BT.601 luma (Y) channel with a border shaved off.
//
// Shared rules:
//   - Images are ddt::Image with samples in 0..1 (as read_image returns
//     8-bit files); metrics work on Y in the 0..255 scale, like MATLAB's
//     rgb2ycbcr on double input multiplied by 255 (Y itself is not rounded).
//   - A plane is an Eigen array with one row per image row (height x width),
//     as MATLAB stores a matrix.
//   - Mismatched sizes throw ddt::Error; so does a shave that leaves nothing
//     (or, for SSIM, less than the 11 x 11 window).

#include "util/image.hpp"

#include <Eigen/Core>

namespace ddt {

// BT.601 luma of a picture with samples in 0..1:
//   Y = 16 + (65.481 R + 128.553 G + 24.966 B) / 255,  R, G, B in 0..255
// (so Y is in 16..235).
//
// Inputs:  img  width x height x channels; channels >= 3 use channels 0..2 as
//               R, G, B (a 4th, alpha, is ignored); 1 or 2 channels are grey
//               (+ alpha): channel 0 stands for R = G = B.
// Outputs: returns a height x width plane of Y.
Eigen::ArrayXXd luma_bt601(const Image& img);

// Drops `border` rows and columns on every side (MATLAB: Y(1+b:end-b, 1+b:end-b)).
// Inputs:  plane  H x W;  border >= 0 with 2 * border < min(H, W)
// Outputs: returns (H - 2 border) x (W - 2 border)
Eigen::ArrayXXd shave(const Eigen::ArrayXXd& plane, int border);

// PSNR = 10 log10(peak^2 / MSE) in dB; +infinity when the planes are equal.
// Inputs: a, b  planes of the same size;  peak  the signal range (255)
double psnr(const Eigen::ArrayXXd& a, const Eigen::ArrayXXd& b, double peak = 255.0);

// Mean SSIM of Wang et al. 2004 as their ssim_index.m computes it: an
// 11 x 11 Gaussian window (sigma 1.5, normalized), 'valid' filtering (no
// padding), C1 = (K1 L)^2, C2 = (K2 L)^2 with K1 = 0.01, K2 = 0.03, and the
// mean of the SSIM map. 1 for identical planes.
// Inputs: a, b  planes of the same size, each side >= 11;  dynamic_range  L (255)
double ssim(const Eigen::ArrayXXd& a, const Eigen::ArrayXXd& b, double dynamic_range = 255.0);

// The protocol's scores: Y of both images, `border` pixels shaved, then
// psnr() / ssim() with L = 255.
// Inputs: result, reference  same width, height and colour layout, values in 0..1
double psnr_y(const Image& result, const Image& reference, int border);
double ssim_y(const Image& result, const Image& reference, int border);

}  // namespace ddt
