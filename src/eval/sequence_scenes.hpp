#pragma once
// Moving test scenes with known truth for frame-rate upsampling: every
// frame is rendered exactly (box-filtered: a pixel is the average of the
// scene over its footprint) at any instant, so a sequence rendered at the
// full frame rate is the truth, and every s-th frame of it the input.
//
// Scenes (t in frames of the full rate; speeds in pixels a frame at the
// rendered width, so the motion between kept frames is s times that):
//   disk     the bright disk of synthetic_scenes.hpp (radius 0.2), moving
//            right and down at (1, 0.5) px a frame
//   bar      a dark bar 0.06 wide and 0.7 long turning about the centre at
//            1 degree a frame (about 0.8 px a frame at its ends at 128^2)
//   strokes  the 'A' and 'S' strokes of synthetic_scenes.hpp moving left
//            and down at (0.75, 0.5) px a frame
//   pan      a photograph panned at (0.5, 0.25) px a frame, each pixel the
//            average of a 2x2 block of the photograph's pixels at that
//            sub-pixel position
//   zoom     the same photograph, zoomed in about its centre by 0.5 % a
//            frame (footprints from 2 photograph pixels down)
// The first three move edges; pan and zoom need a
// photograph (any image; RGB or grey), of at least twice the frame size
// plus the motion.
//
// Errors: ddt::Error for an unknown scene (listing the valid ones), a bad
// size, or a photograph missing or too small.

#include "util/image.hpp"

#include <string>
#include <vector>

namespace ddt {

struct SequenceScene {
  std::string name;
  std::string description;
  bool photo = false;         // pan, zoom: rendered from a photograph
};

const std::vector<SequenceScene>& sequence_scenes();
const SequenceScene& find_sequence_scene(const std::string& name);

// The frame at instant t (full-rate frames from 0), width x height.
Image render_sequence_frame(const std::string& scene, double t, int width, int height,
                            const Image* photo = nullptr);

// Box filter of `photo` (its pixels constant squares) over the footprints
// of a width x height frame whose pixel (i, j) covers
// [x0 + i * footprint, x0 + (i + 1) * footprint] x [y0 + j * ..., ...]
// in photograph pixels. Throws when a footprint leaves the photograph.
Image box_resample(const Image& photo, double x0, double y0, double footprint, int width, int height);

}  // namespace ddt
