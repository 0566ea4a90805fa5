// Checks and conversions shared by the volume loaders (load_nrrd.cpp, load_raw.cpp).
// Private to src/volume. Every function that refuses throws InputError "<path>: <problem>"
// through core/scene_files.h detail::fail, like the scene loaders.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "volume/load_volume.h"

namespace multiray::volume_detail {

// Refuses a grid with an axis outside 1..kMaxVolumeDimension or more than
// kMaxVolumeVoxels voxels. Takes the sizes as read (before any narrowing).
void check_dimensions(const std::string& path, uint64_t nx, uint64_t ny, uint64_t nz);

// The spacing as floats, refused unless each is finite and in [kMinSpacing, kMaxSpacing]
// after conversion to float and the longest is at most kMaxSpacingRatio times the
// shortest. `what` names the source in messages ("spacings", "space directions").
Vec3 checked_spacing(const std::string& path, const double s[3], const char* what);

// Peak bytes a load takes: `file_bytes` held while the decoder produces `decoded_bytes`,
// then the decoded samples while the float values are filled in.
uint64_t load_peak_bytes(uint64_t voxels, uint64_t file_bytes, uint64_t decoded_bytes);

// Refuses the load when `peak_bytes`, or the float values of `voxels` voxels with what
// the renderer keeps per voxel (options.kept_bytes_per_voxel), exceed options.max_bytes
// (0 = no limit).
void check_memory(const std::string& path, const VolumeLoadOptions& options, uint64_t voxels,
                  uint64_t peak_bytes, const std::string& grid);

// `x` with up to 9 significant digits ("1e-300", "0.95703125"), for messages.
std::string number_text(double x);

// Bytes a data file may hold beyond what its voxels need before it is refused unread
// (line and byte skips, gzip overhead); anything between is read and then refused by
// the exact size check with a message saying by how much it is off.
uint64_t data_file_slack(uint64_t data_bytes);

// Refuses `have` bytes of voxel data where exactly `need` are described: "<path>: <what>
// is 1 byte short: it holds 999 bytes of voxel data, 1000 are needed for 10x10x10 uint8"
// (or "too long"). `what` names the data ("data file 'x.raw'", "the file").
void check_data_size(const std::string& path, const std::string& what, uint64_t have,
                     uint64_t need, const std::string& grid);

// The `need` voxel bytes of gzip data `gz` (one or more gzip members, as NRRD's "gzip"
// encoding writes them), after `byte_skip` decoded bytes (-1: the voxels are the last
// `need` decoded bytes). Every zlib status is checked: corrupt data (a failed CRC or
// length check included), a truncated stream, bytes after the last member, and data
// decoding to more or less than described are refused with one line naming `what`. The
// buffer grows with the decoded data, up to skip + need, so data that cannot hold the
// grid never allocate it.
std::string gunzip_voxels(const std::string& path, const std::string& what, std::string_view gz,
                          int64_t byte_skip, uint64_t need, const std::string& grid);

// The most bytes `gzip_bytes` of gzip data can decode to (deflate's ratio bound).
uint64_t max_gunzip_bytes(uint64_t gzip_bytes);

// "256x256x108 int16", for messages.
std::string grid_text(uint64_t nx, uint64_t ny, uint64_t nz, VoxelType type);

// Fills v->values (and min/max) from nx*ny*nz packed voxels of v->type at `data`,
// swapping the bytes of 16-bit voxels when `swap_bytes`.
void set_values(Volume* v, const void* data, bool swap_bytes);

}  // namespace multiray::volume_detail
