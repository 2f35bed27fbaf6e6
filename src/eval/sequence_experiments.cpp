#include "eval/sequence_experiments.hpp"

#include "eval/sequence_scenes.hpp"
#include "io/frame_sequence.hpp"
#include "io/image_io.hpp"
#include "util/child_process.hpp"
#include "util/error.hpp"
#include "util/timing.hpp"
#include "volume/sequence_upscale.hpp"


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <numeric>


namespace fs = std::filesystem;

namespace ddt {
namespace {

double frame_psnr(const Image& a, const Image& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    const double d = double(a.pixels[i]) - b.pixels[i];
    sum += d * d;
  }
  const double mse = sum / double(a.pixels.size());
  return mse > 0 ? 10 * std::log10(1.0 / mse) : 99.0;
}

Image quantized(Image f) {
  for (float& v : f.pixels) v = std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f;
  return f;
}

// A private directory under the system's temporary one, removed with it.
struct TemporaryDirectory {
  fs::path path;
  TemporaryDirectory() {
    std::string name = (fs::temp_directory_path() / "ddtscale-seq-XXXXXX").string();
    if (!::mkdtemp(name.data())) throw Error("cannot make a temporary directory for ffmpeg");
    path = name;
  }
  ~TemporaryDirectory() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

bool have_program(const std::string& program) { return run_program({program, "-version"}) == 0; }

// FFmpeg's minterpolate on the frames (8-bit PNG through a temporary
// directory). The input is read at 1 frame a second and written at
// p / q frames a second, so output frame g is the instant g q / p; the last
// input frame is given twice because the filter stops before the last
// input's instant.
std::vector<Image> minterpolate(const std::vector<Image>& frames, int p, int q, const std::string& ffmpeg) {
  TemporaryDirectory dir;
  const FramePattern in = parse_frame_pattern((dir.path / "in_%04d.png").string());
  for (std::size_t k = 0; k <= frames.size(); ++k)
    write_image(in.path(static_cast<int>(k)), frames[std::min(k, frames.size() - 1)], SampleFormat::uint8);
  const std::string out = (dir.path / "out_%04d.png").string();
  const int status = run_program({ffmpeg, "-nostdin", "-loglevel", "error", "-y", "-framerate", "1", "-start_number",
                                  "0", "-i", in.text, "-vf",
                                  "minterpolate=fps=" + std::to_string(p) + "/" + std::to_string(q) + ":mi_mode=mci",
                                  "-start_number",
                                  "0", out});
  if (status != 0) throw Error("ffmpeg's minterpolate failed (exit status " + std::to_string(status) + ")");
  const FramePattern made = parse_frame_pattern(out);
  std::vector<Image> result;
  const int count = sequence_output_frames(static_cast<int>(frames.size()), double(p) / q);
  for (int k = 0; k < count; ++k) {
    if (!fs::exists(made.path(k)))
      throw Error("ffmpeg's minterpolate made " + std::to_string(k) + " frames, not " + std::to_string(count));
    Image f = read_image(made.path(k)).image;
    if (f.channels > frames[0].channels) {  // grey written back as RGB
      Image g(f.width, f.height, frames[0].channels);
      for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x)
          for (int c = 0; c < g.channels; ++c) g.at(x, y, c) = f.at(x, y, c);
      f = std::move(g);
    }
    result.push_back(std::move(f));
  }
  return result;
}

std::vector<Image> ddt_frames(const std::vector<Image>& frames, double time_scale, const std::string& method,
                              double presmooth) {
  SequenceUpscaleOptions o;
  if (presmooth >= 0) {  // the sigma asked for, whatever the mesh
    o.volume.presmooth = {presmooth, presmooth, 0.0};
    o.presmooth_along_motion = -1;
  }
  const std::size_t colon = method.find(':');
  const std::string base = method.substr(0, colon);
  if (colon != std::string::npos) o.volume.cost = method.substr(colon + 1);
  o.volume.method = base == "delaunay" ? VolumeMethod::delaunay : VolumeMethod::ddt;
  if (base == "ddt-cubic") o.volume.render = Render::cubic;
  if (base == "ddt-unsmoothed") {
    o.volume.presmooth = {};
    o.presmooth_along_motion = -1;
  }
  if (base == "ddt-all-flips") o.volume.keep_slow_texture = false;
  if (base == "ddt-lattice") o.shear_dominant_motion = false;
  std::vector<Image> out;
  const Image& f0 = frames.front();
  upscale_sequence(
      static_cast<int>(frames.size()), f0.width, f0.height, f0.channels, [&](int k) { return frames[k]; }, f0.width,
      f0.height, time_scale, o, [&](Image f, int) { out.push_back(std::move(f)); });
  return out;
}

// The space-time slice through row y: x across, one row per frame.
Image xt_slice(const std::vector<Image>& frames, int y) {
  Image out(frames[0].width, static_cast<int>(frames.size()), frames[0].channels);
  for (int t = 0; t < out.height; ++t)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < out.channels; ++c) out.at(x, t, c) = frames[t].at(x, y, c);
  return out;
}

// The images (of one size) left to right, 2 white pixels apart.
Image row_of(const std::vector<Image>& images) {
  const Image& first = images.front();
  const int gap = 2, n = static_cast<int>(images.size());
  Image out(n * first.width + (n - 1) * gap, first.height, first.channels, 1.0f);
  for (int i = 0; i < n; ++i)
    for (int y = 0; y < first.height; ++y)
      for (int x = 0; x < first.width; ++x)
        for (int c = 0; c < first.channels; ++c) out.at(i * (first.width + gap) + x, y, c) = images[i].at(x, y, c);
  return out;
}

}  // namespace

std::vector<Image> blend_frames(const std::vector<Image>& frames, double time_scale) {
  std::vector<Image> out;
  const int count = sequence_output_frames(static_cast<int>(frames.size()), time_scale);
  for (int g = 0; g < count; ++g) {
    const double u = g / time_scale;
    const std::size_t k = std::min(frames.size() - 1, static_cast<std::size_t>(std::floor(u + 1e-9)));
    const float w = static_cast<float>(u - double(k));
    if (k + 1 >= frames.size() || w <= 1e-6f) {
      out.push_back(frames[k]);
      continue;
    }
    Image f = frames[k];
    for (std::size_t i = 0; i < f.pixels.size(); ++i)
      f.pixels[i] = (1 - w) * frames[k].pixels[i] + w * frames[k + 1].pixels[i];
    out.push_back(std::move(f));
  }
  return out;
}

std::vector<SequenceExperimentRow> run_sequence_experiments(const SequenceExperimentOptions& o) {
  if (o.input_frames < 2) throw Error("the experiments need at least 2 input frames");
  if (o.output_step < 1 || o.time_scale <= o.output_step)
    throw Error("the experiments need a frame-rate factor above 1 (time scale " + std::to_string(o.time_scale) + "/" +
                std::to_string(o.output_step) + ")");
  const int p = o.time_scale, q = o.output_step;
  const double factor = double(p) / q;
  if (!o.picture_dir.empty() && !fs::is_directory(o.picture_dir))
    throw Error("no directory '" + o.picture_dir + "' for the pictures");
  for (const std::string& m : o.methods) {
    const std::string base = m.substr(0, m.find(':'));
    if (base != "blend" && base != "minterpolate" && base != "delaunay" && base != "ddt" && base != "ddt-cubic" &&
        base != "ddt-unsmoothed" && base != "ddt-all-flips" && base != "ddt-lattice")
      throw Error("unknown method '" + m +
                  "' (valid: blend, minterpolate, delaunay, ddt, ddt-cubic, ddt-unsmoothed, ddt-all-flips, ddt-lattice, ddt:COST)");
  }
  auto log = [&](const std::string& line) {
    if (o.log) o.log(line);
  };
  Image photo;
  const bool has_ffmpeg = std::any_of(o.methods.begin(), o.methods.end(),
                                      [](const std::string& m) { return m == "minterpolate"; }) &&
                          have_program(o.ffmpeg);
  std::vector<SequenceExperimentRow> rows;
  for (const std::string& name : o.scenes) {
    const SequenceScene& scene = find_sequence_scene(name);
    if (scene.photo && o.photo.empty()) {
      log("skipped " + name + ": no photograph given");
      continue;
    }
    if (scene.photo && photo.empty()) photo = read_image(o.photo).image;
    // Full-rate frame t is the instant t / p of the kept frames; output
    // frame g (at g / factor) is full-rate frame g q.
    const int made_count = sequence_output_frames(o.input_frames, factor);
    std::vector<Image> truth, input;
    for (int t = 0; t <= (o.input_frames - 1) * p; ++t) {
      if (t % p != 0 && t % q != 0) continue;
      const Image frame = render_sequence_frame(name, t * o.speed, o.width, o.height, &photo);
      if (t % p == 0) input.push_back(quantized(frame));
      if (t % q == 0) truth.push_back(frame);
    }
    std::vector<std::vector<Image>> shown = {truth};
    for (const std::string& m : o.methods) {
      if (m == "minterpolate" && !has_ffmpeg) {
        log("skipped minterpolate: no '" + o.ffmpeg + "' program found");
        continue;
      }
      const auto t0 = Clock::now();
      std::vector<Image> made = m == "blend"          ? blend_frames(input, factor)
                                : m == "minterpolate" ? minterpolate(input, p, q, o.ffmpeg)
                                                      : ddt_frames(input, factor, m, o.presmooth);
      SequenceExperimentRow row{name, m, 0, std::numeric_limits<double>::infinity(), seconds_since(t0)};
      int count = 0;
      for (int g = 0; g < made_count; ++g) {
        if ((g * q) % p == 0) continue;  // a kept frame
        const double psnr = frame_psnr(made[g], truth[g]);
        row.psnr += psnr, row.worst_psnr = std::min(row.worst_psnr, psnr), ++count;
      }
      row.psnr /= count;
      char line[200];
      std::snprintf(line, sizeof line, "%s %s: mean PSNR %.2f dB (worst frame %.2f), %.2f s", name.c_str(), m.c_str(),
                    row.psnr, row.worst_psnr, row.seconds);
      log(line);
      rows.push_back(row);
      shown.push_back(std::move(made));
    }
    if (!o.picture_dir.empty()) {
      // The made frame nearest halfway after the middle kept frame.
      const int t = std::min(made_count - 1, static_cast<int>(std::lround(((o.input_frames / 2) * p + p / 2.0) / q)));
      std::vector<Image> frames, slices;
      for (const auto& seq : shown) frames.push_back(seq[t]), slices.push_back(xt_slice(seq, o.height / 2));
      const fs::path dir(o.picture_dir);
      write_image((dir / (name + "-frames.png")).string(), row_of(frames), SampleFormat::uint8);
      write_image((dir / (name + "-xt.png")).string(), row_of(slices), SampleFormat::uint8);
    }
  }
  return rows;
}

std::string sequence_experiment_table(const std::vector<SequenceExperimentRow>& rows) {
  std::string out = "| scene | method | mean PSNR (dB) | worst frame (dB) | seconds |\n|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    char line[200];
    std::snprintf(line, sizeof line, "| %s | %s | %.2f | %.2f | %.2f |\n", r.scene.c_str(), r.method.c_str(), r.psnr,
                  r.worst_psnr, r.seconds);
    out += line;
  }
  return out;
}

}  // namespace ddt
