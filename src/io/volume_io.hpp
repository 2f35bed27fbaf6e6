#pragma once
// Volume file I/O: NRRD (.nrrd with attached header, .nhdr with a detached
// data file) through Teem's nrrd library, the format's reference
// implementation. image_io.hpp's twin for volumes.
//
// Shared rules:
//   - Every function throws ddt::Error with a one-line message on failure.
//   - Samples are read as stored, converted to float without rescaling
//     (an 8-bit volume stays 0..255, a CT volume keeps its units). Integer
//     output is rounded and clamped to its type's range.
//   - Any encoding Teem reads is accepted (raw, gzip, bzip2, ascii, hex);
//     the output keeps the input's encoding unless asked otherwise.
//   - A volume has 3 spatial axes (2: one slice, nz = 1), or 4 for a
//     volume series (x, y, z, t: Volume::nt time steps), after a leading
//     non-spatial axis when there are channels: the first axis holds the
//     channels when Teem's kind calls it non-spatial (vector, RGB-color,
//     3-vector, 3-color, 4-color, RGBA-color, ...: any kind but domain,
//     space, time and unknown), or, with 4 axes, when it has size 1 (a 3D
//     volume, as before series were read), or with 5 axes whatever its kind
//     but domain, space or time. The channels are read interleaved
//     (Volume::channels). Written volumes keep the input's axes and kinds; a
//     volume of several channels without an input header gets a leading
//     axis of kind 3-vector (3 channels) or vector, a series without one a
//     time axis of kind time.
//   - The time axis of a series is node-centred (its steps are instants)
//     unless its header says "centers: cell" for it: VolumeFile::node_centred.
//   - Writing is atomic and exclusive (safe_file.hpp): everything is
//     written into a private directory beside the target, every write
//     error seen, and renamed into place only after a complete, synced
//     write (data file first, then the header), so a failed run never
//     leaves a truncated file or destroys an existing one. A file the
//     `like` volume was read from (header or data file) is never replaced.
//     A .nhdr output's data file is named <stem>.<suffix of the encoding>
//     (raw, raw.gz, raw.bz2, ascii, hex) beside it.
//
// Geometry: the input's header (space, space directions, origin, spacing,
// units, labels, key/value pairs, comments) is kept and written with the
// output, scaled to the new size. With s = n_out / n_in on an axis and the
// voxel convention of volume.hpp (samples at cell centres):
//   spacing and space direction  /= s
//   space origin (the position of the first sample)
//                                += (0.5 / s - 0.5) * old space direction
//   axis min / max               unchanged (the same cells are covered)
//   centering                    cell
// and on a node-centred axis (a series' time: the first and last samples
// stay where they were), with s = (n_out - 1) / (n_in - 1):
//   spacing and space direction  /= s
//   space origin, axis min / max unchanged
//   centering                    node
// so every output sample sits at its true world position (or instant).

#include "util/size_limits.hpp"
#include "volume/volume.hpp"

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ddt {

enum class VolumeSampleType { int8, uint8, int16, uint16, int32, uint32, int64, uint64, float32, float64 };
enum class VolumeEncoding { raw, gzip, bzip2, ascii, hex };

const char* sample_type_name(VolumeSampleType type);  // "uint8", "float32", ...
const char* encoding_name(VolumeEncoding encoding);   // "raw", "gzip", ...
// Parse the names above (also NRRD's "uchar", "short", "ushort", "float", ...);
// throw ddt::Error listing the valid ones.
VolumeSampleType parse_sample_type(const std::string& name);
VolumeEncoding parse_encoding(const std::string& name);

// The input's header without its samples (opaque; Teem's Nrrd inside).
struct VolumeHeader;

struct VolumeFile {
  Volume volume;
  VolumeSampleType type = VolumeSampleType::float32;
  VolumeEncoding encoding = VolumeEncoding::raw;
  std::shared_ptr<const VolumeHeader> header;  // null for volumes not read from a file
  // Per axis x, y, z, t: samples are instants (node centring). Spatial axes
  // are read as cells (the voxel convention); the time axis of a series as
  // instants unless its header says "centers: cell".
  std::array<bool, 4> node_centred{};
};

// True for the extensions write_volume and read_volume handle: .nrrd, .nhdr
// (case-insensitive).
bool is_volume_path(const std::string& path);

struct VolumeReadOptions {
  // A detached header may name its data file by any path; by default only
  // names inside the header's directory are read (relative, no '..'), so a
  // header from elsewhere cannot make us read, then write out, any file
  // (`data file: /etc/passwd`).
  bool any_data_path = false;
  // Limits checked from the header, before a sample is read or
  // decompressed (size_limits.hpp): the voxel count against max_voxels
  // (named `option` in the refusal), the samples against the memory
  // available; then `check`, when set, sees the size and may throw (the CLI
  // sizes its whole job there: the size, then the channels).
  long long max_voxels = default_max_input_voxels();
  std::string option = "--max-input-voxels";
  std::function<void(const std::array<int, 4>& size, int channels)> check;  // size: nx, ny, nz, nt
};

// Reads a NRRD file. The header and every data file it names must be
// regular files (a device or FIFO is refused before it is opened).
VolumeFile read_volume(const std::string& path, const VolumeReadOptions& options = {});

// The files reading `path` opens: the header, then its data files (paths
// usable from here). Reads the header only; throws as read_volume does.
std::vector<std::string> volume_files(const std::string& path, const VolumeReadOptions& options = {});

// Writes `volume` to `path` (.nrrd or .nhdr) as `type` with `encoding`.
// like: the header of the volume it was made from (may be null); its
// geometry is scaled to `volume`'s size as described above. `comment`, when
// not empty, is added as a NRRD comment line. node_centred: per axis x, y,
// z, t, the output axes written as instants (geometry scaled as above; the
// t flag matters for series only).
void write_volume(const std::string& path, const Volume& volume, VolumeSampleType type, VolumeEncoding encoding,
                  const VolumeHeader* like = nullptr, const std::string& comment = {},
                  const std::array<bool, 4>& node_centred = {false, false, false, true});

// Throws if `output` cannot be written as a volume: it or the data file a
// .nhdr output would write is one of the files `input` is read from (by
// identity: header and data files), not .nrrd/.nhdr, or a directory that
// does not exist or is not writable. Called before any long work.
void check_volume_output_path(const std::string& output, const std::string& input,
                              const VolumeReadOptions& options = {});

}  // namespace ddt
