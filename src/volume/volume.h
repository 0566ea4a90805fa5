// Scalar volumes for the raycaster (Bruder, Frey & Ertl 2017, "Prediction-based load
// balancing and resolution tuning for interactive volume raycasting"): a regular grid of
// samples read from NRRD or raw files, kept in the file's own units so transfer functions
// can speak in them (Hounsfield units for CT). Built once, read-only while rendering.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"

namespace multiray {

// Voxel types a volume file may hold (NRRD names: uchar, char, ushort, short, ...).
enum class VoxelType { u8, i8, u16, i16 };

// "uint8", "int8", "uint16", "int16": the names raw specs and messages use.
const char* voxel_type_name(VoxelType type);
// Bytes one voxel of `type` takes in a file: 1 or 2.
int voxel_bytes(VoxelType type);

// Which way a volume's grid faces a patient, as signed world (grid) axes: where the front
// (anterior) and the top of the head (superior) are. The default camera looks at the front
// with the superior axis up (render/default_view.h). `from_file`: read from NRRD's `space`
// and `space directions`; otherwise the assumed convention (kAssumedOrientation).
struct VolumeOrientation {
  Vec3 anterior{0, 1, 0}, superior{0, 0, 1};
  bool from_file = false;
};

// The anatomical spaces NRRD names (scanner-xyz is DICOM's LPS); `none` for the others
// (3D-right-handed, ...) and for files without a `space` field.
enum class AnatomicalSpace { none, ras, las, lps };

// Without an anatomical space the grid is taken as a stack of axial CT/MR slices the way
// VTK-based tools (InVesalius, vtkDICOMImageReader) write a DICOM series: slices by
// ascending patient z (+z superior), rows bottom-up as the image is displayed (+y
// anterior: DICOM's first row, the anterior one, comes last) and columns from the
// patient's right to left (+x left). That is NRRD's left-anterior-superior with unit
// directions. DICOM's own pixel order (+y posterior, LPS) would show the cranium CT of
// the data folder from behind; docs/volumes.md has the renders that decided it.
inline constexpr AnatomicalSpace kAssumedSpace = AnatomicalSpace::las;

// The orientation of a grid in `space` whose axis i has a space direction with the sign
// signs[i] (+1 or -1; the directions must be axis-aligned, load_nrrd checks): anterior
// and superior in space coordinates, each component flipped with its axis's sign. `none`
// gives kAssumedSpace with unit directions and from_file false.
VolumeOrientation orientation_from_space(AnatomicalSpace space, Vec3 signs = Vec3{1, 1, 1});

struct Volume {
  std::string name;  // file name
  int nx = 0, ny = 0, nz = 0;
  Vec3 spacing{1, 1, 1};  // world units between voxel centres along x, y, z (> 0)
  VoxelType type = VoxelType::u8;
  std::vector<float> values;  // nx*ny*nz samples in the file's units, x fastest, then y, z
  float min_value = 0, max_value = 0;  // over all values
  VolumeOrientation orientation = orientation_from_space(AnatomicalSpace::none);

  size_t voxel_count() const { return size_t(nx) * size_t(ny) * size_t(nz); }
  float at(int x, int y, int z) const {
    return values[(size_t(z) * size_t(ny) + size_t(y)) * size_t(nx) + size_t(x)];
  }
  // World extent of the grid: voxel (i, j, k) has its centre at
  // lower() + ((i, j, k) + 0.5) * spacing; the box is centred on the origin.
  Vec3 extent() const { return Vec3{nx * spacing.x, ny * spacing.y, nz * spacing.z}; }
  Vec3 lower() const { return extent() * -0.5f; }
  Bounds3 bounds() const;
  // The shortest spacing: the "voxel length" step sizes are relative to.
  float voxel_length() const;
};

// Largest grid dimension and voxel count accepted from a file or the command line.
constexpr int kMaxVolumeDimension = 1 << 14;
constexpr size_t kMaxVolumeVoxels = size_t(1) << 31;

}  // namespace multiray
