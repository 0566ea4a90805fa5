// Material mapping for the assimp loader. Legacy formats (3DS, FBX's Phong, DAE's
// <phong>, X) describe surfaces as diffuse + specular with a shininess exponent; multiray
// has one metallic-roughness model, so the diffuse colour becomes the base colour and
// the shininess becomes a roughness. Specular colours are ignored, as in the OBJ loader:
// a dielectric's specular layer is not part of the model.
#include "scene/assimp_material.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <system_error>

#include "scene/loaders.h"

namespace multiray::detail {

namespace fs = std::filesystem;

namespace {

// Property `key` as a float, if the material has it and it is finite.
bool get_number(const aiMaterial& m, const char* key, unsigned type, unsigned index, float* out) {
  ai_real v = 0;
  if (m.Get(key, type, index, v) != AI_SUCCESS || !std::isfinite(v)) return false;
  *out = float(v);
  return true;
}

// Property `key` as a colour, if the material has it; fails on a non-finite one.
bool get_colour(const aiMaterial& m, const char* key, unsigned type, unsigned index,
                const std::string& material, const std::string& path, Vec3* out) {
  aiColor3D c;
  if (m.Get(key, type, index, c) != AI_SUCCESS) return false;
  *out = Vec3(c.r, c.g, c.b);
  if (!is_finite(*out))
    fail(path, "material '" + material + "' has a non-finite colour (" + key + ")");
  return true;
}

// Perceptual roughness of a Phong exponent: the Beckmann / GGX alpha of a Phong lobe is
// about sqrt(2 / (n + 2)) (Walter et al. 2007), and roughness = sqrt(alpha). Exponent 0
// (no highlight) gives 1, 100 about 0.37, 10^4 0.12.
float roughness_of_shininess(float n) {
  n = std::clamp(n, 0.0f, 1e6f);
  return std::sqrt(std::sqrt(2.0f / (n + 2.0f)));
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// `candidate` if it exists and is not a directory, else a file in its folder whose name
// differs only in letter case (exporters from Windows often get the case wrong), else "".
std::string existing_ignoring_case(const fs::path& candidate) {
  std::error_code ec;
  const fs::file_status st = fs::status(candidate, ec);
  if (fs::exists(st) && !fs::is_directory(st)) return candidate.string();
  const std::string wanted = lower(candidate.filename().string());
  for (fs::directory_iterator it(candidate.parent_path(), ec), end; !ec && it != end;
       it.increment(ec))
    if (lower(it->path().filename().string()) == wanted && !it->is_directory(ec))
      return it->path().string();
  return {};
}

}  // namespace

AssimpMaterials::AssimpMaterials(const aiScene& ai, SceneFiles* files, Scene* scene)
    : ai_(ai), files_(files), scene_(scene) {
  dir_ = fs::path(files->scene_path()).parent_path();
  if (dir_.empty()) dir_ = ".";
}

Material AssimpMaterials::convert(const aiMaterial& m) {
  Material out;
  out.name = m.GetName().C_Str();
  const std::string& path = files_->scene_path();
  Vec3 c;
  if (get_colour(m, AI_MATKEY_BASE_COLOR, out.name, path, &c) ||
      get_colour(m, AI_MATKEY_COLOR_DIFFUSE, out.name, path, &c))
    out.base_color = min(max(c, Vec3(0.0f)), Vec3(1.0f));
  if (get_colour(m, AI_MATKEY_COLOR_EMISSIVE, out.name, path, &c)) {
    float intensity = 1;
    if (get_number(m, AI_MATKEY_EMISSIVE_INTENSITY, &intensity))
      intensity = std::max(intensity, 0.f);
    out.emission = max(c, Vec3(0.0f)) * intensity;
  }
  float x = 0;
  if (get_number(m, AI_MATKEY_METALLIC_FACTOR, &x)) out.metallic = std::clamp(x, 0.0f, 1.0f);
  if (get_number(m, AI_MATKEY_ROUGHNESS_FACTOR, &x))
    out.roughness = std::clamp(x, 0.0f, 1.0f);
  else if (get_number(m, AI_MATKEY_SHININESS, &x))
    out.roughness = roughness_of_shininess(x);
  if (get_number(m, AI_MATKEY_OPACITY, &x) && x < 1.0f) {
    out.opacity = std::clamp(x, 0.0f, 1.0f);
    out.alpha_mode = AlphaMode::blend;
  }
  if (get_number(m, AI_MATKEY_TRANSMISSION_FACTOR, &x) && x > 0.0f) {
    out.transmission = std::min(x, 1.0f);
    if (get_number(m, AI_MATKEY_REFRACTI, &x) && x >= 1.0f) out.ior = x;
  }
  aiString name;
  for (aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE})
    if (m.GetTextureCount(type) > 0 && m.GetTexture(type, 0, &name) == AI_SUCCESS) {
      out.base_color_texture = texture(name.C_Str(), out.name);
      break;
    }
  return out;
}

// Texture file `name` next to the model: the path as written (relative to the model's
// folder, or absolute), else its last component in the model's folder, since exporters
// often keep the absolute path of the machine the model was made on ("C:\maps\a.jpg").
// Either in any letter case. "" if neither exists.
std::string AssimpMaterials::find_file(std::string name) const {
  std::replace(name.begin(), name.end(), '\\', '/');
  if (name.empty()) return {};
  std::string found = existing_ignoring_case(dir_ / name);
  const std::string base = fs::path(name).filename().string();
  if (found.empty() && !base.empty() && base != name) found = existing_ignoring_case(dir_ / base);
  return found;
}

int AssimpMaterials::texture(const std::string& name, const std::string& material) {
  const auto cached = cache_.find(name);
  if (cached != cache_.end()) return cached->second;
  int& index = cache_[name] = -1;
  auto drop = [&](const std::string& why) {
    warn(files_->options(), files_->scene_path(),
         "texture '" + name + "' " + why + "; material '" + material + "' keeps its plain colour");
    return -1;
  };
  Texture tex;
  if (const aiTexture* embedded = ai_.GetEmbeddedTexture(name.c_str())) {
    // mHeight == 0: an encoded file (PNG, JPEG) of mWidth bytes; otherwise raw texels.
    if (embedded->mHeight != 0) return drop("is an uncompressed embedded image (not supported)");
    if (!decode_texture(reinterpret_cast<const unsigned char*>(embedded->pcData), embedded->mWidth,
                        &tex, files_->options(),
                        files_->scene_path() + ": texture '" + name + "'"))
      return drop("is not a decodable image");
    return index = add(std::move(tex));
  }
  const std::string file = find_file(name);
  if (file.empty()) return drop("not found");
  std::string bytes, why;
  if (!files_->read(file, &bytes, &why)) return drop("refused: " + why);
  if (!decode_texture(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), &tex,
                      files_->options(), files_->scene_path() + ": texture '" + name + "'"))
    return drop("is not a decodable image (or over " + std::to_string(kMaxTexturePixels) +
                " pixels)");
  return index = add(std::move(tex));
}

int AssimpMaterials::add(Texture tex) {
  scene_->textures.push_back(std::move(tex));
  return int(scene_->textures.size()) - 1;
}

}  // namespace multiray::detail
