// Headerless raw volumes: the grid comes from a command-line spec, the bytes from the
// file, which must hold exactly nx*ny*nz voxels.
#include <bit>
#include <charconv>
#include <filesystem>
#include <string_view>
#include <vector>

#include "core/scene_files.h"
#include "volume/load_volume.h"
#include "volume/volume_input.h"

namespace multiray {

using detail::fail;
using namespace volume_detail;

namespace {

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  for (size_t start = 0;;) {
    const size_t end = s.find(sep, start);
    parts.push_back(s.substr(start, end == std::string_view::npos ? end : end - start));
    if (end == std::string_view::npos) return parts;
    start = end + 1;
  }
}

// A whole number made of digits only (no sign, no spaces), or false.
bool parse_count(std::string_view s, uint64_t* out) {
  if (s.empty() || s.size() > 19) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return std::from_chars(s.data(), s.data() + s.size(), *out).ec == std::errc();
}

bool parse_double(std::string_view s, double* out) {
  if (s.empty() || s.front() == '+' || s.front() == ' ') return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), *out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool parse_type(std::string_view s, VoxelType* out) {
  for (VoxelType t : {VoxelType::u8, VoxelType::i8, VoxelType::u16, VoxelType::i16}) {
    if (s == voxel_type_name(t)) {
      *out = t;
      return true;
    }
  }
  return false;
}

// Applies one ":option" of a spec: "be", "le" or "spacing=SX,SY,SZ". Returns a problem or
// "".
std::string apply_option(std::string_view opt, const std::string& where, RawVolumeSpec* spec,
                         bool* seen_endian, bool* seen_spacing) {
  if (opt == "be" || opt == "le") {
    if (*seen_endian) return "the byte order is given twice";
    *seen_endian = true;
    spec->big_endian = opt == "be";
    return "";
  }
  constexpr std::string_view kSpacing = "spacing=";
  if (opt.substr(0, kSpacing.size()) != kSpacing)
    return "unknown option '" + std::string(opt) + "' (be, le, spacing=SX,SY,SZ)";
  if (*seen_spacing) return "the spacing is given twice";
  *seen_spacing = true;
  const auto v = split(opt.substr(kSpacing.size()), ',');
  double s[3];
  if (v.size() != 3 || !parse_double(v[0], &s[0]) || !parse_double(v[1], &s[1]) ||
      !parse_double(v[2], &s[2]))
    return "spacing must be three numbers SX,SY,SZ";
  spec->spacing = checked_spacing(where, s, "spacing");
  return "";
}

}  // namespace

RawVolumeSpec parse_raw_spec(const std::string& text) {
  const std::string where = "raw volume spec '" + text + "'";
  const auto parts = split(text, ':');
  const auto dims = split(parts[0], 'x');
  uint64_t n[3] = {};
  if (dims.size() != 3 || !parse_count(dims[0], &n[0]) || !parse_count(dims[1], &n[1]) ||
      !parse_count(dims[2], &n[2]))
    fail(where, "the grid must be NXxNYxNZ with whole numbers, e.g. 256x256x108:int16");
  check_dimensions(where, n[0], n[1], n[2]);
  RawVolumeSpec spec;
  spec.nx = int(n[0]), spec.ny = int(n[1]), spec.nz = int(n[2]);
  if (parts.size() < 2) fail(where, "the voxel type is missing (uint8, int8, uint16, int16)");
  if (!parse_type(parts[1], &spec.type))
    fail(where, "unknown voxel type '" + std::string(parts[1]) + "' (uint8, int8, uint16, int16)");
  bool seen_endian = false, seen_spacing = false;
  for (size_t i = 2; i < parts.size(); ++i) {
    const std::string problem = apply_option(parts[i], where, &spec, &seen_endian, &seen_spacing);
    if (!problem.empty()) fail(where, problem);
  }
  return spec;
}

std::string raw_name_mismatch(const std::string& path, const RawVolumeSpec& spec,
                              bool* described) {
  const std::string stem = std::filesystem::path(path).stem().string();
  uint64_t n[3] = {};
  std::string grid, type;  // as the name gives them
  for (std::string_view token : split(stem, '_')) {
    const auto dims = split(token, 'x');
    uint64_t d[3];
    if (dims.size() == 3 && parse_count(dims[0], &d[0]) && parse_count(dims[1], &d[1]) &&
        parse_count(dims[2], &d[2]))
      grid = std::string(token), n[0] = d[0], n[1] = d[1], n[2] = d[2];
    // A byte order may follow the type: int16le, uint16be.
    const std::string_view bare = token.size() > 2 && (token.substr(token.size() - 2) == "le" ||
                                                       token.substr(token.size() - 2) == "be")
                                      ? token.substr(0, token.size() - 2)
                                      : token;
    for (const char* t : {"uint8", "int8", "uint16", "int16", "uint32", "int32", "float32",
                          "float64", "float", "double"})
      if (token == t || bare == t) type = t;
  }
  *described = !grid.empty() || !type.empty();
  const bool grid_differs =
      !grid.empty() &&
      (n[0] != uint64_t(spec.nx) || n[1] != uint64_t(spec.ny) || n[2] != uint64_t(spec.nz));
  const bool type_differs = !type.empty() && type != voxel_type_name(spec.type);
  if (!grid_differs && !type_differs) return "";
  const std::string named = grid + (grid.empty() || type.empty() ? "" : " ") + type;
  return "its name says " + named + ", but --raw reads it as " +
         grid_text(uint64_t(spec.nx), uint64_t(spec.ny), uint64_t(spec.nz), spec.type) +
         " (the data cannot tell which is right; check --raw)";
}

Volume load_raw_volume(const std::string& path, const RawVolumeSpec& spec,
                       const VolumeLoadOptions& options) {
  // The spec may come from code rather than parse_raw_spec: check it again.
  if (spec.nx < 0 || spec.ny < 0 || spec.nz < 0)
    fail(path, "raw volume grid " + std::to_string(spec.nx) + "x" + std::to_string(spec.ny) + "x" +
                   std::to_string(spec.nz) + " has a negative axis");
  check_dimensions(path, uint64_t(spec.nx), uint64_t(spec.ny), uint64_t(spec.nz));
  const double s[3] = {spec.spacing.x, spec.spacing.y, spec.spacing.z};
  Volume v;
  v.name = detail::file_name(path);
  v.nx = spec.nx, v.ny = spec.ny, v.nz = spec.nz;
  v.type = spec.type;
  v.spacing = checked_spacing(path, s, "spacing");
  const uint64_t need = uint64_t(v.voxel_count()) * uint64_t(voxel_bytes(v.type));
  const std::string grid = grid_text(v.nx, v.ny, v.nz, v.type);
  // The file's bytes are the decoded samples: they are held while the floats are filled.
  check_memory(path, options, v.voxel_count(), load_peak_bytes(v.voxel_count(), need, need), grid);

  LoadOptions read_options;
  read_options.max_total_bytes = need + data_file_slack(need);
  SceneFiles files(path, read_options);
  const std::string bytes = files.read_scene_file();
  check_data_size(path, "the file", bytes.size(), need, grid);
  const bool host_big = std::endian::native == std::endian::big;
  set_values(&v, bytes.data(), spec.big_endian != host_big);
  return v;
}

}  // namespace multiray
