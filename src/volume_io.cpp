#include "volume_io.hpp"

#include "error.hpp"

#include <teem/nrrd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <system_error>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace ddt {

struct VolumeHeader {
  Nrrd* nrrd = nullptr;  // sizes and metadata; data freed
  unsigned axis0 = 0;    // index of the x axis (1 when a size-1 axis leads)
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

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
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

VolumeFile read_volume(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error("cannot read '" + path + "': no such file");
  if (fs::is_directory(path, ec)) throw Error("cannot read '" + path + "': it is a directory");
  auto header = std::make_shared<VolumeHeader>();
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

  std::size_t size[3] = {1, 1, 1};
  if (nin->dim == 2 || nin->dim == 3) {
    for (unsigned a = 0; a < nin->dim; ++a) size[a] = nin->axis[a].size;
  } else if (nin->dim == 4 && nin->axis[0].size == 1) {
    header->axis0 = 1;
    for (unsigned a = 0; a < 3; ++a) size[a] = nin->axis[a + 1].size;
  } else {
    std::string sizes;
    for (unsigned a = 0; a < nin->dim; ++a) {
      if (a) sizes.push_back('x');
      sizes.append(std::to_string(nin->axis[a].size));
    }
    throw Error("cannot read '" + path + "': a scalar volume has 3 axes, this NRRD has " + std::to_string(nin->dim) +
                " (" + sizes + ")");
  }
  for (std::size_t s : size)
    if (s == 0 || s > static_cast<std::size_t>(std::numeric_limits<int>::max()))
      throw Error("cannot read '" + path + "': an axis has size 0 or is too large");
  file.volume = Volume(static_cast<int>(size[0]), static_cast<int>(size[1]), static_cast<int>(size[2]));
  const std::size_t n = file.volume.voxel_count();
  for (std::size_t i = 0; i < n; ++i) {
    const double v = nrrdDLookup[nin->type](nin->data, i);
    if (!std::isfinite(v)) throw Error("cannot read '" + path + "': the volume holds NaN or infinite samples");
    file.volume.voxels[i] = static_cast<float>(v);
  }
  nin->data = airFree(nin->data);
  file.header = header;
  return file;
}

void check_volume_output_path(const std::string& output, const std::string& input) {
  std::error_code ec;
  if (output.empty()) throw Error("no output file given");
  if (!is_volume_path(output))
    throw Error("cannot write '" + output + "': a volume is written as .nrrd or .nhdr");
  if (!input.empty() && fs::exists(output, ec) && fs::equivalent(output, input, ec))
    throw Error("output '" + output + "' is the input file; refusing to overwrite it");
  if (!input.empty() && fs::weakly_canonical(output, ec) == fs::weakly_canonical(input, ec))
    throw Error("output '" + output + "' is the input file; refusing to overwrite it");
  if (fs::is_directory(output, ec)) throw Error("output '" + output + "' is a directory");
  fs::path dir = fs::path(output).parent_path();
  if (dir.empty()) dir = ".";
  if (!fs::is_directory(dir, ec)) throw Error("output directory '" + dir.string() + "' does not exist");
  if (::access(dir.c_str(), W_OK) != 0) throw Error("output directory '" + dir.string() + "' is not writable");
}

void write_volume(const std::string& path, const Volume& volume, VolumeSampleType type, VolumeEncoding encoding,
                  const VolumeHeader* like, const std::string& comment) {
  if (volume.empty()) throw Error("cannot write '" + path + "': the volume is empty");
  if (!is_volume_path(path)) throw Error("cannot write '" + path + "': a volume is written as .nrrd or .nhdr");
  const TypeInfo& info = type_info(type);
  struct NrrdOwner {
    Nrrd* n = nrrdNew();
    ~NrrdOwner() { nrrdNuke(n); }
  } owner;
  Nrrd* nout = owner.n;
  const unsigned axis0 = like ? like->axis0 : 0;
  const bool flat = like && like->nrrd->dim == 2 && volume.nz == 1;
  int failed = 0;
  const std::size_t nx = volume.nx, ny = volume.ny, nz = volume.nz;
  if (axis0 == 1) failed = nrrdAlloc_va(nout, info.teem, 4, std::size_t(1), nx, ny, nz);
  else if (flat) failed = nrrdAlloc_va(nout, info.teem, 2, nx, ny);
  else failed = nrrdAlloc_va(nout, info.teem, 3, nx, ny, nz);
  if (failed) throw Error("cannot write '" + path + "': " + teem_error());
  const std::size_t n = volume.voxel_count();
  for (std::size_t i = 0; i < n; ++i) {
    double v = volume.voxels[i];
    if (info.integer) v = std::clamp(std::nearbyint(v), info.lo, info.hi);
    nrrdDInsert[info.teem](nout->data, i, v);
  }
  const unsigned spatial = flat ? 2 : 3;
  if (like) {
    const Nrrd* nin = like->nrrd;
    if (nrrdBasicInfoCopy(nout, nin,
                          NRRD_BASIC_INFO_DATA_BIT | NRRD_BASIC_INFO_TYPE_BIT | NRRD_BASIC_INFO_BLOCKSIZE_BIT |
                              NRRD_BASIC_INFO_DIMENSION_BIT | NRRD_BASIC_INFO_OLDMIN_BIT | NRRD_BASIC_INFO_OLDMAX_BIT) ||
        nrrdAxisInfoCopy(nout, nin, nullptr, NRRD_AXIS_INFO_SIZE_BIT))
      throw Error("cannot write '" + path + "': " + teem_error());
    const std::size_t new_size[3] = {nx, ny, nz};
    for (unsigned a = 0; a < spatial; ++a) {
      NrrdAxisInfo& ax = nout->axis[axis0 + a];
      const double s = double(new_size[a]) / double(nin->axis[axis0 + a].size);
      if (std::isfinite(ax.spacing)) ax.spacing /= s;
      if (std::isfinite(ax.thickness)) ax.thickness /= s;
      if (nout->spaceDim > 0 && std::isfinite(ax.spaceDirection[0])) {
        const bool origin = std::isfinite(nout->spaceOrigin[0]);
        for (unsigned d = 0; d < nout->spaceDim; ++d) {
          if (origin) nout->spaceOrigin[d] += (0.5 / s - 0.5) * ax.spaceDirection[d];
          ax.spaceDirection[d] /= s;
        }
      }
      ax.center = nrrdCenterCell;
    }
  } else {
    for (unsigned a = 0; a < spatial; ++a) nout->axis[a].center = nrrdCenterCell;
  }
  if (!comment.empty()) nrrdCommentAdd(nout, comment.c_str());

  // Write into a fresh directory beside the target under the final names
  // (a detached header names its data file relatively), then rename.
  const fs::path target(path);
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::string pattern = (dir / ".ddtscale-XXXXXX").string();
  if (!mkdtemp(pattern.data())) throw Error("cannot write '" + path + "': cannot create a temporary directory");
  const fs::path tmp_dir(pattern);
  auto cleanup = [&] {
    std::error_code ec;
    fs::remove_all(tmp_dir, ec);
  };
  NrrdIoState* nio = nrrdIoStateNew();
  for (const auto& e : encodings())
    if (e.encoding == encoding) nio->encoding = e.teem;
  const int save_failed = nrrdSave((tmp_dir / target.filename()).string().c_str(), nout, nio);
  nrrdIoStateNix(nio);
  if (save_failed) {
    const std::string why = teem_error();
    cleanup();
    throw Error("cannot write '" + path + "': " + why);
  }
  std::vector<fs::path> written;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(tmp_dir, ec)) written.push_back(entry.path());
  std::stable_partition(written.begin(), written.end(), [&](const fs::path& p) { return p.filename() != target.filename(); });
  for (const fs::path& p : written) {
    fs::rename(p, dir / p.filename(), ec);
    if (ec) {
      cleanup();
      throw Error("cannot write '" + path + "': " + ec.message());
    }
  }
  cleanup();
}

}  // namespace ddt
