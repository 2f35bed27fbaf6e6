// Image sequences on the command line (volume/sequence_upscale.hpp):
//   ddtscale frames/in_%04d.png out/out_%04d.png --time-scale 4 [--scale 2]

#include "command_line.hpp"
#include "commands.hpp"
#include "output_options.hpp"
#include "whole_number.hpp"

#include "core/costs.hpp"
#include "eval/sequence_experiments.hpp"
#include "eval/sequence_scenes.hpp"
#include "io/safe_file.hpp"
#include "io/frame_sequence.hpp"
#include "io/video_io.hpp"
#include "util/error.hpp"
#include "util/progress.hpp"
#include "util/size_limits.hpp"
#include "util/thread_limit.hpp"
#include "util/timing.hpp"
#include "volume/sequence_upscale.hpp"

#include <CLI/CLI.hpp>
#include <OpenImageIO/imageio.h>

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

namespace {

// The memory a tile holds at least: its input and output frames as floats
// (8 bytes an output sample with the ownership count), the mesh (about
// 0.5 KB an input sample, docs/volumes.md) and the cubic render's gradients.
double tile_bytes(int width, int height, int channels, int out_width, int out_height, int tile_frames,
                  int margin_frames, double time_scale) {
  const double in = double(width) * height * (tile_frames + 2 * margin_frames + 1);
  const double out = double(out_width) * out_height * ((tile_frames + 2 * margin_frames) * time_scale + 1);
  return channels * (16.0 * in + 8.0 * out) + 512.0 * in;
}

}  // namespace

static int run_sequence_eval(int argc, char** argv) {
  ddt::SequenceExperimentOptions options;
  std::string table, size_spec;
  bool quiet = false;
  CLI::App app{"Frame-rate upsampling with known truth: moving scenes rendered (box-filtered) at the full frame\n"
               "rate, every SCALE-th frame kept (8-bit), the frames between rebuilt by each method and scored\n"
               "against the truth (mean PSNR over the rebuilt frames, peak 1). Prints a Markdown table.",
               "ddtscale sequence-eval"};
  app.add_option("--scenes", options.scenes, "scenes: disk, bar, strokes (moving edges), pan, zoom (a photograph)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--methods", options.methods,
                 "blend (linear in time), minterpolate (FFmpeg's motion-compensated interpolation, needs ffmpeg), "
                 "delaunay, ddt, ddt-cubic, ddt-unsmoothed (no graduated optimization), ddt-all-flips (slow texture flipped too), ddt-lattice (no shear along the dominant motion), ddt:COST")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--size", size_spec, "frame size, N or WxH (default 128)");
  app.add_option("--frames", options.input_frames, "input frames kept")->check(whole_number(2, 10000))->capture_default_str();
  app.add_option("--speed", options.speed, "multiplies every scene's motion (a sweep over speeds)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  std::string eval_time_scale = "4";
  app.add_option("--time-scale", eval_time_scale,
                 "frame-rate factor P or P/Q (whole numbers, P > Q): every P-th frame of the full rate is kept and "
                 "every Q-th made (5/2: 24 to 60 frames a second)")
      ->capture_default_str();
  app.add_option("--presmooth", options.presmooth,
                 "the ddt methods' --presmooth sigma (default: the sequence command's; ddt-unsmoothed stays 0)")
      ->check(CLI::Range(0.0, 16.0));
  app.add_option("--photo", options.photo,
                 "photograph for pan and zoom (any image at least 2 x the frame size plus the motion; without it "
                 "they are skipped), e.g. ../shared/datasets/Set14/baboon.png");
  app.add_option("--ffmpeg", options.ffmpeg, "the ffmpeg program")->capture_default_str();
  app.add_option("--pictures", options.picture_dir, "write <scene>-frames.png and <scene>-xt.png into this directory");
  app.add_option("--table", table, "also write the Markdown table to this file");
  app.add_flag("-q,--quiet", quiet, "print the table only");
  if (const auto status = parse_command_line(app, argc, argv, "ddtscale sequence-eval")) return *status;
  try {
    if (!size_spec.empty()) parse_width_height(size_spec, "--size", 4, 4096, options.width, options.height);
    {
      int p = 0, q = 1, used = 0;
      const int n = std::sscanf(eval_time_scale.c_str(), "%d%n/%d%n", &p, &used, &q, &used);
      if (n < 1 || static_cast<std::size_t>(used) != eval_time_scale.size() || q < 1 || p <= q || p > 64)
        throw ddt::Error("--time-scale wants P or P/Q, whole numbers with Q < P <= 64, got '" + eval_time_scale + "'");
      options.time_scale = p, options.output_step = q;
    }
    if (!quiet) options.log = [](const std::string& line) { std::cerr << line << "\n"; };
    const std::string text = ddt::sequence_experiment_table(ddt::run_sequence_experiments(options));
    std::cout << text;
    if (!table.empty()) ddt::write_file_atomically(table, text);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "ddtscale sequence-eval: " << e.what() << "\n";
    return 1;
  }
}

static int run_sequence_scene(int argc, char** argv) {
  std::string scene, output, size_spec = "128", photo;
  int frames = 65;
  CLI::App app{"Write a moving test scene as frames (box-filtered at every instant: the truth of sequence-eval).",
               "ddtscale sequence-scene"};
  app.add_option("scene", scene, "disk, bar, strokes, pan or zoom")->required();
  app.add_option("output", output, "frame pattern, e.g. disk/f_%04d.png (numbered from 0)")->required();
  app.add_option("--frames", frames, "frames to write")->check(whole_number(1, 100000))->capture_default_str();
  app.add_option("--size", size_spec, "frame size, N or WxH")->capture_default_str();
  app.add_option("--photo", photo, "photograph for pan and zoom");
  if (const auto status = parse_command_line(app, argc, argv, "ddtscale sequence-scene")) return *status;
  try {
    int w = 0, h = 0;
    parse_width_height(size_spec, "--size", 1, 16384, w, h);
    const ddt::SequenceScene& s = ddt::find_sequence_scene(scene);
    const ddt::FramePattern pattern = ddt::parse_frame_pattern(output);
    ddt::check_output_path(pattern.path(0), "");
    ddt::Image picture;
    if (s.photo) {
      if (photo.empty()) throw ddt::Error("the scene '" + scene + "' needs --photo");
      picture = ddt::read_image(photo).image;
    }
    ddt::FrameSequenceWriter writer(pattern, ddt::SampleFormat::uint8, -1, nullptr, {}, photo.empty() ? std::vector<std::string>{} : std::vector<std::string>{photo});
    for (int t = 0; t < frames; ++t) writer.write(t, ddt::render_sequence_frame(scene, t, w, h, &picture));
    writer.commit();
    std::cerr << pattern.path(0) << " .. " << pattern.path(frames - 1) << ": " << frames << " frames of " << w << "x"
              << h << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "ddtscale sequence-scene: " << e.what() << "\n";
    return 1;
  }
}

bool is_sequence_command(int argc, char** argv) {
  if (argc >= 2 && (std::string(argv[1]) == "sequence-eval" || std::string(argv[1]) == "sequence-scene")) return true;
  for (int i = 1; i < argc; ++i)
    if (argv[i][0] != '-' && (ddt::is_frame_pattern(argv[i]) || ddt::is_video_path(argv[i]))) return true;
  return false;
}

namespace {

// The sequence command's arguments, as given.
struct SequenceArguments {
  std::string input, output, size_spec, method = "ddt", cost = "variance", slopes = "mc4";
  std::string render = ddt::to_string(ddt::sequence_volume_defaults().render);
  double scale = 1;
  std::string time_scale_text = "1";
  int threads = 0;
  double tolerance = 1e-9;
  bool verbose = false, quiet = false, flip_slow_texture = false, slow_motion = false;
  ddt::SequenceUpscaleOptions options;
  OutputOptions writing;
  long long max_pixels = ddt::default_max_voxels;
  double presmooth = ddt::sequence_volume_defaults().presmooth[0];
  const CLI::Option* presmooth_given = nullptr;
  std::string motion = "auto", fps_text = "24";
  ddt::VideoEncoding video;
};

void add_sequence_options(CLI::App& app, SequenceArguments& a) {
  app.add_option("input", a.input,
                 "input frames, a printf-style pattern: %04d (zero-padded to 4 digits) or %d, e.g. shot/in_%04d.png; "
                 "every frame OpenImageIO reads (PNG, TIFF, EXR, JPEG, ...), consecutive numbers, one size and type; "
                 "or a video file (.mp4, .mov, .mkv, .webm, .m4v, .avi)")
      ->required();
  app.add_option("output", a.output,
                 "output frames, a pattern too (e.g. out/out_%04d.png; the format follows its extension), or a "
                 "video file")
      ->required();
  app.add_option("-t,--time-scale", a.time_scale_text,
                 "frame-rate factor: a whole number N (T input frames become (T - 1) * N + 1, input frame k is "
                 "output frame k * N), or any number or ratio, e.g. 2.5 or 60/24 to make 60 frames a second of 24 "
                 "(output frame g is the instant g / N: floor((T - 1) * N) + 1 frames); default 1 (then give --scale or --size)")
      ->capture_default_str();
  app.add_option("-s,--scale", a.scale, "spatial magnification of every frame, any real > 0 (default 1)");
  app.add_option("--size", a.size_spec, "output frame size instead of --scale: WxH");
  app.add_option("--method", a.method, "ddt (default) or delaunay (the initial tetrahedrization, no flips)")
      ->check(CLI::IsMember({"ddt", "delaunay"}))
      ->capture_default_str();
  app.add_option("--cost", a.cost, "flip cost: " + ddt::cost_names_joined())->capture_default_str();
  app.add_option("--render", a.render,
                 "field drawn on the tetrahedra: linear (the paper's; the default: sharper on moving edges) or cubic "
                 "(a cubic Bézier tetrahedron from the values and limited slopes at its vertices, smoother)")
      ->check(CLI::IsMember(ddt::render_names()))
      ->capture_default_str();
  app.add_option("--slopes", a.slopes, "cubic render: slope limiter of the vertex gradients: mc4, mc, central, minmod")
      ->check(CLI::IsMember(ddt::slope_limiter_names()))
      ->capture_default_str();
  char presmooth_help[360];
  std::snprintf(presmooth_help, sizeof presmooth_help,
                "graduated optimization: flip first on the frames smoothed by a Gaussian of this sigma (pixels), then "
                "on the frames themselves; 0: flip on the frames only. Default %g, and %g where the mesh starts along "
                "a zoom or a shift of whole pixels a frame (--motion), or the frames move by a pixel or less a frame",
                a.presmooth, ddt::SequenceUpscaleOptions{}.presmooth_along_motion);
  a.presmooth_given = app.add_option("--presmooth", a.presmooth, presmooth_help)->check(CLI::Range(0.0, 16.0));
  app.add_option("--tolerance", a.tolerance, "a flip must lower the local cost by more than this fraction")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_flag("--flip-slow-texture", a.flip_slow_texture,
               "let the flips re-pair fine texture that moves by a pixel or less a frame (by default it stays paired "
               "along time, as frame blending pairs it: docs/sequences.md, \"Slow texture\")");
  app.add_option("--motion", a.motion,
                 "initial mesh: auto (along the frames' dominant motion when they have one of more than a pixel a "
                 "frame: a translation, a pan or one object moving, or else a zoom about the centre), off (the pixel "
                 "lattice's), DX,DY (sheared by that many pixels a frame, rounded to 1/8) or DX,DY,ZOOM (with a "
                 "zoom by the factor ZOOM a frame about the centre, 0.5 to 2, e.g. 0,0,1.02); docs/sequences.md, "
                 "\"Dominant motion\" and \"Zoom\"")
      ->capture_default_str();
  app.add_option("--time-tile", a.options.tile_frames,
                 "input frames reconstructed at once (default: about 4 million input pixels a tile, margins "
                 "included); bounds the memory")
      ->check(whole_number(1));
  app.add_option("--time-margin", a.options.margin_frames,
                 "extra input frames reconstructed on either side of a tile, so its joins match (with "
                 "--exact-tiles: the least)")
      ->check(whole_number(0, 1000))
      ->capture_default_str();
  app.add_flag("--exact-tiles", a.options.exact_tiles,
               "make the tiles' result the untiled one bit for bit: margins of whole slabs of the optimizer's "
               "schedule, widened as its phases need (several times the work on large frames)");
  app.add_option("--fps", a.fps_text,
                 "frame patterns into a video: the input's frames a second (e.g. 24 or 24000/1001); a video input "
                 "has its own")
      ->capture_default_str();
  app.add_option("--crf", a.video.crf, "video output: quality, 0 (lossless) to 51 (FFmpeg's -crf; 18 looks like the input)")
      ->check(whole_number(0, 51))
      ->capture_default_str();
  app.add_flag("--slow-motion", a.slow_motion,
               "video output: keep the input's frame rate, so the video lasts N times longer (no audio); by default "
               "the rate is multiplied by N, the duration and the audio kept");
  app.add_option("--max-pixels", a.max_pixels, "refuse outputs with more pixels in all (frames x width x height)")
      ->check(whole_number(1))
      ->capture_default_str();
  app.add_option("--threads", a.threads,
                 "threads to use (default: all cores); the output is the same for any number")
      ->check(whole_number(1));
  add_output_options(app, a.writing, false);
  app.add_flag("-v,--verbose", a.verbose, "report tiles, stages, flips and times");
  app.add_flag("-q,--quiet", a.quiet, "print nothing but errors");
  app.footer(
      "\nNumbering: output frame number = first input number + index; with input frames 1..64 at --time-scale 4\n"
      "the output is frames 1..253, and input frame n is output frame 1 + 4 * (n - 1).\n"
      "Frames are written into a private directory beside the output and renamed into place only when all are\n"
      "written: a failed run leaves no output frame behind and replaces none; input frames are never replaced.\n"
      "Colour: one tetrahedrization for all channels, the cost summed over them (alpha included).\n"
      "Video files (.mp4, .mov, .mkv, .webm, .m4v, .avi) work in place of either pattern, through FFmpeg.\n"
      "Examples: ddtscale shot/in_%04d.png slow/out_%04d.png --time-scale 4\n"
      "          ddtscale clip.mp4 clip_60fps.mp4 --time-scale 60/24");
}

// Where the frames come from and where they go: a frame pattern or a video
// file each; the input's frames found, the output's checked before any work.
struct SequenceEnds {
  bool video_in = false, video_out = false;
  std::optional<ddt::FramePattern> in_pattern, out_pattern;
  std::vector<std::string> input_paths;
  ddt::VideoInfo in_video;
  int first_number = 1, frames = 0, out_frames = 0;
};

bool is_video_end(const std::string& path) { return !ddt::is_frame_pattern(path) && ddt::is_video_path(path); }

// Each end a frame pattern or a video file; throws ddt::Error.
void check_sequence_ends(const SequenceArguments& a) {
  if (!is_video_end(a.input) && !ddt::is_frame_pattern(a.input))
    throw ddt::Error("the input '" + a.input + "' is neither a frame pattern (in_%04d.png) nor a video file");
  if (!is_video_end(a.output) && !ddt::is_frame_pattern(a.output))
    throw ddt::Error("the output '" + a.output + "' is neither a frame pattern (out_%04d.png) nor a video file");
  if (is_video_end(a.input) && a.options.exact_tiles)
    throw ddt::Error("--exact-tiles needs frame files: a video is read once, in order");
}

// After check_sequence_ends.
SequenceEnds sequence_ends(SequenceArguments& a, double time_scale) {
  SequenceEnds e;
  e.video_in = is_video_end(a.input);
  e.video_out = is_video_end(a.output);
  if (e.video_in) {
    e.in_video = ddt::probe_video(a.input);
    e.frames = e.in_video.frames;
    e.input_paths.push_back(a.input);
  } else {
    e.in_pattern = ddt::parse_frame_pattern(a.input);
    const std::vector<int> numbers = ddt::find_frames(*e.in_pattern);
    e.first_number = numbers.front(), e.frames = static_cast<int>(numbers.size());
    for (int n : numbers) e.input_paths.push_back(e.in_pattern->path(n));
  }
  e.out_frames = ddt::sequence_output_frames(e.frames, time_scale);
  if (e.video_out) {
    ddt::check_not_an_input(a.output, e.input_paths);
    const std::string in_rate = e.video_in ? e.in_video.rate : a.fps_text;
    parse_ratio(in_rate, "--fps", 0, 1000);
    a.video.rate = a.slow_motion ? in_rate : rate_text(in_rate, a.time_scale_text);
    if (e.video_in && !a.slow_motion && e.in_video.audio) a.video.audio_from = a.input;
    return e;
  }
  e.out_pattern = ddt::parse_frame_pattern(a.output);
  if (e.in_pattern && e.out_pattern->path(e.first_number) == e.in_pattern->path(e.first_number))
    throw ddt::Error("the output pattern '" + a.output + "' names the input frames");
  // Any spelling of an input among the outputs is refused before the work.
  std::vector<ddt::FileId> input_ids;
  for (const std::string& path : e.input_paths)
    if (const auto id = ddt::file_id(path)) input_ids.push_back(*id);
  for (int k = 0; k < e.out_frames; ++k)
    if (const auto id = ddt::file_id(e.out_pattern->path(e.first_number + k));
        id && std::find(input_ids.begin(), input_ids.end(), *id) != input_ids.end())
      throw ddt::Error("output frame '" + e.out_pattern->path(e.first_number + k) + "' is an input frame");
  ddt::check_output_path(e.out_pattern->path(e.first_number), e.input_paths.front());
  ddt::check_encode_options(e.out_pattern->path(e.first_number), a.writing.encode);
  return e;
}

// The first frame sizes the job: the output frame size, the size limit and
// the memory of a tile.
void size_sequence_job(const SequenceArguments& a, const SequenceEnds& e, double time_scale, int width, int height,
                       int channels, int& out_w, int& out_h) {
  if (!a.size_spec.empty()) {
    parse_width_height(a.size_spec, "--size", 1, 65536, out_w, out_h);
  } else {
    out_w = static_cast<int>(std::max(1.0, std::round(width * a.scale)));
    out_h = static_cast<int>(std::max(1.0, std::round(height * a.scale)));
  }
  ddt::check_size_limit("output", std::to_string(e.out_frames) + " frames of " + std::to_string(out_w) + "x" +
                                      std::to_string(out_h),
                        ddt::checked_product({e.out_frames, out_w, out_h}), a.max_pixels, "--max-pixels");
  const int tile = a.options.tile_frames > 0 ? a.options.tile_frames
                                             : ddt::sequence_tile_frames(width, height, a.options.margin_frames);
  ddt::check_memory_fits("this job", tile_bytes(width, height, channels, out_w, out_h, std::min(tile, e.frames),
                                                a.options.margin_frames, time_scale));
}

// The reconstruction's options from the arguments.
void set_sequence_options(SequenceArguments& a) {
  ddt::SequenceUpscaleOptions& options = a.options;
  options.volume.method = ddt::volume_method_by_name(a.method);
  options.volume.cost = a.cost;
  options.volume.relative_tolerance = a.tolerance;
  options.volume.render = ddt::render_by_name(a.render);
  options.volume.slopes = ddt::slope_limiter_by_name(a.slopes);
  options.volume.presmooth = {a.presmooth, a.presmooth, 0.0};
  if (a.presmooth_given->count() > 0) options.presmooth_along_motion = -1;
  options.volume.keep_slow_texture = !a.flip_slow_texture;
}

}  // namespace

static int run_sequence_upscale(int argc, char** argv) {
  SequenceArguments a;
  CLI::App app{
      "ddtscale (sequences): frame-rate upsampling and enlargement of an image sequence by data-dependent\n"
      "tetrahedrization of (x, y, t). The frames are the slices of one space-time volume; a moving edge is a\n"
      "slanted surface in it, and the Lawson flips align tetrahedra with it, so the new frames interpolate\n"
      "along the motion (no optical flow, no double images of blended frames).",
      "ddtscale"};
  add_sequence_options(app, a);
  if (const auto status =
          parse_command_line(app, argc, argv, "ddtscale", "ddtscale in_%04d.png out_%04d.png --help"))
    return *status;

  try {
    ddt::find_cost(a.cost);
    ddt::set_motion(a.options, a.motion);
    // Frames come from a pattern or a video file (FFmpeg), and go to either.
    check_sequence_ends(a);
    if (!(a.scale > 0) || !std::isfinite(a.scale)) throw ddt::Error("--scale must be a positive number");
    if (a.scale != 1 && !a.size_spec.empty()) throw ddt::Error("give either --scale or --size, not both");
    // As the image command asks for a magnification: a run that changes
    // nothing is a mistake, not a copy.
    if (app.count("--time-scale") == 0 && app.count("--scale") == 0 && a.size_spec.empty())
      throw ddt::Error("give the frame-rate factor: --time-scale T (and/or --scale S or --size WxH for the frames)");
    const double time_scale = parse_ratio(a.time_scale_text, "--time-scale", 0, 1024);
    const SequenceEnds ends = sequence_ends(a, time_scale);
    const bool verbose = a.verbose;
    auto log = [&](const std::string& line) {
      if (verbose) std::cerr << line << "\n";
    };
    const int threads = ddt::usable_threads(a.threads);
    const auto thread_limit = ddt::limit_threads(threads);
    if (threads > 0) OIIO::attribute("threads", threads);

    int out_w = 0, out_h = 0;
    ddt::ImageReadLimits limits;
    limits.check = [&](const ddt::ImageHeader& h) {
      size_sequence_job(a, ends, time_scale, h.width, h.height, h.channels, out_w, out_h);
      if (ends.out_pattern)
        ddt::check_image_writable(ends.out_pattern->path(ends.first_number), out_w, out_h, h.channels, h.format,
                                  h.alpha_channel, a.writing.encode);
    };
    ddt::SequenceUpscaleOptions& options = a.options;
    std::unique_ptr<ddt::VideoReader> reader;
    ddt::ImageFile first;
    if (ends.video_in) {
      size_sequence_job(a, ends, time_scale, ends.in_video.width, ends.in_video.height, 3, out_w, out_h);
      reader = std::make_unique<ddt::VideoReader>(a.input, ends.in_video);
      if (options.shear_dominant_motion && a.method == "ddt") {
        // The motion's frames from a reader of their own: the main one
        // only goes forward, from the first frame.
        auto motion_reader = std::make_shared<ddt::VideoReader>(a.input, ends.in_video);
        auto next = std::make_shared<int>(0);
        options.motion_frames = [motion_reader, next](int k) {
          if (k < *next) throw ddt::Error("a video's frames are read in order");
          ddt::Image frame;
          for (; *next <= k; ++*next) frame = motion_reader->next();
          return frame;
        };
      }
      first.image = reader->next();
      first.format = ddt::SampleFormat::uint16;
      first.alpha_channel = -1;
    } else {
      first = ddt::read_frame(*ends.in_pattern, ends.first_number, nullptr, limits);
    }
    const int width = first.image.width, height = first.image.height, channels = first.image.channels;
    const int frames = ends.frames, first_number = ends.first_number;
    log("read: " + std::to_string(frames) + " frames " +
        (ends.video_in ? "of " + a.input + " (" + ends.in_video.rate + " a second" +
                             (ends.in_video.audio ? ", audio" : "") + ")"
                       : std::to_string(first_number) + ".." + std::to_string(first_number + frames - 1)) +
        " of " + std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(channels));
    if (a.method == "ddt" && channels > ddt::max_cost_channels)
      throw ddt::Error("frames of " + std::to_string(channels) + " channels: the flip costs take at most " +
                       std::to_string(ddt::max_cost_channels));

    ddt::Progress progress;
    std::unique_ptr<ddt::ProgressBar> bar;
    if (!a.quiet && ddt::ProgressBar::is_terminal(stderr)) bar = std::make_unique<ddt::ProgressBar>(progress, stderr);
    options.progress = &progress;
    set_sequence_options(a);
    auto print = [&](const std::string& line) {
      if (!verbose) return;
      if (bar) bar->print(line);
      else std::cerr << line << "\n";
    };
    if (verbose) options.volume.log = print;

    const OIIO::ParamValueList metadata =
        ddt::scaled_metadata(first.metadata, double(out_w) / width, double(out_h) / height);
    std::unique_ptr<ddt::FrameSequenceWriter> frame_writer;
    std::unique_ptr<ddt::VideoWriter> video_writer;
    if (ends.video_out) {
      video_writer = std::make_unique<ddt::VideoWriter>(a.output, out_w, out_h, a.video, ends.input_paths);
    } else {
      frame_writer = std::make_unique<ddt::FrameSequenceWriter>(*ends.out_pattern, first.format, first.alpha_channel,
                                                                &metadata, a.writing.encode, ends.input_paths);
    }
    int next_frame = 1;  // of a video: read once, in order
    auto read = [&](int k) {
      if (k == 0) return first.image;
      if (!reader) return ddt::read_frame(*ends.in_pattern, first_number + k, &first).image;
      if (k != next_frame) throw ddt::Error("a video's frames are read in order");
      ++next_frame;
      return reader->next();
    };
    auto write = [&](ddt::Image frame, int k) {
      if (video_writer) video_writer->write(frame);
      else frame_writer->write(first_number + k, frame);
    };
    ddt::SequenceUpscaleStats stats;
    ddt::upscale_sequence(frames, width, height, channels, read, out_w, out_h, time_scale, options, write, &stats);
    const auto t0 = ddt::Clock::now();
    if (video_writer) video_writer->commit();
    else frame_writer->commit();
    if (bar) bar->stop();
    struct rusage ru {};
    getrusage(RUSAGE_SELF, &ru);
    char line[400];
    std::snprintf(line, sizeof line,
                  "done: %d tiles, %lld flips, read %.2f s, tetrahedralize %.2f s, optimize %.2f s, render %.2f s, "
                  "write %.2f s, peak memory %.0f MB",
                  stats.tiles, stats.flips, stats.seconds_read, stats.seconds_triangulate, stats.seconds_optimize,
                  stats.seconds_render, stats.seconds_write + ddt::seconds_since(t0), ru.ru_maxrss / 1024.0);
    log(line);
    if (!a.quiet && !verbose)
      std::cerr << (ends.video_out ? a.output + " (" + a.video.rate + " frames a second)"
                                   : ends.out_pattern->path(first_number) + " .. " +
                                         ends.out_pattern->path(first_number + ends.out_frames - 1))
                << ": " << ends.out_frames << " frames of " << out_w << "x" << out_h << "\n";
    return 0;
  } catch (const std::bad_alloc&) {
    std::cerr << "ddtscale: out of memory (try a smaller --time-tile)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "ddtscale: " << e.what() << "\n";
    return 1;
  }
}

int run_sequence_command(int argc, char** argv) {
  if (std::string(argv[1]) == "sequence-eval") return run_sequence_eval(argc - 1, argv + 1);
  if (std::string(argv[1]) == "sequence-scene") return run_sequence_scene(argc - 1, argv + 1);
  return run_sequence_upscale(argc, argv);
}
