#pragma once
// Image sequences on disk, named by a printf-style frame pattern, the
// convention of VFX frame sequences (ffmpeg, Nuke, OpenImageIO's tools):
// "shot/in_%04d.png" names shot/in_0001.png, shot/in_0002.png, ...
//
// Pattern rules: exactly one conversion %d or %0Nd (N = 1..9, the number
// zero-padded to N digits; numbers longer than N are written in full, as
// printf does), in the file name (not in a directory); "%%" is a literal
// percent. Frame numbers are >= 0.
//
// Reading: the frames of a pattern are the files in its directory whose
// names match it (prefix, digits, suffix; with %0Nd at least N digits, with
// %d no leading zero), sorted by number; they must be consecutive
// (a missing frame is named in the error) and all of one size, channel
// count and sample type.
//
// Writing: every frame goes into one private directory beside the targets
// (safe_file.hpp's StagedOutput) and all are renamed into place only after
// the last is written, so a failed run leaves no output frame and replaces
// none; an input frame is never replaced.
//
// Every function throws ddt::Error with a one-line message on failure.

#include "io/encode_options.hpp"
#include "io/image_io.hpp"
#include "io/safe_file.hpp"

#include <memory>
#include <string>
#include <vector>

namespace ddt {

struct FramePattern {
  std::string text;       // as given
  std::string directory;  // "" for the current one
  std::string prefix;     // of the file name, before the number
  std::string suffix;     // after it
  int digits = 0;         // zero padding (%04d: 4); 0 for %d

  std::string file_name(int number) const;
  std::string path(int number) const;
  // The number in `file_name`, or -1 when the name does not match.
  int number_of(const std::string& file_name) const;
};

// True when `text` holds a %d or %0Nd conversion (what main() dispatches on).
bool is_frame_pattern(const std::string& text);
FramePattern parse_frame_pattern(const std::string& text);

// The numbers of the existing frames, sorted and consecutive; throws when
// none matches or one is missing.
std::vector<int> find_frames(const FramePattern& pattern);

// Reads frame `number`, checking it against `first` (size, channels, type)
// when given. `limits` as read_image's.
ImageFile read_frame(const FramePattern& pattern, int number, const ImageFile* first = nullptr,
                     const ImageReadLimits& limits = {});

// Writes frames one by one into a private directory beside the pattern's
// directory; commit() renames them all into place (none if it is never
// called: the destructor removes what was written).
class FrameSequenceWriter {
 public:
  // `inputs`: the paths of the input frames, never replaced.
  FrameSequenceWriter(const FramePattern& pattern, SampleFormat source_format, int alpha_channel,
                      const OIIO::ParamValueList* metadata, const EncodeOptions& encode,
                      const std::vector<std::string>& inputs);
  void write(int number, const Image& frame);
  void commit();

 private:
  FramePattern pattern_;
  SampleFormat format_;
  int alpha_channel_;
  const OIIO::ParamValueList* metadata_;
  EncodeOptions encode_;
  std::vector<FileId> keep_;
  std::unique_ptr<StagedOutput> staged_;
  std::vector<std::string> names_;
};

}  // namespace ddt
