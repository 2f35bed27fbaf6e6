#pragma once
// Video files in and out through FFmpeg's programs (ffprobe, ffmpeg; the
// Debian package ffmpeg), run as child processes with their frames passed
// through pipes as raw 16-bit RGB: no temporary frames on disk, and the
// frames are read and written in order while the sequence path works
// (volume/sequence_upscale.hpp reads each input frame once, in order, and
// writes the output frames in order).
//
// Reading: probe_video() asks ffprobe for the first video stream's size
// (as displayed: swapped when it is tagged as turned a quarter), frame
// rate and frame count (counted by packets, exact for the containers we
// know), and whether there is audio; VideoReader decodes the frames as
// RGB, 0..1 floats (16-bit, so 10- and 12-bit sources keep their depth).
//
// Writing: VideoWriter encodes RGB frames at a given rate into the output's
// container (from its extension) with FFmpeg's default codec for it
// (H.264 in .mp4/.mkv/.mov, VP9 in .webm; 4:2:0, so even sizes), quality
// `crf`, into a staged file (io/safe_file.hpp) renamed into place by
// commit(); optionally with the audio of another file (a frame-rate
// conversion keeps the duration): copied into .mkv, encoded as AAC (Opus
// in .webm, MP3 in .avi) elsewhere. Without commit() nothing is left
// behind.
//
// Errors: ddt::Error with FFmpeg's last message line (a missing program,
// a file that is not a video, an encoder that fails).

#include "io/safe_file.hpp"
#include "util/child_process.hpp"
#include "util/image.hpp"

#include <memory>
#include <string>
#include <vector>

namespace ddt {

// Whether `path` names a video container by its extension (mp4, m4v, mov,
// mkv, webm, avi; not gif, which OpenImageIO reads as an image).
bool is_video_path(const std::string& path);

struct VideoInfo {
  int width = 0, height = 0;
  int frames = 0;
  std::string rate;  // frames a second as FFmpeg writes it, e.g. "24000/1001"
  double fps = 0;    // the same as a number
  bool audio = false;
};

VideoInfo probe_video(const std::string& path);

class VideoReader {
 public:
  VideoReader(const std::string& path, const VideoInfo& info);
  // The next frame (width x height x 3); throws when the video ends early.
  Image next();

 private:
  VideoInfo info_;
  std::string path_;
  ChildProcess decoder_;
  std::vector<unsigned short> buffer_;
  int read_ = 0;
};

struct VideoEncoding {
  std::string rate;          // output frames a second, "60" or "60000/1001"
  int crf = 18;              // quality: 0 (lossless) .. 51; 18 looks like the input
  std::string audio_from;    // a file whose audio is copied ("" for none)
};

class VideoWriter {
 public:
  // `inputs`: files never replaced.
  VideoWriter(const std::string& path, int width, int height, const VideoEncoding& encoding,
              const std::vector<std::string>& inputs);
  void write(const Image& frame);  // width x height, 1 to 4 channels (grey repeated, alpha dropped)
  void commit();

 private:
  int width_, height_;
  std::vector<FileId> keep_;
  std::unique_ptr<StagedOutput> staged_;
  std::string name_;
  std::unique_ptr<ChildProcess> encoder_;
  std::vector<unsigned short> buffer_;
};

}  // namespace ddt
