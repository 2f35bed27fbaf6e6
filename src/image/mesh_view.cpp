#include "image/mesh_view.hpp"
#include "util/file_names.hpp"

#include "util/error.hpp"
#include "io/image_io.hpp"

#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <charconv>
#include <limits>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <unordered_set>

namespace ddt {
namespace {

std::uint64_t edge_key(index_t u, index_t v) {
  if (u > v) std::swap(u, v);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(u)) << 32) | static_cast<std::uint32_t>(v);
}

// RGB view of the region: grey replicated, extra channels dropped.
Image region_rgb(const Image& image, const PixelRegion& r, int alpha_channel_guess) {
  Image out(r.width, r.height, 3);
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x)
      for (int c = 0; c < 3; ++c) {
        int src_c = image.channels >= 3 ? c : 0;
        if (src_c == alpha_channel_guess) src_c = 0;
        out.at(x, y, c) = std::clamp(image.at(r.x + x, r.y + y, src_c), 0.0f, 1.0f);
      }
  return out;
}

struct EdgeLists {
  std::vector<std::pair<index_t, index_t>> kept, flipped;
};

EdgeLists visible_edges(const Mesh2& mesh, const Mesh2* initial, const PixelRegion& r) {
  std::unordered_set<std::uint64_t> before;
  if (initial)
    for (index_t e = 0; e < initial->half_edge_count(); ++e)
      before.insert(edge_key(initial->tri[e], initial->tri[next_edge(e)]));
  EdgeLists lists;
  for (index_t e = 0; e < mesh.half_edge_count(); ++e) {
    if (mesh.opp[e] != no_edge && mesh.opp[e] < e) continue;  // each edge once
    const index_t u = mesh.tri[e], v = mesh.tri[next_edge(e)];
    const Point2 &p = mesh.points[u], &q = mesh.points[v];
    if (std::max(p.x, q.x) < r.x || std::min(p.x, q.x) > r.x + r.width || std::max(p.y, q.y) < r.y ||
        std::min(p.y, q.y) > r.y + r.height)
      continue;
    (initial && !before.count(edge_key(u, v)) ? lists.flipped : lists.kept).emplace_back(u, v);
  }
  return lists;
}

std::string svg_path(const Mesh2& mesh, const std::vector<std::pair<index_t, index_t>>& edges) {
  std::string d;
  char buf[96];
  for (auto [u, v] : edges) {
    std::snprintf(buf, sizeof buf, "M%.6g %.6gL%.6g %.6g", mesh.points[u].x, mesh.points[u].y, mesh.points[v].x,
                  mesh.points[v].y);
    d += buf;
  }
  return d;
}

}  // namespace

void write_mesh_view(const std::string& path, const Mesh2& mesh, const Mesh2* initial, const Image& image,
                     PixelRegion roi, int magnification) {
  if (roi.width == 0) roi = {0, 0, image.width, image.height};
  check_region(roi, image.width, image.height);
  const Image pixels = region_rgb(image, roi, image.channels == 4 ? 3 : image.channels == 2 ? 1 : -1);
  const EdgeLists edges = visible_edges(mesh, initial, roi);
  const std::string ext = lower_extension(path);

  if (ext == ".svg") {
    const std::vector<unsigned char> png = encode_png(pixels);
    const double px = magnification > 0 ? magnification : std::max(4.0, 1024.0 / std::max(roi.width, roi.height));
    std::ostringstream svg;
    svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << roi.width * px << "\" height=\"" << roi.height * px
        << "\" viewBox=\"" << roi.x << ' ' << roi.y << ' ' << roi.width << ' ' << roi.height << "\">\n"
        << "<title>ddtscale mesh: " << mesh.triangle_count() << " triangles, " << edges.flipped.size()
        << " flipped edges in view</title>\n"
        << "<image x=\"" << roi.x << "\" y=\"" << roi.y << "\" width=\"" << roi.width << "\" height=\"" << roi.height
        << "\" style=\"image-rendering:pixelated\" preserveAspectRatio=\"none\" href=\"data:image/png;base64,"
        << OIIO::Strutil::base64_encode(
               OIIO::string_view(reinterpret_cast<const char*>(png.data()), png.size()))
        << "\"/>\n"
        << "<path fill=\"none\" stroke=\"#9ecbff\" stroke-opacity=\"0.6\" stroke-width=\"0.04\" d=\""
        << svg_path(mesh, edges.kept) << "\"/>\n"
        << "<path fill=\"none\" stroke=\"#ff7f0e\" stroke-width=\"0.07\" d=\"" << svg_path(mesh, edges.flipped)
        << "\"/>\n</svg>\n";
    write_file_atomically(path, svg.str());
    return;
  }

  const int m = magnification > 0 ? magnification : std::clamp(1024 / std::max(roi.width, roi.height), 4, 16);
  OIIO::ImageBuf base = buf_from_image(pixels);
  OIIO::ImageBuf big(OIIO::ImageSpec(roi.width * m, roi.height * m, 3, OIIO::TypeDesc::FLOAT));
  OIIO::ImageBufAlgo::resample(big, base, /*interpolate=*/false);
  auto draw = [&](const std::vector<std::pair<index_t, index_t>>& list, const float* colour) {
    for (auto [u, v] : list) {
      const Point2 &p = mesh.points[u], &q = mesh.points[v];
      OIIO::ImageBufAlgo::render_line(big, int((p.x - roi.x) * m), int((p.y - roi.y) * m), int((q.x - roi.x) * m),
                                      int((q.y - roi.y) * m), OIIO::cspan<float>(colour, 3));
    }
  };
  const float light[3] = {0.62f, 0.80f, 1.0f}, orange[3] = {1.0f, 0.5f, 0.05f};
  draw(edges.kept, light);
  draw(edges.flipped, orange);
  write_image(path, image_from_buf(big), SampleFormat::uint8);
}

}  // namespace ddt
