// Volume loaders: NRRD (attached .nrrd or detached .nhdr + data file, read with Teem) and
// headerless raw files described on the command line. Both return a Volume whose values
// are the file's numbers converted to float (no rescaling), or throw InputError with one
// line "<path>: <problem>". They never trust a number from a file: dimensions, voxel
// counts, spacings and file sizes are range-checked before anything is allocated, and
// the memory a load will take is estimated and compared with VolumeLoadOptions::max_bytes
// before it is taken.
#pragma once

#include <cstdint>
#include <string>

#include "volume/volume.h"

namespace multiray {

// What a load may read and take. The defaults are the safe choice for files from
// anywhere; files are checked with stat() before they are opened (a FIFO, directory or
// device is refused, never read), as scene loads do (core/scene_files.h LoadOptions).
struct VolumeLoadOptions {
  // A detached header's data file is read only if it lies inside the header's folder
  // after symlinks and '..' are resolved; true lifts that rule (not the regular-file one).
  bool allow_outside = false;
  // Peak memory one load may take, in bytes (file bytes, decoded samples and the float
  // values together); 0 = no limit.
  uint64_t max_bytes = 0;
  // Bytes per voxel the renderer keeps beside the float values once the load is done (the
  // CPU raycaster's copy in the file's type: render/voxel_grid.h), counted with the load
  // so that a volume that could be read but not rendered is refused before it is read.
  uint64_t kept_bytes_per_voxel = 0;
};

// A headerless raw file: nx*ny*nz voxels of `type`, x fastest, then y, then z.
struct RawVolumeSpec {
  int nx = 0, ny = 0, nz = 0;
  VoxelType type = VoxelType::u8;
  bool big_endian = false;  // byte order of 16-bit voxels
  Vec3 spacing{1, 1, 1};    // world units between voxel centres (each in [1e-6, 1e6])
};

// Largest ratio between a volume's longest and shortest spacing: ray-marching steps are
// relative to the shortest (Volume::voxel_length), so a larger ratio means runaway steps.
constexpr float kMaxSpacingRatio = 1000;
// Range of one spacing value, in world units.
constexpr float kMinSpacing = 1e-6f, kMaxSpacing = 1e6f;

// Reads a NRRD file: `path` is an attached .nrrd or a detached .nhdr whose
// "data file:" names one file (lists and numbered series are refused). Accepts
// dimension 3 only; types uchar/char/ushort/short (any NRRD spelling: uint8, int16, ...);
// encodings raw and gzip; either byte order; "spacings" or axis-aligned "space
// directions" (their lengths; missing: 1; orientation ignored). Raw data must be exactly
// as long as the header says; gzip data must pass zlib's checks (CRC and length included)
// and decode to exactly that, with nothing after the last gzip member.
Volume load_volume(const std::string& path, const VolumeLoadOptions& options = {});

// Reads a raw file described by `spec`; its size must be exactly nx*ny*nz voxels.
Volume load_raw_volume(const std::string& path, const RawVolumeSpec& spec,
                       const VolumeLoadOptions& options = {});

// A raw file's bytes cannot say what they are, but its name often does, in the common
// "<name>_<NX>x<NY>x<NZ>_<type>.raw" convention (bonsai_256x256x256_uint8.raw). Returns
// one line saying how the name's grid or type differs from `spec`, or "" when the name
// gives neither or agrees; *described tells whether it gives either.
std::string raw_name_mismatch(const std::string& path, const RawVolumeSpec& spec, bool* described);

// Parses "NXxNYxNZ:TYPE[:be|:le][:spacing=SX,SY,SZ]", e.g. "256x256x108:int16:le"
// or "256x256x256:uint8:spacing=0.96,0.96,1.5". TYPE: uint8, int8, uint16, int16.
// Throws InputError "raw volume spec '<text>': <problem>".
RawVolumeSpec parse_raw_spec(const std::string& text);

}  // namespace multiray
