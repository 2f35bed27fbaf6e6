#include "io/video_io.hpp"
#include "util/file_names.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace ddt {
namespace {

// "24000/1001" or "25" as a number; 0 when it is not one.
double rate_value(const std::string& rate) {
  double a = 0, b = 1;
  char slash = 0;
  std::istringstream in(rate);
  in >> a;
  if (in >> slash && slash == '/') in >> b;
  return b > 0 && a > 0 ? a / b : 0;
}

}  // namespace

bool is_video_path(const std::string& path) {
  static const char* const extensions[] = {".mp4", ".m4v", ".mov", ".mkv", ".webm", ".avi"};
  const std::string ext = lower_extension(path);
  return std::any_of(std::begin(extensions), std::end(extensions), [&](const char* e) { return ext == e; });
}

VideoInfo probe_video(const std::string& path) {
  check_regular_file(path);
  std::string text;
  try {
    text = program_output({"ffprobe", "-v", "error", "-select_streams", "v:0", "-count_packets", "-show_entries",
                           "stream=width,height,r_frame_rate,nb_read_packets:stream_side_data=rotation:stream_tags=rotate",
                           "-of", "default=noprint_wrappers=1",
                           path});
  } catch (const Error& e) {
    throw Error("cannot read video '" + path + "': " + e.what());
  }
  VideoInfo info;
  bool quarter_turn = false;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    if (key == "width") info.width = std::atoi(value.c_str());
    if (key == "height") info.height = std::atoi(value.c_str());
    if (key == "nb_read_packets") info.frames = std::atoi(value.c_str());
    if (key == "r_frame_rate") info.rate = value;
    if (key == "rotation" || key == "TAG:rotate")
      quarter_turn |= std::lround(std::abs(std::atof(value.c_str()))) % 180 == 90;
  }
  info.fps = rate_value(info.rate);
  // FFmpeg turns frames tagged as rotated by a quarter turn upright: the
  // frames it decodes are then height x width.
  if (quarter_turn) std::swap(info.width, info.height);
  if (info.width < 1 || info.height < 1 || info.frames < 1 || !(info.fps > 0))
    throw Error("cannot read video '" + path + "': no video stream with frames");
  try {
    info.audio = !program_output({"ffprobe", "-v", "error", "-select_streams", "a", "-show_entries", "stream=index",
                                  "-of", "csv=p=0", path})
                      .empty();
  } catch (const Error&) {
    info.audio = false;
  }
  return info;
}

VideoReader::VideoReader(const std::string& path, const VideoInfo& info)
    : info_(info),
      path_(path),
      decoder_({"ffmpeg", "-v", "error", "-nostdin", "-i", path, "-map", "0:v:0", "-fps_mode", "passthrough", "-f",
                "rawvideo", "-pix_fmt", "rgb48le", "-"},
               ChildProcess::Pipe::from_stdout),
      buffer_(static_cast<std::size_t>(info.width) * info.height * 3) {}

Image VideoReader::next() {
  if (!decoder_.read(buffer_.data(), buffer_.size() * sizeof(unsigned short))) {
    decoder_.wait();
    const std::string why = decoder_.last_error_line();
    throw Error("video '" + path_ + "' ended after " + std::to_string(read_) + " of " + std::to_string(info_.frames) +
                " frames" + (why.empty() ? "" : ": " + why));
  }
  ++read_;
  Image frame(info_.width, info_.height, 3);
  for (std::size_t i = 0; i < buffer_.size(); ++i) frame.pixels[i] = buffer_[i] / 65535.0f;  // little-endian hosts
  return frame;
}

VideoWriter::VideoWriter(const std::string& path, int width, int height, const VideoEncoding& encoding,
                         const std::vector<std::string>& inputs)
    : width_(width), height_(height), buffer_(static_cast<std::size_t>(width) * height * 3) {
  if (!is_video_path(path))
    throw Error("cannot write video '" + path + "': use .mp4, .m4v, .mov, .mkv, .webm or .avi");
  if (encoding.crf < 0 || encoding.crf > 51) throw Error("--crf must be between 0 and 51");
  const std::string ext = lower_extension(path);
  const bool subsampled = ext == ".mp4" || ext == ".m4v" || ext == ".mov" || ext == ".mkv" || ext == ".webm";
  if (subsampled && (width % 2 || height % 2))
    throw Error("cannot write video '" + path + "': " + std::to_string(width) + "x" + std::to_string(height) +
                " is odd, and 4:2:0 video needs an even width and height (give --size with even numbers)");
  for (const std::string& input : inputs)
    if (const auto id = file_id(input)) keep_.push_back(*id);
  check_not_an_input(path, inputs);
  staged_ = std::make_unique<StagedOutput>(path);
  name_ = staged_->target().filename().string();
  std::vector<std::string> args = {"ffmpeg",         "-v",      "error", "-nostdin", "-y", "-f", "rawvideo", "-pix_fmt",
                                   "rgb48le",        "-s",      std::to_string(width) + "x" + std::to_string(height),
                                   "-framerate",     encoding.rate, "-i", "-"};
  if (!encoding.audio_from.empty())
    // Copied into Matroska, which takes any codec; else encoded as the container expects.
    args.insert(args.end(), {"-i", encoding.audio_from, "-map", "0:v", "-map", "1:a?", "-c:a",
                             ext == ".mkv" ? "copy" : ext == ".webm" ? "libopus" : ext == ".avi" ? "libmp3lame" : "aac"});
  if (ext == ".mp4" || ext == ".m4v" || ext == ".mov" || ext == ".mkv")
    args.insert(args.end(), {"-crf", std::to_string(encoding.crf), "-pix_fmt", "yuv420p"});
  if (ext == ".webm") args.insert(args.end(), {"-crf", std::to_string(encoding.crf), "-b:v", "0"});
  args.push_back(staged_->stage_path(name_).string());
  encoder_ = std::make_unique<ChildProcess>(args, ChildProcess::Pipe::to_stdin);
}

void VideoWriter::write(const Image& frame) {
  if (frame.width != width_ || frame.height != height_) throw Error("a video frame of another size");
  const int C = frame.channels;
  for (std::size_t p = 0, n = static_cast<std::size_t>(width_) * height_; p < n; ++p)
    for (int c = 0; c < 3; ++c) {
      const float v = frame.pixels[p * C + std::min(c, C < 3 ? 0 : c)];
      buffer_[p * 3 + c] = static_cast<unsigned short>(std::lround(std::clamp(v, 0.0f, 1.0f) * 65535.0f));
    }
  if (!encoder_->write(buffer_.data(), buffer_.size() * sizeof(unsigned short))) {
    encoder_->wait();
    throw Error("cannot write video '" + staged_->target().string() + "': ffmpeg stopped: " +
                encoder_->last_error_line());
  }
}

void VideoWriter::commit() {
  const int status = encoder_->wait();
  if (status != 0)
    throw Error("cannot write video '" + staged_->target().string() + "': ffmpeg failed" +
                (encoder_->last_error_line().empty() ? "" : ": " + encoder_->last_error_line()));
  staged_->finish(staged_->adopt(name_));
  staged_->commit({name_}, keep_);
}

}  // namespace ddt
