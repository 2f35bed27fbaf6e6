// paper_experiments — the 2D experiments of Tóth et al., "N-dimensional
// Data-Dependent Reconstruction Using Topological Changes", reproduced
// for docs/paper-experiments.md.
//
//   paper_experiments fig1 IMAGE --crop 40x32+44+46 --scale 10 --out fig1.png
//     Figure 1: bicubic (left) beside DDT (right).
//   paper_experiments fig8 IMAGE --crop 40x40+24+50 --scale 6 --seed 1 --mesh-roi 2,18,20,20 --out fig8.png
//     Figure 8: Lawson's optimization (top row) and simulated annealing
//     (bottom row); left the reconstruction, right the mesh of the framed
//     part over the input pixels, the edges the optimizer created in orange.
//
//   paper_experiments smooth IMAGE... --cost sederberg,variance --seeds 1,2,3 [--lookahead]
//     (an IMAGE "scene:NAME@WxH" renders a synthetic scene, synthetic_scenes.hpp)
//     Where do the flips land? Prints a Markdown table per image: for the
//     Lawson mesh and the annealed mesh of every cost (and seed), how the
//     edges the optimizer created, the edges that are not Delaunay and the
//     thin triangles split over the quarters of the image by local variance
//     (Q1 = the smoothest quarter of the pixels).
//
// Definitions (pixel units, samples at pixel centres):
//   local variance  variance of the luma (Rec. 601) in the 5x5 window around
//                   a pixel, clamped at the border
//   Q1..Q4          the pixel's quartile of local variance over the image
//                   (Q1: at most the 25th percentile, so on piecewise-flat
//                   images every flat pixel is in Q1, however many)
//   region of an edge or triangle: the highest quartile among its vertices,
//                   so "in Q1" means every vertex sits in a smooth window
//   created edge    an edge absent from the initial Delaunay mesh
//   non-Delaunay    the opposite vertex lies strictly inside the
//                   circumcircle of a triangle of the edge (exact in double
//                   for pixel centres: all differences are integers)
//   thin triangle   longest edge / height on it > 4, i.e. L^2 > 8 area (the
//                   Delaunay triangles of a grid have 2)

#include "image/annealing.hpp"
#include "eval/classic_resize.hpp"
#include "core/costs.hpp"
#include "util/error.hpp"
#include "io/image_io.hpp"
#include "image/image_mesh.hpp"
#include "image/lookahead.hpp"
#include "image/mesh_view.hpp"
#include "image/optimizer.hpp"
#include "image/rasterizer.hpp"
#include "eval/synthetic_scenes.hpp"
#include "image/triangulation.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <unordered_set>
#include <vector>

namespace {

using namespace ddt;

// The channels that drive the flips, as upscale() takes them by default:
// every colour channel, the cost summed over them.
std::vector<float> drive_values(const Image& img, int& K) {
  K = std::min(img.channels, 3);
  std::vector<float> v(img.pixel_count() * K);
  for (std::size_t i = 0; i < img.pixel_count(); ++i)
    for (int k = 0; k < K; ++k) v[i * K + k] = img.pixels[i * img.channels + k];
  return v;
}

Mesh2 initial_mesh(const Image& img) { return delaunay_triangulation(pixel_centres(img.width, img.height)); }

// Quartile (0..3) of each pixel's local luma variance.
std::vector<int> variance_quartiles(const Image& img) {
  const int w = img.width, h = img.height;
  std::vector<double> luma(img.pixel_count());
  for (std::size_t i = 0; i < luma.size(); ++i) {
    const float* p = &img.pixels[i * img.channels];
    luma[i] = img.channels >= 3 ? 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2] : p[0];
  }
  std::vector<double> var(luma.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0, s2 = 0;
      int n = 0;
      for (int j = std::max(0, y - 2); j <= std::min(h - 1, y + 2); ++j)
        for (int i = std::max(0, x - 2); i <= std::min(w - 1, x + 2); ++i) {
          const double v = luma[static_cast<std::size_t>(j) * w + i];
          s += v, s2 += v * v, ++n;
        }
      var[static_cast<std::size_t>(y) * w + x] = std::max(0.0, s2 / n - (s / n) * (s / n));
    }
  std::vector<double> sorted = var;
  std::sort(sorted.begin(), sorted.end());
  const double q1 = sorted[sorted.size() / 4], q2 = sorted[sorted.size() / 2], q3 = sorted[3 * sorted.size() / 4];
  std::vector<int> quartile(var.size());
  for (std::size_t i = 0; i < var.size(); ++i)
    quartile[i] = var[i] <= q1 ? 0 : var[i] <= q2 ? 1 : var[i] <= q3 ? 2 : 3;
  return quartile;
}

std::uint64_t edge_key(index_t u, index_t v) {
  if (u > v) std::swap(u, v);
  return (static_cast<std::uint64_t>(u) << 32) | static_cast<std::uint32_t>(v);
}

std::unordered_set<std::uint64_t> edge_set(const Mesh2& m) {
  std::unordered_set<std::uint64_t> s;
  for (index_t e = 0; e < m.half_edge_count(); ++e) s.insert(edge_key(m.tri[e], m.tri[next_edge(e)]));
  return s;
}

// d strictly inside the circumcircle of the counter-clockwise (a, b, c).
bool in_circle(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const double adx = a.x - d.x, ady = a.y - d.y, bdx = b.x - d.x, bdy = b.y - d.y, cdx = c.x - d.x, cdy = c.y - d.y;
  const double det = (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) - (bdx * bdx + bdy * bdy) * (adx * cdy - cdx * ady) +
                     (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
  return det > 0;
}

struct RegionCounts {
  std::array<long long, 4> created{}, non_delaunay{}, thin{}, flips{};
  long long created_total() const { return created[0] + created[1] + created[2] + created[3]; }
};

RegionCounts count_regions(const Mesh2& m, const std::unordered_set<std::uint64_t>& initial_edges,
                           const std::vector<int>& quartile) {
  RegionCounts r;
  for (index_t e = 0; e < m.half_edge_count(); ++e) {
    const index_t u = m.tri[e], v = m.tri[next_edge(e)];
    if (m.opp[e] != no_edge && m.opp[e] < e) continue;  // each edge once
    const int q = std::max(quartile[u], quartile[v]);
    if (!initial_edges.count(edge_key(u, v))) ++r.created[q];
    if (m.opp[e] != no_edge) {
      const Point2 &a = m.points[u], &b = m.points[v], &c = m.points[m.tri[prev_edge(e)]];
      const Point2& d = m.points[m.tri[prev_edge(m.opp[e])]];
      if (in_circle(a, b, c, d)) ++r.non_delaunay[q];
    }
  }
  for (index_t t = 0; t < m.triangle_count(); ++t) {
    const index_t* v = &m.tri[3 * t];
    const Point2 &a = m.points[v[0]], &b = m.points[v[1]], &c = m.points[v[2]];
    auto len2 = [](const Point2& p, const Point2& q) { return (p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y); };
    const double longest2 = std::max({len2(a, b), len2(b, c), len2(c, a)});
    const double area = 0.5 * std::abs(signed_area2(a, b, c));
    if (longest2 > 8 * area) ++r.thin[std::max({quartile[v[0]], quartile[v[1]], quartile[v[2]]})];
  }
  return r;
}

// A file, or "scene:NAME@WxH" (a synthetic scene rendered at W x H).
Image load(const std::string& spec) {
  if (spec.rfind("scene:", 0) != 0) return read_image(spec).image;
  const std::size_t at = spec.find('@'), x = spec.find('x', at == std::string::npos ? 0 : at);
  if (at == std::string::npos || x == std::string::npos) throw Error("write a scene as scene:NAME@WxH, not " + spec);
  return render_scene(find_scene(spec.substr(6, at - 6)), std::stoi(spec.substr(at + 1, x - at - 1)),
                      std::stoi(spec.substr(x + 1)));
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string quarters(const std::array<long long, 4>& a) {
  char s[96];
  std::snprintf(s, sizeof s, "%lld / %lld / %lld / %lld", a[0], a[1], a[2], a[3]);
  return s;
}

std::string percent(long long part, long long whole) {
  char s[32];
  std::snprintf(s, sizeof s, "%.0f%%", whole ? 100.0 * part / whole : 0.0);
  return s;
}

int run_smooth(const std::vector<std::string>& images, const std::vector<std::string>& costs,
               const std::vector<std::uint64_t>& seeds, const AnnealOptions& schedule, bool with_lookahead) {
  for (const std::string& path : images) {
    const Image img = load(path);
    int K = 0;
    const std::vector<float> values = drive_values(img, K);
    const std::vector<int> quartile = variance_quartiles(img);
    const Mesh2 start = initial_mesh(img);
    const auto initial_edges = edge_set(start);
    const RegionCounts base = count_regions(start, initial_edges, quartile);
    std::printf("\n%s (%dx%d): the initial Delaunay mesh has %s non-Delaunay edges and %s thin triangles "
                "(Q1 / Q2 / Q3 / Q4)\n\n",
                std::filesystem::path(path).filename().string().c_str(), img.width, img.height,
                quarters(base.non_delaunay).c_str(), quarters(base.thin).c_str());
    std::printf("| cost | optimizer | final cost | flips (in Q1) | created edges Q1 / Q2 / Q3 / Q4 | in Q1 | "
                "non-Delaunay edges Q1 / Q2 / Q3 / Q4 | thin triangles Q1 / Q2 / Q3 / Q4 | seconds |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|\n");
    for (const std::string& cost_name : costs) {
      const CostFunction& cost = find_cost(cost_name);
      auto row = [&](const std::string& optimizer, const Mesh2& m, double final_cost, long long flips,
                     const std::string& flips_q1, double seconds) {
        const RegionCounts r = count_regions(m, initial_edges, quartile);
        std::printf("| %s | %s | %.4f | %lld%s | %s | %s | %s | %s | %.2f |\n", cost_name.c_str(), optimizer.c_str(),
                    final_cost, flips, flips_q1.c_str(), quarters(r.created).c_str(),
                    percent(r.created[0], r.created_total()).c_str(), quarters(r.non_delaunay).c_str(),
                    quarters(r.thin).c_str(), seconds);
        std::fflush(stdout);
      };
      {
        Mesh2 m = start;
        const auto t0 = std::chrono::steady_clock::now();
        const LawsonStats st = optimize_lawson(m, values, K, cost);
        row("lawson", m, st.cost_after, st.flips, "", seconds_since(t0));
      }
      if (with_lookahead) {
        Mesh2 m = start;
        const auto t0 = std::chrono::steady_clock::now();
        const LookaheadStats st = optimize_lookahead(m, values, K, cost);
        row("lookahead", m, st.cost_after, st.lawson_flips + 2 * st.pairs, "", seconds_since(t0));
      }
      for (std::uint64_t seed : seeds) {
        Mesh2 m = start;
        AnnealOptions opt = schedule;
        opt.seed = seed;
        long long flips_q1 = 0;
        opt.on_flip = [&](const Mesh2& mesh, index_t e) {
          flips_q1 += std::max(quartile[mesh.tri[e]], quartile[mesh.tri[next_edge(e)]]) == 0;
        };
        const auto t0 = std::chrono::steady_clock::now();
        const AnnealStats st = optimize_anneal(m, values, K, cost, opt);
        row("anneal, seed " + std::to_string(seed), m, st.cost_after, st.accepted + st.lawson.flips,
            " (" + std::to_string(flips_q1) + ")", seconds_since(t0));
      }
    }
  }
  return 0;
}

// Images of equal height side by side, `gap` black pixels apart (RGB).
Image beside(const std::vector<Image>& parts, int gap) {
  int w = -gap;
  for (const Image& p : parts) w += p.width + gap;
  Image out(w, parts.front().height, 3, 0.0f);
  int x0 = 0;
  for (const Image& p : parts) {
    for (int y = 0; y < p.height; ++y)
      for (int x = 0; x < p.width; ++x)
        for (int c = 0; c < 3; ++c) out.at(x0 + x, y, c) = p.at(x, y, std::min(c, p.channels - 1));
    x0 += p.width + gap;
  }
  return out;
}

// Images of equal width one above the other, `gap` black pixels apart.
Image above(const std::vector<Image>& parts, int gap) {
  int h = -gap;
  for (const Image& p : parts) h += p.height + gap;
  Image out(parts.front().width, h, 3, 0.0f);
  int y0 = 0;
  for (const Image& p : parts) {
    for (int y = 0; y < p.height; ++y)
      for (int x = 0; x < p.width; ++x)
        for (int c = 0; c < 3; ++c) out.at(x, y0 + y, c) = p.at(x, y, std::min(c, p.channels - 1));
    y0 += p.height + gap;
  }
  return out;
}

// "WxH+X+Y" (oiiotool's --cut) of `img`; empty text: all of it.
Image crop(const Image& img, const std::string& spec) {
  if (spec.empty()) return img;
  int w = 0, h = 0, x = 0, y = 0;
  if (std::sscanf(spec.c_str(), "%dx%d+%d+%d", &w, &h, &x, &y) != 4 || w < 2 || h < 2 || x < 0 || y < 0 ||
      x + w > img.width || y + h > img.height)
    throw Error("--crop wants WxH+X+Y inside the " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                " image, not '" + spec + "'");
  Image out(w, h, img.channels);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      for (int c = 0; c < img.channels; ++c) out.at(i, j, c) = img.at(x + i, y + j, c);
  return out;
}

RenderGrid scaled_grid(const Image& img, double scale) {
  RenderGrid grid;
  grid.width = static_cast<int>(std::lround(img.width * scale));
  grid.height = static_cast<int>(std::lround(img.height * scale));
  grid.scale_x = static_cast<double>(grid.width) / img.width;
  grid.scale_y = static_cast<double>(grid.height) / img.height;
  return grid;
}

// Figure 1: bicubic (left) beside DDT with `cost` and Lawson (right).
int run_fig1(const std::string& path, const std::string& crop_spec, double scale, const std::string& cost_name,
             const std::string& out) {
  const Image img = crop(read_image(path).image, crop_spec);
  const CostFunction& cost = find_cost(cost_name);
  int K = 0;
  const std::vector<float> values = drive_values(img, K);
  Mesh2 m = initial_mesh(img);
  optimize_lawson(m, values, K, cost);
  const RenderGrid grid = scaled_grid(img, scale);
  const Image ddt_img = render_mesh(m, img.pixels, img.channels, grid);
  const Image bicubic = classic_resize(img, grid.width, grid.height, "bicubic");
  write_image(out, beside({bicubic, ddt_img}, 4), SampleFormat::uint8);
  std::printf("fig1: %s, %dx%d at x%g\n", out.c_str(), img.width, img.height, scale);
  return 0;
}

// A one-pixel white frame around `r` (input pixels) on an image enlarged by `scale`.
void frame(Image& img, const PixelRegion& r, double scale) {
  const int x0 = static_cast<int>(r.x * scale), y0 = static_cast<int>(r.y * scale);
  const int x1 = std::min(img.width, static_cast<int>((r.x + r.width) * scale)) - 1;
  const int y1 = std::min(img.height, static_cast<int>((r.y + r.height) * scale)) - 1;
  auto set = [&](int x, int y) {
    for (int c = 0; c < std::min(img.channels, 3); ++c) img.at(x, y, c) = 1.0f;
  };
  for (int x = x0; x <= x1; ++x) set(x, y0), set(x, y1);
  for (int y = y0; y <= y1; ++y) set(x0, y), set(x1, y);
}

// Figure 8: rows Lawson and annealing; left the reconstruction at `scale`
// (the region of the mesh view framed in white), right the mesh over the
// input pixels of `mesh_roi` (the edges the optimizer created in orange),
// enlarged to the reconstruction's height.
int run_fig8(const std::string& path, const std::string& crop_spec, double scale, const std::string& cost_name,
             const AnnealOptions& schedule, const std::string& out, PixelRegion mesh_roi) {
  const Image img = crop(read_image(path).image, crop_spec);
  const CostFunction& cost = find_cost(cost_name);
  int K = 0;
  const std::vector<float> values = drive_values(img, K);
  const Mesh2 start = initial_mesh(img);
  const RenderGrid grid = scaled_grid(img, scale);
  if (mesh_roi.width == 0) mesh_roi = {0, 0, img.width, img.height};
  const int magnification = std::max(1, grid.height / mesh_roi.height);
  const std::string mesh_tmp = out + ".mesh.tmp.png";
  std::vector<Image> rows;
  for (const std::string optimizer : {"lawson", "anneal"}) {
    Mesh2 m = start;
    if (optimizer == "lawson") {
      const LawsonStats st = optimize_lawson(m, values, K, cost);
      std::printf("fig8 lawson: %lld flips, cost %.6g -> %.6g\n", st.flips, st.cost_before, st.cost_after);
    } else {
      const AnnealStats st = optimize_anneal(m, values, K, cost, schedule);
      std::printf("fig8 anneal (seed %llu): T0 %.4g, %lld flips (%lld uphill) + %lld Lawson flips, "
                  "cost %.6g -> %.6g -> %.6g\n",
                  static_cast<unsigned long long>(schedule.seed), st.initial_temperature, st.accepted, st.uphill,
                  st.lawson.flips, st.cost_before, st.cost_annealed, st.cost_after);
    }
    write_mesh_view(mesh_tmp, m, &start, img, mesh_roi, magnification);
    const Image mesh_img = read_image(mesh_tmp).image;
    std::filesystem::remove(mesh_tmp);
    Image rendered = render_mesh(m, img.pixels, img.channels, grid);
    if (mesh_roi.width < img.width || mesh_roi.height < img.height) frame(rendered, mesh_roi, scale);
    rows.push_back(beside({rendered, mesh_img}, 4));
  }
  write_image(out, above(rows, 4), SampleFormat::uint8);
  std::printf("fig8: %s\n", out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"paper_experiments: the 2D experiments of Tóth et al. (figure 8 and where the flips land)"};
  app.require_subcommand(1);
  AnnealOptions schedule;
  auto add_schedule = [&](CLI::App* sub) {
    sub->add_option("--anneal-steps", schedule.temperature_steps, "temperature steps")->capture_default_str();
    sub->add_option("--anneal-cooling", schedule.cooling, "cooling factor")->capture_default_str();
    sub->add_option("--anneal-moves", schedule.moves_per_edge, "proposals per edge and step")->capture_default_str();
    sub->add_option("--anneal-accept", schedule.initial_acceptance, "automatic T0's acceptance")->capture_default_str();
  };

  auto* fig1 = app.add_subcommand("fig1", "bicubic beside DDT (Lawson) at --scale");
  auto* fig8 = app.add_subcommand("fig8", "Lawson above annealing: reconstructions at --scale and meshes");
  std::string image, out, crop_spec, cost = "sederberg";
  double scale = 6;
  for (CLI::App* sub : {fig1, fig8}) {
    sub->add_option("image", image, "input image")->required();
    sub->add_option("--crop", crop_spec, "WxH+X+Y: the part of the image to use (default: all)");
    sub->add_option("--scale", scale, "magnification of the reconstructions")->capture_default_str();
    sub->add_option("--cost", cost, "flip cost")->capture_default_str();
    sub->add_option("--out", out, "the figure (PNG)")->required();
  }
  fig8->add_option("--seed", schedule.seed, "annealing seed")->capture_default_str();
  std::string mesh_roi;
  fig8->add_option("--mesh-roi", mesh_roi, "x,y,w,h in the crop: the part the mesh view shows (default: all)");
  add_schedule(fig8);

  auto* smooth = app.add_subcommand("smooth", "where the flips land, by local variance");
  std::vector<std::string> images, costs{"sederberg"};
  std::vector<std::uint64_t> seeds{1};
  smooth->add_option("images", images, "input images, or scene:NAME@WxH")->required();
  smooth->add_option("--cost", costs, "costs, comma-separated")->delimiter(',')->capture_default_str();
  smooth->add_option("--seeds", seeds, "annealing seeds, comma-separated")->delimiter(',')->capture_default_str();
  bool lookahead = false;
  smooth->add_flag("--lookahead", lookahead, "also a row for the look-ahead optimizer (lookahead.hpp)");
  add_schedule(smooth);

  CLI11_PARSE(app, argc, argv);
  try {
    if (fig1->parsed()) return run_fig1(image, crop_spec, scale, cost, out);
    if (fig8->parsed())
      return run_fig8(image, crop_spec, scale, cost, schedule, out, mesh_roi.empty() ? PixelRegion{} : parse_region(mesh_roi));
    return run_smooth(images, costs, seeds, schedule, lookahead);
  } catch (const std::exception& e) {
    std::cerr << "paper_experiments: " << e.what() << "\n";
    return 1;
  }
}
