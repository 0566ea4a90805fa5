// Wavefront OBJ + MTL through tinyobjloader (Debian's compiled library, float build).
//
// tinyobjloader is lenient in ways that would hide bad input: a coordinate it cannot
// parse ("nan", "abc") silently becomes 0, and out-of-range face indices are only
// warnings. So the vertex lines are checked here first, and every face index is checked
// before use. Faces are read untriangulated and split here (quads along the shorter
// diagonal, larger polygons as fans) so an n-gon always gives n-2 triangles and none
// is dropped silently. Attributes are de-indexed per corner (three vertices per
// triangle), because OBJ indexes positions, normals and uvs separately.
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <system_error>

#include "core/scene_files.h"
#include "scene/loaders.h"

namespace multiray {
namespace {

namespace fs = std::filesystem;

// Rejects `v`, `vn` and `vt` lines whose leading coordinates are missing, not numbers,
// or not finite, naming the line.
void check_vertex_lines(const std::string& path, const std::string& text) {
  size_t pos = 0, line_no = 0;
  while (pos < text.size()) {
    size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    ++line_no;
    const char* p = text.data() + pos;
    const char* end = text.data() + eol;
    pos = eol + 1;
    while (p < end && (*p == ' ' || *p == '\t')) ++p;
    if (end - p < 2 || p[0] != 'v') continue;
    int needed = 0;
    if (p[1] == ' ' || p[1] == '\t')
      needed = 3, p += 1;
    else if (end - p >= 3 && p[1] == 'n' && (p[2] == ' ' || p[2] == '\t'))
      needed = 3, p += 2;
    else if (end - p >= 3 && p[1] == 't' && (p[2] == ' ' || p[2] == '\t'))
      needed = 1, p += 2;
    else
      continue;
    for (int i = 0; i < needed; ++i) {
      while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
      const char* tok = p;
      while (p < end && !std::isspace(static_cast<unsigned char>(*p))) ++p;
      const std::string where = "line " + std::to_string(line_no) + ": ";
      if (tok == p) detail::fail(path, where + "too few coordinates");
      float v = 0;
      const auto [q, ec] = std::from_chars(tok + (*tok == '+' ? 1 : 0), p, v);
      if (ec != std::errc() || q != p || !std::isfinite(v))
        detail::fail(path, where + "coordinate '" +
                               std::string(tok, std::min<size_t>(p - tok, 40)) +
                               "' is not a finite number");
    }
  }
}

// Finds a file named in an OBJ or MTL file, relative to `dir`. Exporters often get the
// letter case wrong (10 of the 18 texture names in Dabrovic Sponza) or use '\'
// separators, so if the exact path does not exist its directory is searched for a name
// differing only in case. Returns "" if there is none. What it returns may be anything
// but a directory (a FIFO, a file outside `dir`): SceneFiles decides whether to read it.
// Only stat() and directory listings here, never open().
std::string resolve_file(const fs::path& dir, std::string name) {
  std::replace(name.begin(), name.end(), '\\', '/');
  const fs::path exact = dir / name;
  std::error_code ec;
  const fs::file_status st = fs::status(exact, ec);
  if (fs::exists(st) && !fs::is_directory(st)) return exact.string();
  auto lower = [](std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  const std::string wanted = lower(exact.filename().string());
  for (fs::directory_iterator it(exact.parent_path(), ec), end; !ec && it != end; it.increment(ec))
    if (lower(it->path().filename().string()) == wanted && !it->is_directory(ec))
      return it->path().string();
  return {};
}

// `mtllib` reader using resolve_file and SceneFiles (tinyobjloader's own reader is
// case-sensitive, splits its search path at ':' and opens whatever it finds). A missing
// or refused MTL file is not an error: the faces then get the default material, with one
// warning per file name.
class MtlReader : public tinyobj::MaterialReader {
 public:
  MtlReader(fs::path dir, SceneFiles* files) : dir_(std::move(dir)), files_(files) {}
  bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* names, std::string* warn,
                  std::string* err) override {
    const std::string file = resolve_file(dir_, name);
    if (file.empty()) {
      if (missing_.insert(name).second)
        detail::warn(files_->options(), files_->scene_path(),
                     "material library '" + name +
                         "' not found; its materials' faces get the default material");
      return false;
    }
    std::string text, why;
    if (!files_->read(file, &text, &why)) {
      detail::warn(files_->options(), files_->scene_path(),
                   "material library refused: " + why + "; its faces get the default material");
      return false;
    }
    std::istringstream in(text);
    tinyobj::LoadMtl(names, materials, &in, warn, err);
    return true;
  }

 private:
  fs::path dir_;
  SceneFiles* files_;
  std::set<std::string> missing_;  // names already warned about
};

// Element i of a flat xyz array (indices checked by the caller).
Vec3 vec3_at(const std::vector<float>& xyz, int i) {
  return Vec3(xyz[3 * size_t(i)], xyz[3 * size_t(i) + 1], xyz[3 * size_t(i) + 2]);
}

}  // namespace

Scene load_obj(const std::string& path, const LoadOptions& options) {
  SceneFiles files(path, options);
  const std::string text = files.read_scene_file();
  check_vertex_lines(path, text);

  const fs::path dir =
      fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> mtls;
  std::string warn, err;
  std::istringstream in(text);
  MtlReader mtl_reader(dir, &files);
  if (!tinyobj::LoadObj(&attrib, &shapes, &mtls, &warn, &err, &in, &mtl_reader,
                        /*triangulate=*/false, /*default_vcols_fallback=*/false))
    detail::fail(path, "malformed OBJ: " + (err.empty() ? std::string("parse error") : err));

  Scene scene;
  scene.name = detail::file_name(path);

  // Materials. Kd -> base colour, Ke -> emission, map_Kd -> texture. Ks/Ns are ignored:
  // the material model has no diffuse+specular layer, and legacy MTL specular values
  // are mostly exporter defaults, so every OBJ material is diffuse.
  std::map<std::string, int> texture_of_file;
  std::set<std::string> missing;  // texture names already warned about
  for (const tinyobj::material_t& m : mtls) {
    Material& out = scene.materials.emplace_back();
    out.name = m.name;
    out.base_color = Vec3(m.diffuse[0], m.diffuse[1], m.diffuse[2]);
    out.emission = Vec3(m.emission[0], m.emission[1], m.emission[2]);
    if (!is_finite(out.base_color) || !is_finite(out.emission))
      detail::fail(path, "material '" + m.name + "' has a non-finite colour");
    if (m.diffuse_texname.empty()) continue;
    const std::string file = resolve_file(dir, m.diffuse_texname);
    if (file.empty()) {  // missing texture: keep the plain colour, and say so once
      if (missing.insert(m.diffuse_texname).second)
        detail::warn(options, path,
                     "texture '" + m.diffuse_texname + "' not found; material '" + m.name +
                         "' (and any other using it) keeps its plain colour");
      continue;
    }
    auto [it, inserted] = texture_of_file.try_emplace(file, -1);
    if (inserted) {
      std::string bytes, why;
      Texture tex;
      if (!files.read(file, &bytes, &why))
        detail::warn(
            options, path,
            "texture refused: " + why + "; material '" + m.name + "' keeps its plain colour");
      else if (detail::decode_texture(reinterpret_cast<const unsigned char*>(bytes.data()),
                                      bytes.size(), &tex, options,
                                      path + ": texture '" + m.diffuse_texname + "'")) {
        it->second = int(scene.textures.size());
        scene.textures.push_back(std::move(tex));
      } else {
        detail::warn(options, path,
                     "texture '" + m.diffuse_texname + "' is not a decodable image (or over " +
                         std::to_string(detail::kMaxTexturePixels) + " pixels); material '" +
                         m.name + "' keeps its plain colour");
      }
    }
    out.base_color_texture = it->second;
  }
  const uint32_t default_material = uint32_t(scene.materials.size());
  bool used_default = false;

  const size_t nv = attrib.vertices.size() / 3, nn = attrib.normals.size() / 3,
               nt = attrib.texcoords.size() / 2;
  const bool with_normals = nn > 0, with_uvs = nt > 0;
  for (const tinyobj::shape_t& shape : shapes) {
    const tinyobj::mesh_t& mesh = shape.mesh;
    size_t total = 0;
    for (unsigned char n : mesh.num_face_vertices) total += n;
    // tinyobjloader stores corner counts as unsigned char; larger faces wrap around.
    if (total != mesh.indices.size())
      detail::fail(path, "shape '" + shape.name + "' has a face with more than 255 corners");
    for (const tinyobj::index_t& c : mesh.indices) {
      auto bad = [&](const char* what, int i, size_t n) {
        detail::fail(path, "shape '" + shape.name + "': face uses " + what + " " +
                               std::to_string(i + 1) + " but the file has only " +
                               std::to_string(n) + " (index out of range)");
      };
      if (c.vertex_index < 0 || size_t(c.vertex_index) >= nv) bad("vertex", c.vertex_index, nv);
      if (c.normal_index < -1 || (c.normal_index >= 0 && size_t(c.normal_index) >= nn))
        bad("normal", c.normal_index, nn);
      if (c.texcoord_index < -1 || (c.texcoord_index >= 0 && size_t(c.texcoord_index) >= nt))
        bad("texture coordinate", c.texcoord_index, nt);
    }

    size_t first = 0;
    for (size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
      const size_t n = mesh.num_face_vertices[f];
      const tinyobj::index_t* c = mesh.indices.data() + first;
      first += n;
      int mat = f < mesh.material_ids.size() ? mesh.material_ids[f] : -1;
      if (mat < 0 || size_t(mat) >= mtls.size()) mat = int(default_material), used_default = true;
      auto pos = [&](size_t k) { return vec3_at(attrib.vertices, c[k].vertex_index); };
      for (size_t k = 1; k + 1 < n; ++k) {
        size_t tri[3] = {0, k, k + 1};
        if (n == 4) {  // split along the shorter diagonal, as tinyobjloader would
          const Vec3 d02 = pos(2) - pos(0), d13 = pos(3) - pos(1);
          const bool diag02 = dot(d02, d02) < dot(d13, d13);
          if (!diag02) tri[0] = k == 1 ? 0 : 1, tri[1] = k == 1 ? 1 : 2, tri[2] = 3;
        }
        const Vec3 flat = detail::flat_normal(pos(tri[0]), pos(tri[1]), pos(tri[2]));
        for (size_t j : tri) {
          scene.indices.push_back(uint32_t(scene.positions.size()));
          scene.positions.push_back(pos(j));
          if (with_normals) {  // corners without a (non-zero) normal get the flat one
            Vec3 n = flat;
            if (c[j].normal_index >= 0) {
              const Vec3 file_n =
                  detail::shading_normal(vec3_at(attrib.normals, c[j].normal_index));
              if (is_finite(file_n)) n = file_n;
            }
            scene.normals.push_back(n);
          }
          if (with_uvs) {  // OBJ has v = 0 at the bottom; Texture wants it at the top
            const int t = c[j].texcoord_index;
            scene.uvs.push_back(t >= 0 ? Vec2{attrib.texcoords[2 * size_t(t)],
                                              1.0f - attrib.texcoords[2 * size_t(t) + 1]}
                                       : Vec2{});
          }
        }
        scene.material_ids.push_back(uint32_t(mat));
      }
    }
  }
  if (scene.positions.size() > UINT32_MAX) detail::fail(path, "too many triangles");
  if (used_default) scene.materials.emplace_back().name = "default";
  detail::validate_loaded(&scene, path, options);
  return scene;
}

}  // namespace multiray
