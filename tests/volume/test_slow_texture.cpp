// The slow-texture detector of image sequences and what it does to the
// flips: slow fine texture stays paired along time, moving edges are left
// to the flips.

#include "eval/sequence_scenes.hpp"
#include "util/error.hpp"
#include "volume/sequence_upscale.hpp"
#include "volume/slow_texture.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace ddt;

namespace {

// Fine texture: uniform noise averaged over 2x2 pixels.
Image texture_photo(int size, int channels) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0, 1);
  Image noise(size + 1, size + 1, channels);
  for (float& v : noise.pixels) v = u(rng);
  Image photo(size, size, channels);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < channels; ++c)
        photo.at(x, y, c) =
            0.25f * (noise.at(x, y, c) + noise.at(x + 1, y, c) + noise.at(x, y + 1, c) + noise.at(x + 1, y + 1, c));
  return photo;
}

// Frames of a scene at the instants first, first + dt, ... (the scenes
// move 0.5 px an instant along x for the pan, (1, 0.5) for the disk).
std::vector<Image> frames_at(const std::string& scene, int count, double dt, int size, const Image* photo = nullptr) {
  std::vector<Image> frames;
  for (int k = 0; k < count; ++k) frames.push_back(render_sequence_frame(scene, k * dt, size, size, photo));
  return frames;
}

std::vector<float> stacked(const std::vector<Image>& frames) {
  std::vector<float> values;
  for (const Image& f : frames) values.insert(values.end(), f.pixels.begin(), f.pixels.end());
  return values;
}

double flagged_share(const std::vector<char>& flags, std::size_t first, std::size_t count) {
  return double(std::count(flags.begin() + first, flags.begin() + first + count, char(1))) / count;
}

std::vector<Image> run(const std::vector<Image>& in, int time_scale, bool keep_slow_texture) {
  SequenceUpscaleOptions o;
  o.volume.keep_slow_texture = keep_slow_texture;
  const Image& f = in.front();
  std::vector<Image> out;
  upscale_sequence(
      static_cast<int>(in.size()), f.width, f.height, f.channels, [&](int k) { return in.at(k); }, f.width, f.height,
      time_scale, o, [&](Image frame, int) { out.push_back(std::move(frame)); });
  return out;
}

// PSNR (peak 1) of the frames between the kept ones.
double made_psnr(const std::vector<Image>& out, const std::vector<Image>& truth, int time_scale) {
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t g = 0; g < out.size(); ++g) {
    if (g % time_scale == 0) continue;
    for (std::size_t i = 0; i < out[g].pixels.size(); ++i, ++n) sum += std::pow(double(out[g].pixels[i]) - truth[g].pixels[i], 2);
  }
  return 10 * std::log10(n / sum);
}

}  // namespace

TEST_CASE("slow_texture_samples: texture moving half a pixel is flagged - texture moving 4 pixels, edges and flat "
          "areas are not") {
  const int size = 40;
  const std::size_t frame = std::size_t(size) * size;
  const Image photo = texture_photo(160, 3);
  const std::vector<char> slow = slow_texture_samples(stacked(frames_at("pan", 3, 1, size, &photo)), size, size, 3, 3);
  REQUIRE(slow.size() == 3 * frame);
  CHECK(flagged_share(slow, 0, frame) > 0.8);
  CHECK(flagged_share(slow, 2 * frame, frame) == 0);  // the last frame: no next one
  const std::vector<char> fast = slow_texture_samples(stacked(frames_at("pan", 3, 8, size, &photo)), size, size, 3, 3);
  CHECK(flagged_share(fast, 0, 2 * frame) < 0.1);
  // A disk's rim is an edge, its inside and outside flat: nothing, at any speed.
  for (const double dt : {0.5, 4.0}) {
    const std::vector<char> disk = slow_texture_samples(stacked(frames_at("disk", 3, dt, size)), size, size, 3, 1);
    CHECK(std::count(disk.begin(), disk.end(), char(1)) == 0);
  }
  CHECK_THROWS_AS(slow_texture_samples(std::vector<float>(10), size, size, 3, 3), Error);
  CHECK_THROWS_AS(slow_texture_samples({}, 0, size, 3, 3), Error);
}

TEST_CASE("upscale_sequence: slow texture stays paired along time (several dB over flipping it) - a moving edge's "
          "frames are the unrestricted ones bit for bit") {
  const int size = 32, scale = 4, kept = 4;
  const Image photo = texture_photo(128, 1);
  // A pan of 0.5 px between kept frames: truth at every made instant.
  const std::vector<Image> truth = frames_at("pan", (kept - 1) * scale + 1, 0.25, size, &photo);
  std::vector<Image> in;
  for (int k = 0; k < kept; ++k) in.push_back(truth[std::size_t(k * scale)]);
  const double kept_pairs = made_psnr(run(in, scale, true), truth, scale);
  const double flipped = made_psnr(run(in, scale, false), truth, scale);
  CAPTURE(kept_pairs);
  CAPTURE(flipped);
  CHECK(kept_pairs > flipped + 3);

  const std::vector<Image> disk = frames_at("disk", kept, scale, size);
  const std::vector<Image> a = run(disk, scale, true), b = run(disk, scale, false);
  REQUIRE(a.size() == b.size());
  for (std::size_t g = 0; g < a.size(); ++g) CHECK(a[g].pixels == b[g].pixels);
}
