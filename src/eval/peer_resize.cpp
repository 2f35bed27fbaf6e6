#include "eval/peer_resize.hpp"

#include "util/error.hpp"
#include "util/text.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vips/vips.h>

#include <algorithm>
#include <cstring>
#include <mutex>

namespace ddt {
namespace {

Image opencv_resize(const Image& src, int out_w, int out_h, int interpolation) {
  Image out(out_w, out_h, src.channels);
  // Views of our buffers: cv::resize writes straight into `out` (it keeps a
  // destination of the right size and type).
  const cv::Mat in_view(src.height, src.width, CV_32FC(src.channels), const_cast<float*>(src.pixels.data()));
  cv::Mat out_view(out_h, out_w, CV_32FC(src.channels), out.pixels.data());
  try {
    cv::resize(in_view, out_view, cv::Size(out_w, out_h), 0, 0, interpolation);
  } catch (const cv::Exception& e) {
    throw Error("opencv resize: " + first_line(e.what()));
  }
  if (out_view.data != reinterpret_cast<uchar*>(out.pixels.data()))
    throw Error("opencv resize: the result was not written in place");
  return out;
}

// libvips keeps per-process state: initialized once, with the operation
// cache off (a cached operation would hold on to our borrowed input buffers).
void init_vips() {
  static std::once_flag once;
  static bool ok = false;
  std::call_once(once, [] {
    ok = VIPS_INIT("ddtscale") == 0;
    if (ok) vips_cache_set_max(0);
  });
  if (!ok) throw Error("vips-nohalo: libvips failed to initialize");
}

std::string vips_failure() {
  std::string why = first_line(vips_error_buffer());
  vips_error_clear();
  return "vips-nohalo: " + (why.empty() ? std::string("libvips failed") : why);
}

Image vips_nohalo(const Image& src, int out_w, int out_h) {
  init_vips();
  // The input is borrowed, not copied: `in` must not outlive `src`.
  VipsImage* in = vips_image_new_from_memory(src.pixels.data(), src.pixels.size() * sizeof(float), src.width,
                                             src.height, src.channels, VIPS_FORMAT_FLOAT);
  if (!in) throw Error(vips_failure());
  VipsInterpolate* nohalo = vips_interpolate_new("nohalo");
  VipsArrayInt* area = vips_array_int_newv(4, 0, 0, out_w, out_h);
  VipsImage* out = nullptr;
  const double sx = static_cast<double>(out_w) / src.width, sy = static_cast<double>(out_h) / src.height;
  // Centre convention (header): out + 0.5 = s (in + 0.5).
  const int failed = !nohalo || vips_affine(in, &out, sx, 0.0, 0.0, sy, "interpolate", nohalo, "idx", 0.5, "idy",
                                            0.5, "odx", -0.5, "ody", -0.5, "oarea", area, "extend",
                                            VIPS_EXTEND_COPY, nullptr);
  vips_area_unref(VIPS_AREA(area));
  if (nohalo) g_object_unref(nohalo);
  std::size_t bytes = 0;
  void* pixels = failed ? nullptr : vips_image_write_to_memory(out, &bytes);
  if (out) g_object_unref(out);
  g_object_unref(in);
  if (!pixels) throw Error(vips_failure());
  Image result(out_w, out_h, src.channels);
  const bool size_ok = bytes == result.pixels.size() * sizeof(float);
  if (size_ok) std::memcpy(result.pixels.data(), pixels, bytes);
  g_free(pixels);
  if (!size_ok) throw Error("vips-nohalo: libvips returned an image of the wrong size");
  return result;
}

}  // namespace

std::vector<std::string> peer_methods() { return {"opencv-lanczos4", "opencv-cubic", "vips-nohalo"}; }

Image peer_resize(const Image& src, int out_w, int out_h, const std::string& method) {
  const std::vector<std::string> names = peer_methods();
  if (std::find(names.begin(), names.end(), method) == names.end()) {
    throw Error("unknown peer method '" + method + "' (valid: " + joined(names) + ")");
  }
  if (src.empty() || src.width <= 0 || src.height <= 0 || src.channels <= 0)
    throw Error("peer_resize: the source image is empty");
  if (out_w < 1 || out_h < 1)
    throw Error("peer_resize: output size " + std::to_string(out_w) + "x" + std::to_string(out_h) +
                " is not positive");
  if (src.channels > CV_CN_MAX) throw Error("peer_resize: more than " + std::to_string(CV_CN_MAX) + " channels");
  if (method == "opencv-lanczos4") return opencv_resize(src, out_w, out_h, cv::INTER_LANCZOS4);
  if (method == "opencv-cubic") return opencv_resize(src, out_w, out_h, cv::INTER_CUBIC);
  return vips_nohalo(src, out_w, out_h);
}

}  // namespace ddt
