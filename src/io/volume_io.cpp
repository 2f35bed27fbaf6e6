#include "io/volume_io.hpp"
#include "util/file_names.hpp"

#include "util/error.hpp"
#include "io/safe_file.hpp"
#include "util/size_limits.hpp"

#include <teem/nrrd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <system_error>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace ddt {

struct VolumeHeader {
  Nrrd* nrrd = nullptr;        // sizes and metadata; data freed
  unsigned axis0 = 0;          // index of the x axis (1 when a size-1 axis leads)
  std::vector<FileId> sources;  // the header and its data files: never replaced by an output
  ~VolumeHeader() {
    if (nrrd) nrrdNuke(nrrd);
  }
};

namespace {

struct TypeInfo {
  VolumeSampleType type;
  int teem;
  const char* name;
  double lo, hi;  // representable range (integers); +-inf for floats
  bool integer;
};

const TypeInfo& type_info(VolumeSampleType type) {
  static const TypeInfo table[] = {
      {VolumeSampleType::int8, nrrdTypeChar, "int8", -128.0, 127.0, true},
      {VolumeSampleType::uint8, nrrdTypeUChar, "uint8", 0.0, 255.0, true},
      {VolumeSampleType::int16, nrrdTypeShort, "int16", -32768.0, 32767.0, true},
      {VolumeSampleType::uint16, nrrdTypeUShort, "uint16", 0.0, 65535.0, true},
      {VolumeSampleType::int32, nrrdTypeInt, "int32", -2147483648.0, 2147483647.0, true},
      {VolumeSampleType::uint32, nrrdTypeUInt, "uint32", 0.0, 4294967295.0, true},
      {VolumeSampleType::int64, nrrdTypeLLong, "int64", -9.2233720368547748e18, 9.2233720368547748e18, true},
      {VolumeSampleType::uint64, nrrdTypeULLong, "uint64", 0.0, 1.8446744073709550e19, true},
      {VolumeSampleType::float32, nrrdTypeFloat, "float32", -HUGE_VAL, HUGE_VAL, false},
      {VolumeSampleType::float64, nrrdTypeDouble, "float64", -HUGE_VAL, HUGE_VAL, false},
  };
  for (const auto& t : table)
    if (t.type == type) return t;
  return table[8];
}

struct EncodingInfo {
  VolumeEncoding encoding;
  const NrrdEncoding* teem;
  const char* name;
};

const std::vector<EncodingInfo>& encodings() {
  static const std::vector<EncodingInfo> table = {
      {VolumeEncoding::raw, nrrdEncodingRaw, "raw"},     {VolumeEncoding::gzip, nrrdEncodingGzip, "gzip"},
      {VolumeEncoding::bzip2, nrrdEncodingBzip2, "bzip2"}, {VolumeEncoding::ascii, nrrdEncodingAscii, "ascii"},
      {VolumeEncoding::hex, nrrdEncodingHex, "hex"},
  };
  return table;
}

// Teem's error stack as one line: its innermost (last) message, which
// names the cause, without the "[nrrd] function:" prefix.
std::string teem_error() {
  char* err = biffGetDone(NRRD);
  std::string all = err ? err : "";
  free(err);
  while (!all.empty() && (all.back() == '\n' || all.back() == ' ')) all.pop_back();
  const auto nl = all.rfind('\n');
  std::string line = nl == std::string::npos ? all : all.substr(nl + 1);
  const auto colon = line.find(": ");
  if (line.rfind("[", 0) == 0 && colon != std::string::npos) line = line.substr(colon + 2);
  while (!line.empty() && line.front() == ' ') line.erase(line.begin());
  return line.empty() ? "unknown NRRD error" : line;
}

// "%d", "%03d", ...: the one conversion a data file format may hold (the
// string goes to snprintf, so nothing else is let through).
bool single_int_conversion(const std::string& format) {
  int conversions = 0;
  for (std::size_t i = 0; i < format.size(); ++i) {
    if (format[i] != '%') continue;
    std::size_t j = i + 1;
    while (j < format.size() && std::isdigit(static_cast<unsigned char>(format[j]))) ++j;
    if (j >= format.size() || format[j] != 'd') return false;
    ++conversions;
    i = j;
  }
  return conversions == 1;
}

// What a NRRD header says, read without its data.
struct HeaderInfo {
  std::vector<std::string> data_files;  // empty when the data is attached; paths usable from here
  std::vector<std::size_t> sizes;       // of every axis
  std::vector<int> kinds;               // of every axis (Teem's nrrdKind*)
  std::vector<int> centers;             // of every axis (Teem's nrrdCenter*)
  std::size_t sample_bytes = 0;         // of one stored sample
};

// The names a pattern "data file: <format> <min> <max> <step>" expands to.
std::vector<std::string> expand_pattern(const std::string& path, const std::string& format, long long min,
                                        long long max, long long step) {
  if (!single_int_conversion(format))
    throw Error("cannot read '" + path + "': unsupported data file pattern '" + format + "'");
  if (step == 0) throw Error("cannot read '" + path + "': data file pattern with step 0");
  std::vector<std::string> names;
  for (long long i = min; step > 0 ? i <= max : i >= max; i += step) {
    if (names.size() >= 100000) throw Error("cannot read '" + path + "': too many data files");
    char name[4096];
    std::snprintf(name, sizeof name, format.c_str(), static_cast<int>(i));
    names.push_back(name);
  }
  return names;
}

// The data file names of a NRRD header, from its text. Teem opens a
// detached header's data files while it parses the header, even when told
// to skip the data, so a FIFO named there would block it before we could
// look: the names are read here first (the "data file" or "datafile" field:
// one name, a pattern, or LIST and one name a line to the end of the file).
// The value of a "data file" field, as Teem reads the field's name: case
// and spaces in the name do not matter ("data file", "datafile", "Data File").
bool data_file_field(const std::string& line, std::string& value) {
  const std::size_t colon = line.find(':');
  if (colon == std::string::npos) return false;
  std::string key;
  for (char ch : line.substr(0, colon))
    if (ch != ' ' && ch != '\t') key.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(ch))));
  if (key != "datafile") return false;
  const std::size_t begin = line.find_first_not_of(" \t", colon + 1);
  value = begin == std::string::npos ? std::string() : line.substr(begin);
  return true;
}

bool is_list(const std::string& value) {
  std::string first = value.substr(0, value.find_first_of(" \t"));
  for (char& ch : first) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return first == "LIST";
}

std::vector<std::string> data_file_names(const std::string& path) {
  constexpr std::size_t max_header_bytes = 1 << 20;
  std::ifstream in(path, std::ios::binary);
  std::vector<std::string> lines;
  std::string line;
  std::size_t bytes = 0;
  bool list = false;
  for (int c; (c = in.get()) != std::char_traits<char>::eof();) {
    if (++bytes > max_header_bytes) throw Error("cannot read '" + path + "': a NRRD header longer than 1 MiB");
    if (c != '\n') {
      line.push_back(static_cast<char>(c));
      continue;
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() && !list) break;  // the header ends; a LIST goes on to the end of the file
    // A header is text: Teem's line reader overflows on a NUL in it (found by fuzz_nrrd).
    for (char ch : line)
      if ((static_cast<unsigned char>(ch) < 0x20 && ch != '\t') || ch == 0x7f)
        throw Error("cannot read '" + path + "': a NRRD header with control bytes in its text");
    if (std::string value; data_file_field(line, value) && is_list(value)) list = true;
    lines.push_back(line);
    line.clear();
    if (lines.size() == 1 && lines[0].rfind("NRRD", 0) != 0) return {};  // not NRRD: Teem will say so
  }
  if (!line.empty()) {
    for (char ch : line)
      if ((static_cast<unsigned char>(ch) < 0x20 && ch != '\t' && ch != '\r') || ch == 0x7f)
        throw Error("cannot read '" + path + "': a NRRD header with control bytes in its text");
    lines.push_back(line);
  }
  std::vector<std::string> names;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::string& l = lines[i];
    std::string value;
    if (!data_file_field(l, value) || value.empty()) continue;
    std::istringstream tokens(value);
    std::string first;
    tokens >> first;
    if (is_list(value)) {
      for (std::size_t j = i + 1; j < lines.size(); ++j)
        if (!lines[j].empty()) names.push_back(lines[j]);
      break;
    }
    long long min = 0, max = 0, step = 0;
    if (first.find('%') != std::string::npos && tokens >> min >> max >> step) {
      names = expand_pattern(path, first, min, max, step);
    } else {
      names = {value};
    }
  }
  return names;
}

// The data files of the header at `path` as paths usable from here, from
// its text. Throws when a name leaves the header's directory and
// !any_data_path.
std::vector<std::string> data_files_of(const std::string& path, bool any_data_path) {
  const fs::path dir = fs::path(path).parent_path();
  std::vector<std::string> files;
  for (const std::string& name : data_file_names(path)) {
    if (name == "-") throw Error("cannot read '" + path + "': data on standard input is not supported");
    const fs::path p(name);
    bool leaves = p.is_absolute();
    for (const auto& part : p)
      if (part == "..") leaves = true;
    if (leaves && !any_data_path)
      throw Error("cannot read '" + path + "': its data file '" + name +
                  "' is outside the header's directory (absolute or '..'; allow with --any-data-file)");
    files.push_back((p.is_absolute() ? p : dir / p).string());
  }
  return files;
}

// Reads the header only, after its data files were checked (Teem opens
// them). Throws when Teem finds other data file names than `data_files`.
HeaderInfo read_header(const std::string& path, const std::vector<std::string>& data_files) {
  Nrrd* nrrd = nrrdNew();
  NrrdIoState* nio = nrrdIoStateNew();
  nio->skipData = AIR_TRUE;
  struct Owner {
    Nrrd* n;
    NrrdIoState* io;
    ~Owner() {
      nrrdNuke(n);
      nrrdIoStateNix(io);
    }
  } owner{nrrd, nio};
  if (nrrdLoad(nrrd, path.c_str(), nio)) throw Error("cannot read '" + path + "': " + teem_error());
  HeaderInfo info;
  for (unsigned a = 0; a < nrrd->dim; ++a) {
    info.sizes.push_back(nrrd->axis[a].size);
    info.kinds.push_back(nrrd->axis[a].kind);
    info.centers.push_back(nrrd->axis[a].center);
  }
  info.sample_bytes = nrrdElementSize(nrrd);
  std::vector<std::string> names;
  if (nio->dataFNFormat)
    names = expand_pattern(path, nio->dataFNFormat, nio->dataFNMin, nio->dataFNMax, nio->dataFNStep);
  else
    for (unsigned i = 0; i < nio->dataFNArr->len; ++i) names.push_back(nio->dataFN[i]);
  if (names.size() != data_files.size())
    throw Error("cannot read '" + path + "': its data file field is not understood");
  const fs::path dir = fs::path(path).parent_path();
  for (std::size_t i = 0; i < names.size(); ++i) {
    const fs::path p(names[i]);
    if ((p.is_absolute() ? p : dir / p).string() != data_files[i])
      throw Error("cannot read '" + path + "': its data file field is not understood");
  }
  info.data_files = data_files;
  return info;
}

// A leading axis holds channels when Teem's kind calls it non-spatial
// (vector, RGB-color, 3-vector, ...: every kind but domain, space, time and
// unknown), or, with 4 axes, when it has size 1 (a 3D volume, as before
// channels), or with 5 axes unless its kind is domain, space or time.
bool channel_axis(const std::vector<std::size_t>& sizes, const std::vector<int>& kinds) {
  if (sizes.size() < 3 || sizes.size() > 5) return false;
  const int kind = kinds.empty() ? nrrdKindUnknown : kinds[0];
  if (kind != nrrdKindUnknown && !nrrdKindIsDomain(kind)) return true;
  if (sizes.size() == 5) return kind == nrrdKindUnknown;
  return sizes.size() == 4 && sizes[0] == 1;
}

// The volume's size and channels from the axis sizes (see volume_io.hpp: 2
// spatial axes are one slice, 4 a series; a leading non-spatial axis holds
// the channels): {nx, ny, nz, nt, channels}; axis0 is the x axis. Throws for
// other shapes and for sizes past an int.
std::array<int, 5> volume_size(const std::vector<std::size_t>& sizes, const std::vector<int>& kinds,
                               const std::string& path, unsigned& axis0) {
  std::size_t size[5] = {1, 1, 1, 1, 1};  // x, y, z, t, channels
  axis0 = channel_axis(sizes, kinds) ? 1 : 0;
  const std::size_t spatial = sizes.size() - axis0;
  if (spatial >= 2 && spatial <= 4) {
    for (unsigned a = 0; a < spatial; ++a) size[a] = sizes[a + axis0];
    if (axis0 == 1) size[4] = sizes[0];
  } else {
    std::string text;
    for (std::size_t s : sizes) {
      if (!text.empty()) text.push_back('x');
      text.append(std::to_string(s));
    }
    throw Error("cannot read '" + path + "': a volume has 3 axes, a volume series 4 (x, y, z, t; after a leading "
                "non-spatial axis of kind vector, RGB-color, ... for channels), this NRRD has " +
                std::to_string(sizes.size()) + " (" + text + ")");
  }
  for (std::size_t s : size)
    if (s == 0 || s > static_cast<std::size_t>(std::numeric_limits<int>::max()))
      throw Error("cannot read '" + path + "': an axis has size 0 or is too large");
  if (size[4] > 256) throw Error("cannot read '" + path + "': more than 256 channels");
  return {static_cast<int>(size[0]), static_cast<int>(size[1]), static_cast<int>(size[2]), static_cast<int>(size[3]),
          static_cast<int>(size[4])};
}

}  // namespace

const char* sample_type_name(VolumeSampleType type) { return type_info(type).name; }

const char* encoding_name(VolumeEncoding encoding) {
  for (const auto& e : encodings())
    if (e.encoding == encoding) return e.name;
  return "raw";
}

VolumeSampleType parse_sample_type(const std::string& name) {
  static const std::pair<const char*, VolumeSampleType> aliases[] = {
      {"int8", VolumeSampleType::int8},       {"char", VolumeSampleType::int8},
      {"uint8", VolumeSampleType::uint8},     {"uchar", VolumeSampleType::uint8},
      {"int16", VolumeSampleType::int16},     {"short", VolumeSampleType::int16},
      {"uint16", VolumeSampleType::uint16},   {"ushort", VolumeSampleType::uint16},
      {"int32", VolumeSampleType::int32},     {"int", VolumeSampleType::int32},
      {"uint32", VolumeSampleType::uint32},   {"uint", VolumeSampleType::uint32},
      {"float32", VolumeSampleType::float32}, {"float", VolumeSampleType::float32},
      {"float64", VolumeSampleType::float64}, {"double", VolumeSampleType::float64},
  };
  for (const auto& [alias, type] : aliases)
    if (name == alias) return type;
  throw Error("unknown sample type '" + name + "' (valid: int8, uint8, int16, uint16, int32, uint32, float32, float64)");
}

VolumeEncoding parse_encoding(const std::string& name) {
  for (const auto& e : encodings())
    if (name == e.name) return e.encoding;
  throw Error("unknown NRRD encoding '" + name + "' (valid: raw, gzip, bzip2, ascii, hex)");
}

bool is_volume_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".nrrd" || ext == ".nhdr";
}

namespace {

// The header's files (volume_files) and what it says, data files checked.
HeaderInfo checked_header(const std::string& path, const VolumeReadOptions& options,
                          std::vector<std::string>& files) {
  check_regular_file(path);
  const std::vector<std::string> data_files = data_files_of(path, options.any_data_path);
  for (const std::string& data : data_files) check_regular_file(data);  // not /dev/zero, not a FIFO
  files = {path};
  files.insert(files.end(), data_files.begin(), data_files.end());
  return read_header(path, data_files);
}

}  // namespace

std::vector<std::string> volume_files(const std::string& path, const VolumeReadOptions& options) {
  std::vector<std::string> files;
  checked_header(path, options, files);
  return files;
}

VolumeFile read_volume(const std::string& path, const VolumeReadOptions& options) {
  std::vector<std::string> files;
  const HeaderInfo info = checked_header(path, options, files);
  // The header's claims, before a sample is read or decompressed
  // (decompression bombs: `sizes: 400 400 400` in a 100-byte file).
  unsigned axis0 = 0;
  const std::array<int, 5> dims = volume_size(info.sizes, info.kinds, path, axis0);
  const std::array<int, 4> size{dims[0], dims[1], dims[2], dims[3]};
  const int channels = dims[4];
  std::string size_text =
      std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]);
  if (info.sizes.size() - axis0 == 4) size_text.append("x").append(std::to_string(dims[3]));
  check_size_limit("input '" + path + "'", size_text, checked_product({dims[0], dims[1], dims[2], dims[3]}),
                   options.max_voxels, options.option);
  // Teem's decoded samples and our floats, both held until the copy ends.
  check_memory_fits("reading '" + path + "' (" + size_text + ")",
                    (4.0 + double(info.sample_bytes)) * dims[0] * dims[1] * dims[2] * dims[3] * channels);
  if (options.check) options.check(size, channels);
  auto header = std::make_shared<VolumeHeader>();
  for (const std::string& f : files)
    if (const auto id = file_id(f)) header->sources.push_back(*id);
  header->nrrd = nrrdNew();
  Nrrd* nin = header->nrrd;
  NrrdIoState* nio = nrrdIoStateNew();
  if (nrrdLoad(nin, path.c_str(), nio)) {
    nrrdIoStateNix(nio);
    throw Error("cannot read '" + path + "': " + teem_error());
  }
  VolumeFile file;
  for (const auto& e : encodings())
    if (nio->encoding == e.teem) file.encoding = e.encoding;
  nrrdIoStateNix(nio);

  bool known_type = false;
  for (VolumeSampleType t : {VolumeSampleType::int8, VolumeSampleType::uint8, VolumeSampleType::int16,
                             VolumeSampleType::uint16, VolumeSampleType::int32, VolumeSampleType::uint32,
                             VolumeSampleType::int64, VolumeSampleType::uint64, VolumeSampleType::float32,
                             VolumeSampleType::float64})
    if (type_info(t).teem == nin->type) file.type = t, known_type = true;
  if (!known_type) throw Error("cannot read '" + path + "': unsupported NRRD sample type (block)");

  // The same sizes as the header read above, unless the file changed since.
  std::vector<std::size_t> sizes;
  for (unsigned a = 0; a < nin->dim; ++a) sizes.push_back(nin->axis[a].size);
  if (sizes != info.sizes) throw Error("cannot read '" + path + "': the file changed while it was read");
  header->axis0 = axis0;
  file.volume = Volume(size, channels, 0.0f);
  // A series' time steps are instants unless the header says they are cells.
  if (info.sizes.size() - axis0 == 4) file.node_centred[3] = info.centers[axis0 + 3] != nrrdCenterCell;
  const std::size_t n = file.volume.voxels.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double v = nrrdDLookup[nin->type](nin->data, i);
    if (!std::isfinite(v)) throw Error("cannot read '" + path + "': the volume holds NaN or infinite samples");
    file.volume.voxels[i] = static_cast<float>(v);
  }
  nin->data = airFree(nin->data);
  file.header = header;
  return file;
}

void check_volume_output_path(const std::string& output, const std::string& input, const VolumeReadOptions& options) {
  std::error_code ec;
  if (output.empty()) throw Error("no output file given");
  if (!is_volume_path(output))
    throw Error("cannot write '" + output + "': a volume is written as .nrrd or .nhdr");
  const fs::path target = resolve_output_link(output);
  if (!input.empty()) {
    // Every file written (the header and, for .nhdr, a data file named
    // after it for any encoding) against every file read, by identity.
    const std::vector<std::string> inputs = volume_files(input, options);
    check_not_an_input(output, inputs);
    if (fs::weakly_canonical(output, ec) == fs::weakly_canonical(input, ec))
      throw Error("output '" + output + "' is the input file; refusing to overwrite it");
    if (lower_extension(output) == ".nhdr")
      for (const auto& e : encodings()) {
        const fs::path data = target.parent_path() / (target.stem().string() + "." + e.teem->suffix);
        const auto id = file_id(data.string());
        for (const std::string& in : inputs)
          if (id && id == file_id(in))
            throw Error("output '" + output + "' would replace '" + data.string() +
                        "', a file the input is read from; refusing to overwrite it");
      }
  }
  if (fs::is_directory(target, ec)) throw Error("output '" + output + "' is a directory");
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  if (!fs::is_directory(dir, ec)) throw Error("output directory '" + dir.string() + "' does not exist");
  if (::access(dir.c_str(), W_OK) != 0) throw Error("output directory '" + dir.string() + "' is not writable");
}

void write_volume(const std::string& path, const Volume& volume, VolumeSampleType type, VolumeEncoding encoding,
                  const VolumeHeader* like, const std::string& comment, const std::array<bool, 4>& node_centred) {
  if (volume.empty()) throw Error("cannot write '" + path + "': the volume is empty");
  if (!is_volume_path(path)) throw Error("cannot write '" + path + "': a volume is written as .nrrd or .nhdr");
  const TypeInfo& info = type_info(type);
  // Float samples are written from the volume's own buffer (wrapped, not
  // copied: at 512^3 the copy and its fresh pages took about a second).
  const bool wrapped = info.teem == nrrdTypeFloat;
  struct NrrdOwner {
    Nrrd* n;
    bool wrapped;
    ~NrrdOwner() { wrapped ? (void)nrrdNix(n) : (void)nrrdNuke(n); }
  } owner{nrrdNew(), wrapped};
  Nrrd* nout = owner.n;
  const std::size_t channels = volume.channels;
  if (channels < 1 || volume.voxels.size() != volume.voxel_count() * channels)
    throw Error("cannot write '" + path + "': the samples do not match the volume's size and channels");
  if (like && (like->axis0 == 1 ? like->nrrd->axis[0].size : 1) != channels)
    throw Error("cannot write '" + path + "': the volume has another number of channels than its input");
  // A channel axis leads when there are channels or the input had one.
  const unsigned axis0 = (like ? like->axis0 : 0) == 1 || channels > 1 ? 1 : 0;
  const bool flat = like && like->nrrd->dim == 2 + axis0 && volume.nz == 1 && volume.nt == 1;
  // A series has four domain axes; so has the output of a series' header.
  const bool series = volume.nt > 1 || (like && like->nrrd->dim == 4 + axis0);
  const unsigned spatial = flat ? 2 : series ? 4 : 3;
  // (A one-slice input enlarged along its thin axis is written with 3 axes, as always.)
  if (series && like && like->nrrd->dim != spatial + axis0)
    throw Error("cannot write '" + path + "': a volume series written with the header of a 3D volume");
  std::size_t sizes[5] = {channels, std::size_t(volume.nx), std::size_t(volume.ny), std::size_t(volume.nz),
                          std::size_t(volume.nt)};
  const int allocated = wrapped ? nrrdWrap_nva(nout, const_cast<float*>(volume.voxels.data()), info.teem,
                                               spatial + axis0, sizes + (1 - axis0))
                                 : nrrdAlloc_nva(nout, info.teem, spatial + axis0, sizes + (1 - axis0));
  if (allocated) throw Error("cannot write '" + path + "': " + teem_error());
  if (!wrapped)
    for (std::size_t i = 0; i < volume.voxels.size(); ++i) {
      double v = volume.voxels[i];
      if (info.integer) v = std::clamp(std::nearbyint(v), info.lo, info.hi);
      nrrdDInsert[info.teem](nout->data, i, v);
    }
  const std::size_t new_size[4] = {std::size_t(volume.nx), std::size_t(volume.ny), std::size_t(volume.nz),
                                   std::size_t(volume.nt)};
  if (like) {
    const Nrrd* nin = like->nrrd;
    if (nrrdBasicInfoCopy(nout, nin,
                          NRRD_BASIC_INFO_DATA_BIT | NRRD_BASIC_INFO_TYPE_BIT | NRRD_BASIC_INFO_BLOCKSIZE_BIT |
                              NRRD_BASIC_INFO_DIMENSION_BIT | NRRD_BASIC_INFO_OLDMIN_BIT | NRRD_BASIC_INFO_OLDMAX_BIT) ||
        nrrdAxisInfoCopy(nout, nin, nullptr, NRRD_AXIS_INFO_SIZE_BIT))
      throw Error("cannot write '" + path + "': " + teem_error());
    for (unsigned a = 0; a < spatial; ++a) {
      NrrdAxisInfo& ax = nout->axis[axis0 + a];
      const double n_in = double(nin->axis[axis0 + a].size), n_out = double(new_size[a]);
      // Instants keep the first and last in place: (n - 1) intervals between them.
      const bool node = node_centred[a] && n_in > 1 && n_out > 1;
      const double s = node ? (n_out - 1) / (n_in - 1) : n_out / n_in;
      if (std::isfinite(ax.spacing)) ax.spacing /= s;
      if (std::isfinite(ax.thickness)) ax.thickness /= s;
      if (nout->spaceDim > 0 && std::isfinite(ax.spaceDirection[0])) {
        const bool origin = std::isfinite(nout->spaceOrigin[0]);
        for (unsigned d = 0; d < nout->spaceDim; ++d) {
          if (origin && !node) nout->spaceOrigin[d] += (0.5 / s - 0.5) * ax.spaceDirection[d];
          ax.spaceDirection[d] /= s;
        }
      }
      ax.center = node ? nrrdCenterNode : nrrdCenterCell;
    }
  } else {
    for (unsigned a = 0; a < spatial; ++a) {
      const bool node = node_centred[a] && new_size[a] > 1;
      nout->axis[axis0 + a].center = node ? nrrdCenterNode : nrrdCenterCell;
      if (axis0 == 1 || series) nout->axis[axis0 + a].kind = a == 3 ? nrrdKindTime : nrrdKindDomain;
    }
    if (axis0 == 1) nout->axis[0].kind = channels == 3 ? nrrdKind3Vector : nrrdKindVector;
  }
  if (!comment.empty()) nrrdCommentAdd(nout, comment.c_str());

  // Teem writes through FILE*s that land in a StagedOutput (safe_file.hpp):
  // every write error is seen, and nothing of Teem's file handling runs
  // (its nrrdSave frees the data file name twice when a detached write
  // fails). A .nhdr is two files: the data (encoded by Teem's encoding),
  // then the header naming it.
  StagedOutput stage(path);
  const std::string name = stage.target().filename().string();
  NrrdIoState* nio = nrrdIoStateNew();
  struct IoOwner {
    NrrdIoState* io;
    ~IoOwner() { nrrdIoStateNix(io); }
  } io_owner{nio};
  for (const auto& e : encodings())
    if (e.encoding == encoding) nio->encoding = e.teem;
  nio->format = nrrdFormatNRRD;
  std::vector<std::string> order;
  auto write_through = [&](const std::string& file_name, auto&& body) {
    const int file = stage.create(file_name);
    struct Target {
      StagedOutput* stage;
      int file;
    } target{&stage, file};
    cookie_io_functions_t io{};
    io.write = [](void* cookie, const char* data, size_t size) -> ssize_t {
      auto* t = static_cast<Target*>(cookie);
      return static_cast<ssize_t>(t->stage->write(t->file, data, size));
    };
    std::FILE* f = ::fopencookie(&target, "w", io);
    if (!f) throw Error("cannot write '" + path + "': out of memory");
    const bool failed = body(f);
    const bool flushed = std::fflush(f) == 0 && !std::ferror(f);
    std::fclose(f);
    if (failed || !flushed) throw Error("cannot write '" + path + "': " + teem_error());
    stage.finish(file);  // throws with the first write error
    order.push_back(file_name);
  };
  if (lower_extension(path) == ".nhdr") {
    const std::string data_name = stage.target().stem().string() + "." + nio->encoding->suffix;
    write_through(data_name, [&](std::FILE* f) {
      return nio->encoding->write(f, nout->data, nrrdElementNumber(nout), nout, nio) != 0;
    });
    nio->detachedHeader = AIR_TRUE;
    nio->skipData = AIR_TRUE;
    const unsigned slot = airArrayLenIncr(nio->dataFNArr, 1);
    nio->dataFN[slot] = airStrdup(data_name.c_str());
  }
  write_through(name, [&](std::FILE* f) { return nrrdWrite(f, nout, nio) != 0; });
  stage.commit(order, like ? like->sources : std::vector<FileId>{});
}

}  // namespace ddt
