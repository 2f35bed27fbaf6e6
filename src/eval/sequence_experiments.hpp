#pragma once
// Frame-rate upsampling experiments with known truth (docs/sequences.md):
// each moving scene (sequence_scenes.hpp) is rendered at the full frame
// rate, (input_frames - 1) * time_scale + 1 frames; every time_scale-th
// frame is kept as the input (quantized to 8 bits, as a video stores it);
// each method rebuilds the full rate from the input, and the frames it
// made (those not in the input) are scored against the truth: mean PSNR
// over those frames (peak 1, all channels).
//
// Methods:
//   blend         frame blending, linear in time (what a plain frame-rate
//                 converter does)
//   minterpolate  FFmpeg's motion-compensated interpolation
//                 (ffmpeg -vf minterpolate=fps=...:mi_mode=mci), run as a
//                 program on the input written as 8-bit PNG frames; skipped
//                 with a note when no ffmpeg is found
//   delaunay      the initial tetrahedrization of (x, y, t), no flips
//   ddt           data-dependent tetrahedrization (sequence_upscale.hpp);
//                 "ddt:COST" picks the cost (plain ddt: variance)
//   ddt-cubic     ddt with the cubic render (plain ddt: the sequences'
//                 default render, linear)
//   ddt-unsmoothed  ddt without the graduated optimization (presmooth 0)
//
// Pictures (picture_dir set): <scene>-frames.png, the truth and each
// method at the frame halfway between the first two kept frames after the
// middle, side by side; <scene>-xt.png, the space-time slice (x across,
// time down) through the middle row, one column per method.
//
// Errors: ddt::Error (unknown scene or method, a photograph scene without
// a photograph, ffmpeg failing on its input).

#include "util/image.hpp"

#include <functional>
#include <string>
#include <vector>

namespace ddt {

struct SequenceExperimentOptions {
  int width = 128, height = 128;
  int input_frames = 17;
  int time_scale = 4;   // every time_scale-th frame of the full rate is kept as input
  int output_step = 1;  // and every output_step-th is made: a frame-rate factor of time_scale / output_step
  double speed = 1;  // multiplies the scenes' motion
  double presmooth = -1;  // >= 0: the ddt methods' --presmooth (ddt-unsmoothed stays 0); < 0: the default
  std::vector<std::string> scenes = {"disk", "bar", "strokes", "pan", "zoom"};
  std::vector<std::string> methods = {"blend", "minterpolate", "delaunay", "ddt"};
  std::string photo;        // path of the photograph for pan and zoom ("" skips them, with a note)
  std::string ffmpeg = "ffmpeg";
  std::string picture_dir;  // empty: no pictures
  std::function<void(const std::string&)> log;
};

struct SequenceExperimentRow {
  std::string scene;
  std::string method;
  double psnr = 0;          // mean over the made frames
  double worst_psnr = 0;    // of the worst made frame
  double seconds = 0;
};

std::vector<SequenceExperimentRow> run_sequence_experiments(const SequenceExperimentOptions& options);
std::string sequence_experiment_table(const std::vector<SequenceExperimentRow>& rows);

// Frames by linear blending between the two kept frames around each
// instant g / s: floor((T - 1) * s) + 1 frames.
std::vector<Image> blend_frames(const std::vector<Image>& frames, double time_scale);

}  // namespace ddt
