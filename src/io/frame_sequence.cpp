#include "io/frame_sequence.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <system_error>

namespace fs = std::filesystem;

namespace ddt {
namespace {

const char* format_name(SampleFormat f) {
  switch (f) {
    case SampleFormat::uint8: return "8-bit";
    case SampleFormat::uint16: return "16-bit";
    case SampleFormat::half: return "half-float";
    case SampleFormat::float32: return "float";
  }
  return "?";
}

// The position and length of the one %d / %0Nd conversion in `name`, with
// its padding; "%%" skipped. found = false when there is none.
struct Conversion {
  bool found = false;
  std::size_t at = 0, length = 0;
  int digits = 0;
};

Conversion find_conversion(const std::string& name, const std::string& text) {
  Conversion c;
  for (std::size_t i = 0; i < name.size(); ++i) {
    if (name[i] != '%') continue;
    if (i + 1 < name.size() && name[i + 1] == '%') {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    int digits = 0;
    if (j < name.size() && name[j] == '0') {
      ++j;
      if (j >= name.size() || !std::isdigit(static_cast<unsigned char>(name[j])) || name[j] == '0')
        throw Error("frame pattern '" + text + "': %0 must be followed by a width of 1 to 9 digits (as in %04d)");
      digits = name[j++] - '0';
    }
    if (j >= name.size() || name[j] != 'd')
      throw Error("frame pattern '" + text + "': only %d and %0Nd (N = 1..9) are understood (use %% for a percent)");
    if (c.found) throw Error("frame pattern '" + text + "' holds more than one frame number");
    c = {true, i, j + 1 - i, digits};
    i = j;
  }
  return c;
}

std::string unescape_percent(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    out += s[i];
    if (s[i] == '%' && i + 1 < s.size() && s[i + 1] == '%') ++i;
  }
  return out;
}

}  // namespace

std::string FramePattern::file_name(int number) const {
  std::string digits_text = std::to_string(number);
  if (static_cast<int>(digits_text.size()) < digits)
    digits_text.insert(0, static_cast<std::size_t>(digits) - digits_text.size(), '0');
  return prefix + digits_text + suffix;
}

std::string FramePattern::path(int number) const {
  return directory.empty() ? file_name(number) : (fs::path(directory) / file_name(number)).string();
}

int FramePattern::number_of(const std::string& name) const {
  if (name.size() <= prefix.size() + suffix.size()) return -1;
  if (name.compare(0, prefix.size(), prefix) != 0) return -1;
  if (name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) return -1;
  const std::string middle = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  if (middle.size() > 9) return -1;
  for (char ch : middle)
    if (!std::isdigit(static_cast<unsigned char>(ch))) return -1;
  // %0Nd writes at least N digits, %d none with a leading zero: a name
  // this pattern could not have written is not its frame.
  if (static_cast<int>(middle.size()) < std::max(1, digits)) return -1;
  if (middle.size() > 1 && middle[0] == '0' && static_cast<int>(middle.size()) > digits) return -1;
  return std::stoi(middle);
}

bool is_frame_pattern(const std::string& text) {
  try {
    return find_conversion(fs::path(text).filename().string(), text).found;
  } catch (const Error&) {
    return false;  // "50%.png" is an image's name
  }
}

FramePattern parse_frame_pattern(const std::string& text) {
  FramePattern p;
  p.text = text;
  const fs::path path(text);
  const std::string name = path.filename().string();
  const Conversion c = find_conversion(name, text);
  if (!c.found) throw Error("frame pattern '" + text + "' holds no frame number (%d or %0Nd, as in in_%04d.png)");
  if (path.has_parent_path() && path.parent_path().string().find('%') != std::string::npos)
    throw Error("frame pattern '" + text + "': the frame number must be in the file name, not in a directory");
  p.directory = path.parent_path().string();
  p.prefix = unescape_percent(name.substr(0, c.at));
  p.suffix = unescape_percent(name.substr(c.at + c.length));
  p.digits = c.digits;
  if (p.suffix.empty() || p.suffix.find('.') == std::string::npos)
    throw Error("frame pattern '" + text + "' has no file extension after the frame number (as in in_%04d.png)");
  return p;
}

std::vector<int> find_frames(const FramePattern& pattern) {
  const fs::path dir = pattern.directory.empty() ? fs::path(".") : fs::path(pattern.directory);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error("frame pattern '" + pattern.text + "': no directory '" + dir.string() + "'");
  std::vector<int> numbers;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const int n = pattern.number_of(it->path().filename().string());
    if (n >= 0) numbers.push_back(n);
  }
  if (ec) throw Error("cannot list '" + dir.string() + "': " + ec.message());
  if (numbers.empty()) throw Error("frame pattern '" + pattern.text + "' matches no file");
  std::sort(numbers.begin(), numbers.end());
  numbers.erase(std::unique(numbers.begin(), numbers.end()), numbers.end());
  for (std::size_t i = 1; i < numbers.size(); ++i)
    if (numbers[i] != numbers[i - 1] + 1)
      throw Error("frame " + std::to_string(numbers[i - 1] + 1) + " ('" + pattern.path(numbers[i - 1] + 1) +
                  "') is missing from the sequence " + std::to_string(numbers.front()) + ".." +
                  std::to_string(numbers.back()) + " of '" + pattern.text + "'");
  return numbers;
}

ImageFile read_frame(const FramePattern& pattern, int number, const ImageFile* first, const ImageReadLimits& limits) {
  const std::string path = pattern.path(number);
  ImageReadLimits checked = limits;
  if (first)
    checked.check = [&](const ImageHeader& h) {
      const Image& f = first->image;
      if (h.width != f.width || h.height != f.height || h.channels != f.channels)
        throw Error("frame '" + path + "' is " + std::to_string(h.width) + "x" + std::to_string(h.height) + "x" +
                    std::to_string(h.channels) + ", the first frame " + std::to_string(f.width) + "x" +
                    std::to_string(f.height) + "x" + std::to_string(f.channels) + " (all frames must match)");
      if (h.format != first->format)
        throw Error("frame '" + path + "' holds " + format_name(h.format) + " samples, the first frame " +
                    format_name(first->format) + " (all frames must match)");
      if (limits.check) limits.check(h);
    };
  return read_image(path, checked);
}

FrameSequenceWriter::FrameSequenceWriter(const FramePattern& pattern, SampleFormat source_format, int alpha_channel,
                                         const OIIO::ParamValueList* metadata, const EncodeOptions& encode,
                                         const std::vector<std::string>& inputs)
    : pattern_(pattern), format_(source_format), alpha_channel_(alpha_channel), metadata_(metadata), encode_(encode) {
  for (const std::string& in : inputs)
    if (const auto id = file_id(in)) keep_.push_back(*id);
  staged_ = std::make_unique<StagedOutput>(pattern_.path(0));
}

void FrameSequenceWriter::write(int number, const Image& frame) {
  const std::string name = pattern_.file_name(number);
  write_image(staged_->stage_path(name).string(), frame, format_, alpha_channel_, metadata_, encode_);
  staged_->finish(staged_->adopt(name));
  names_.push_back(name);
}

void FrameSequenceWriter::commit() { staged_->commit(names_, keep_); }

}  // namespace ddt
