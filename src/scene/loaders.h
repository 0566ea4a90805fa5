// Scene file loaders. Each returns a validated Scene (see validate() in scene.h) with
// every node transform and instance baked into world space, and throws InputError with a
// one-line message naming the file and the problem on bad input. They never abort on
// malformed data: every count, offset and index read from a file is checked before use.
#pragma once

#include <string>

#include "scene/scene.h"

namespace multiray {

// Dispatches on the extension, case-insensitively: .gltf/.glb, .obj, .ply.
Scene load_scene(const std::string& path);

// glTF 2.0, text (.gltf) or binary (.glb). Triangles of the default scene; materials
// from metallic-roughness plus emissive strength, transmission and IOR extensions;
// base-colour textures; perspective cameras. Missing or undecodable images only drop
// that texture.
Scene load_gltf(const std::string& path);

// Wavefront OBJ with its MTL files (Kd, Ke, map_Kd). Without materials every triangle
// gets one diffuse grey material.
Scene load_obj(const std::string& path);

// Stanford PLY, ascii or binary (either byte order): vertex positions, optional normals
// and texture coordinates, polygon faces.
Scene load_ply(const std::string& path);

// Helpers shared by the loaders (texture_load.cpp). Not part of the public interface.
namespace detail {

// `path` with directories removed, for Scene::name and messages.
std::string file_name(const std::string& path);

// Throws InputError "<path>: <what>", with line breaks in `what` folded into "; " so the
// message stays one line (library error strings often end in '\n').
[[noreturn]] void fail(const std::string& path, const std::string& what);

// validate(scene), with its message re-issued as "<path>: <problem>" like every other
// loader error.
void validate_loaded(const Scene& scene, const std::string& path);

// Whole file contents. Throws InputError (via fail) when it is missing, not a regular
// file, unreadable or empty.
std::string read_file(const std::string& path);

// Decodes an encoded image (JPEG, PNG, ...) with stb_image. Returns false, leaving `out`
// untouched, when the data is not a decodable image.
bool decode_texture(const unsigned char* bytes, size_t size, Texture* out);
bool decode_texture_file(const std::string& path, Texture* out);

}  // namespace detail
}  // namespace multiray
