// NRRD volumes through Teem (http://teem.sourceforge.net/nrrd/format.html). Teem reads
// only from memory (nrrd_header.h says why): the header is parsed first without data to
// check the grid, type, encoding and memory; only then is the data file read (through
// core/scene_files.h, which refuses FIFOs, devices and files outside the folder) and
// decoded by Teem from the header plus the data (raw encoding), or by zlib (gzip, see
// gzip_data.cpp).
#include <teem/biff.h>
#include <teem/nrrd.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "core/scene_files.h"
#include "volume/load_volume.h"
#include "volume/nrrd_header.h"
#include "volume/volume_input.h"

namespace multiray {

using detail::fail;
using namespace volume_detail;

namespace {

// Teem reports errors through biff's global message store: one load at a time.
std::mutex teem_mutex;

// Owns what one Teem read allocates.
struct TeemRead {
  Nrrd* nrrd = nrrdNew();
  NrrdIoState* nio = nrrdIoStateNew();
  ~TeemRead() {
    nrrdNuke(nrrd);
    nrrdIoStateNix(nio);
  }
};

// Teem's error as one line: its innermost cause without the "[nrrd] function:" prefixes
// (biff lists the callers first, the cause last). Frees biff's message.
std::string teem_problem() {
  char* all = biffGetDone(NRRD);
  std::string text = all ? all : "";
  std::free(all);
  std::string best;
  size_t pos = 0;
  while (pos < text.size()) {
    size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    std::string line = text.substr(pos, eol - pos);
    pos = eol + 1;
    const size_t colon = line.find(": ");
    if (colon != std::string::npos) line = line.substr(colon + 2);
    if (!line.empty() && line != "trouble") best = line;
  }
  return best.empty() ? "Teem could not read it" : best;
}

// Runs Teem's nrrdRead over `parts` (header, blank line, data) into `r`; `header_only`
// skips the data. Throws InputError "<path>: <what>: <Teem's reason>".
void teem_read(const std::string& path, std::vector<std::string_view> parts, bool header_only,
               const std::string& what, TeemRead* r) {
  SpanFile file(std::move(parts));
  r->nio->skipData = header_only ? AIR_TRUE : AIR_FALSE;
  std::lock_guard<std::mutex> lock(teem_mutex);
  if (nrrdRead(r->nrrd, file.get(), r->nio) != 0) fail(path, what + ": " + teem_problem());
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower((unsigned char)c));
  return s;
}

VoxelType voxel_type(const std::string& path, int teem_type) {
  switch (teem_type) {
    case nrrdTypeUChar:
      return VoxelType::u8;
    case nrrdTypeChar:
      return VoxelType::i8;
    case nrrdTypeUShort:
      return VoxelType::u16;
    case nrrdTypeShort:
      return VoxelType::i16;
  }
  fail(path, std::string("voxel type '") + airEnumStr(nrrdType, teem_type) +
                 "' is not supported (uint8, int8, uint16, int16 are)");
}

// Spacing from "spacings" or axis-aligned "space directions"; 1 where neither is given.
Vec3 header_spacing(const std::string& path, const Nrrd* n, const NrrdIoState* nio) {
  double s[3] = {1, 1, 1};
  if (nio->seen[nrrdField_space_directions]) {
    if (n->spaceDim != 3) fail(path, "space directions: only 3-D spaces are supported");
    for (int a = 0; a < 3; ++a) {
      for (int j = 0; j < 3; ++j) {
        const double d = n->axis[a].spaceDirection[j];
        if (!std::isfinite(d))
          fail(path, "space directions: axis " + std::to_string(a) + " has no finite vector");
        if (j != a && d != 0)
          fail(path, "space directions are not axis-aligned (rotated or permuted grids are " +
                         std::string("not supported)"));
      }
      s[a] = std::fabs(n->axis[a].spaceDirection[a]);
    }
    return checked_spacing(path, s, "space directions");
  }
  if (!nio->seen[nrrdField_spacings]) return Vec3{1, 1, 1};
  for (int a = 0; a < 3; ++a) s[a] = n->axis[a].spacing;
  return checked_spacing(path, s, "spacings");
}

// The orientation `space` and the signs of axis-aligned `space directions` give
// (volume.h); the assumed one without an anatomical space.
VolumeOrientation header_orientation(const Nrrd* n, const NrrdIoState* nio) {
  AnatomicalSpace space = AnatomicalSpace::none;
  if (nio->seen[nrrdField_space]) switch (n->space) {
      case nrrdSpaceRightAnteriorSuperior:
        space = AnatomicalSpace::ras;
        break;
      case nrrdSpaceLeftAnteriorSuperior:
        space = AnatomicalSpace::las;
        break;
      case nrrdSpaceLeftPosteriorSuperior:
      case nrrdSpaceScannerXYZ:
        space = AnatomicalSpace::lps;
        break;
      default:
        break;
    }
  Vec3 signs{1, 1, 1};
  if (nio->seen[nrrdField_space_directions] && n->spaceDim == 3)
    for (int a = 0; a < 3; ++a) signs[a] = n->axis[a].spaceDirection[a] < 0 ? -1.0f : 1.0f;
  return orientation_from_space(space, signs);
}

// The grid, type, spacing and orientation of a parsed header, each checked.
Volume checked_header(const std::string& path, const TeemRead& r) {
  const Nrrd* n = r.nrrd;
  if (n->dim != 3)
    fail(path, "has " + std::to_string(n->dim) + " dimensions; volumes need exactly 3");
  check_dimensions(path, n->axis[0].size, n->axis[1].size, n->axis[2].size);
  Volume v;
  v.name = detail::file_name(path);
  v.nx = int(n->axis[0].size), v.ny = int(n->axis[1].size), v.nz = int(n->axis[2].size);
  v.type = voxel_type(path, n->type);
  v.spacing = header_spacing(path, n, r.nio);
  v.orientation = header_orientation(n, r.nio);
  const NrrdEncoding* e = r.nio->encoding;
  if (e != nrrdEncodingRaw && e != nrrdEncodingGzip)
    fail(path, "encoding '" + lower(e->name) + "' is not supported (raw, gzip are)");
  return v;
}

// Where the data start after the header's line skip (for gzip data, the lines are
// skipped before decoding).
uint64_t after_line_skip(std::string_view data, uint64_t line_skip) {
  uint64_t offset = 0;
  for (uint64_t l = 0; l < line_skip && offset < data.size(); ++l) {
    const size_t eol = data.find('\n', offset);
    offset = eol == std::string_view::npos ? data.size() : eol + 1;
  }
  return offset;
}

// Raw data must be exactly as long as the grid after the header's line and byte skips
// (byte skip -1 means "the last bytes of the file": only a shortfall can be seen).
void check_raw_size(const std::string& path, const std::string& what, std::string_view data,
                    const NrrdHeaderParts& parts, uint64_t need, const std::string& grid) {
  uint64_t offset = after_line_skip(data, parts.line_skip);
  if (parts.byte_skip > 0) offset += uint64_t(parts.byte_skip);
  const uint64_t have = offset < data.size() ? data.size() - offset : 0;
  if (parts.byte_skip == -1 && have >= need) return;
  check_data_size(path, what, have, need, grid);
}

// Reads the data file a detached header names into `*bytes`, through the same checks as
// a scene's files (regular file, inside the header's folder unless allowed), refusing
// one far longer than the header describes unread.
void read_data_file(const std::string& path, const NrrdHeaderParts& parts,
                    const VolumeLoadOptions& options, uint64_t need, std::string* bytes) {
  const std::filesystem::path name(parts.data_file);
  const std::string file = name.is_absolute()
                               ? parts.data_file
                               : (std::filesystem::path(path).parent_path() / name).string();
  LoadOptions read_options;
  read_options.allow_outside = options.allow_outside;
  const uint64_t skip = parts.byte_skip > 0 ? uint64_t(parts.byte_skip) : 0;
  read_options.max_total_bytes = skip + need + data_file_slack(need);
  SceneFiles files(path, read_options);
  std::string why;
  if (!files.read(file, bytes, &why)) fail(path, "data file " + why);
}

}  // namespace

Volume load_volume(const std::string& path, const VolumeLoadOptions& options) {
  LoadOptions read_options;
  read_options.max_total_bytes =
      options.max_bytes ? options.max_bytes : 2 * kMaxVolumeVoxels + (uint64_t(1) << 30);
  std::string text = SceneFiles(path, read_options).read_scene_file();
  const NrrdHeaderParts parts = split_nrrd_header(path, text);
  const bool attached = parts.data_file.empty();
  if (attached && !parts.has_blank_line)
    fail(path, "has no 'data file:' line and no data after its header");

  TeemRead head;
  teem_read(path, {parts.header_no_skips, "\n"}, /*header_only=*/true, "NRRD header", &head);
  Volume v = checked_header(path, head);
  const uint64_t need = uint64_t(v.voxel_count()) * uint64_t(voxel_bytes(v.type));
  const std::string grid = grid_text(v.nx, v.ny, v.nz, v.type);
  const uint64_t file_bytes = text.size() + (attached ? 0 : need);  // data file: estimated
  check_memory(path, options, v.voxel_count(), load_peak_bytes(v.voxel_count(), file_bytes, need),
               grid);

  std::string detached;
  if (!attached) read_data_file(path, parts, options, need, &detached);
  const std::string_view data =
      attached ? std::string_view(text).substr(parts.data_offset) : std::string_view(detached);
  const std::string what =
      attached ? "the data after the header" : "data file '" + parts.data_file + "'";
  if (head.nio->encoding == nrrdEncodingGzip) {
    // Decoded here, every zlib status and the decoded length checked (gzip_data.cpp).
    const std::string voxels =
        gunzip_voxels(path, what, data.substr(after_line_skip(data, parts.line_skip)),
                      parts.byte_skip, need, grid);
    std::string().swap(text);
    std::string().swap(detached);
    // Teem's header check has made sure 16-bit data name their byte order.
    set_values(&v, voxels.data(), voxel_bytes(v.type) > 1 && head.nio->endian != airMyEndian());
    return v;
  }
  check_raw_size(path, what, data, parts, need, grid);

  TeemRead full;
  teem_read(path, {parts.header, "\n", data}, /*header_only=*/false, what, &full);
  if (full.nrrd->data == nullptr || nrrdElementNumber(full.nrrd) != v.voxel_count() ||
      full.nrrd->type != head.nrrd->type)
    fail(path, "NRRD: the data read does not match the header");
  std::string().swap(text);  // the file bytes are no longer needed
  std::string().swap(detached);
  // Teem has swapped the samples to this machine's byte order.
  set_values(&v, full.nrrd->data, false);
  return v;
}

}  // namespace multiray
