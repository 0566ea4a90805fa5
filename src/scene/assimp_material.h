// Materials of an assimp scene in multiray's one material model (scene.h), with their
// diffuse / base-colour textures. Private to src/scene (load_assimp.cpp); only built
// with assimp.
#pragma once

#include <assimp/material.h>
#include <assimp/scene.h>

#include <filesystem>
#include <map>
#include <string>

#include "core/scene_files.h"
#include "scene/scene.h"

namespace multiray::detail {

// Converts materials and decodes their textures into one Scene, each texture file once.
class AssimpMaterials {
 public:
  // `files` reads texture files (so LoadOptions apply to them); textures are appended to
  // `scene->textures`. All three must outlive this object.
  AssimpMaterials(const aiScene& ai, SceneFiles* files, Scene* scene);

  // Contract: base colour from $clr.base (PBR files) or the diffuse colour, clamped to
  // [0, 1]; emission = emissive colour x emissive intensity; metallic and roughness from
  // the PBR factors, else roughness from the Phong shininess (metallic 0); opacity < 1
  // gives alpha blending; transmission and refraction index where the file has a
  // transmission factor. The first base-colour or diffuse texture multiplies the base
  // colour. A non-finite colour is an error (InputError naming the material).
  Material convert(const aiMaterial& m);

 private:
  // Index into scene_->textures of the texture `name` (as the material spells it: a
  // file path or "*N" for an embedded image), or -1 with one warning per name when it
  // is missing, refused or not decodable.
  int texture(const std::string& name, const std::string& material);
  // Path of texture file `name` next to the model, or "" if none (see the .cpp).
  std::string find_file(std::string name) const;
  int add(Texture tex);

  const aiScene& ai_;
  SceneFiles* files_;
  Scene* scene_;
  std::filesystem::path dir_;         // the model file's folder
  std::map<std::string, int> cache_;  // texture name -> index or -1
};

}  // namespace multiray::detail
