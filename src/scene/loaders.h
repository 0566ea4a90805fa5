// Scene file loaders. Each returns a validated Scene (see validate() in scene.h) with
// every node transform and instance baked into world space, and throws InputError with a
// one-line message naming the file and the problem on bad input. They never abort on
// malformed data: every count, offset and index read from a file is checked before use.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "core/scene_files.h"
#include "scene/scene.h"

namespace multiray {

// Dispatches on the extension, case-insensitively: .gltf/.glb, .obj, .ply, .xml to their own
// readers, kAssimpExtensions to load_assimp().
Scene load_scene(const std::string& path, const LoadOptions& options = {});

// Extensions (lower case) of the formats read through assimp: each one's sample files in
// Debian's assimp-testmodels load with assimp 5.2.5 (tests/scene/assimp_models_test.cpp).
inline constexpr const char* kAssimpExtensions[] = {
    ".3ds", ".3mf", ".ac",  ".ase",  ".b3d", ".blend", ".cob", ".dae", ".dxf", ".fbx", ".ifc",
    ".lwo", ".lxo", ".md2", ".ms3d", ".off", ".q3o",   ".q3s", ".smd", ".stl", ".x",   ".x3d"};

// Any format assimp 5.2 reads (kAssimpExtensions are the ones load_scene() sends here):
// triangles of every mesh the node hierarchy uses, in world space; per-vertex normals
// and the first uv set where the file has them; materials (see AssimpMaterials) with
// diffuse / base-colour textures from files beside the model or embedded; perspective
// cameras. Every file assimp opens goes through the LoadOptions checks. A missing,
// refused or undecodable texture gives one warning and the material keeps its colour.
// In a build without assimp (MULTIRAY_WITH_ASSIMP) it throws InputError saying so.
Scene load_assimp(const std::string& path, const LoadOptions& options = {});

// glTF 2.0, text (.gltf) or binary (.glb). Triangles of the default scene; materials
// from metallic-roughness plus emissive strength, transmission and IOR extensions, with
// base-colour (and alpha), emissive, metallic-roughness and normal textures; perspective
// cameras. A missing, refused or undecodable image drops that texture with one warning
// per image; each extension the file uses and we ignore gives one warning. A refused buffer
// is an error. Node graphs that would instance more than 2^28 triangles are refused
// before any instance is built.
Scene load_gltf(const std::string& path, const LoadOptions& options = {});

// Wavefront OBJ with its MTL files (Kd, Ke, map_Kd). Without materials every triangle
// gets one diffuse grey material. A refused MTL file or texture gives a warning and
// the faces keep the default material or the plain colour.
Scene load_obj(const std::string& path, const LoadOptions& options = {});

// Stanford PLY, ascii or binary (either byte order): vertex positions, optional normals
// and texture coordinates, polygon faces.
Scene load_ply(const std::string& path, const LoadOptions& options = {});

// Mitsuba 3 scene XML (.xml), the subset simple scenes such as Mitsuba's Cornell box use:
// perspective sensor (with its film size in Camera::film_width/height), diffuse BSDFs
// (rgb or spectral reflectance), area and constant emitters, obj/ply/rectangle/cube
// shapes with to_world. Each other plugin type gives one warning and is skipped or
// replaced by Mitsuba's default. Meshes are found through the file's <path> folders; those
// outside the XML's folder need allow_outside like any other named file.
Scene load_mitsuba(const std::string& path, const LoadOptions& options = {});

// An equirectangular environment map: Radiance .hdr or OpenEXR .exr, as linear RGB.
// The file gets the scene file's checks (regular, non-empty, LoadOptions' byte limit);
// over detail::kMaxTexturePixels pixels is refused. Negative or non-finite values become
// 0 with one warning.
EnvironmentMap load_environment_map(const std::string& path, const LoadOptions& options = {});

// Helpers shared by the loaders (texture_load.cpp). Not part of the public interface.
namespace detail {

// file_name, fail and warn: core/scene_files.h.

// The last step of every loader: replaces unusable shading normals (see
// shading_normal) by face normals, with one warning saying how many, then
// validate(scene), with its message re-issued as "<path>: <problem>" like every other
// loader error.
void validate_loaded(Scene* scene, const std::string& path, const LoadOptions& options);

// `n` scaled to unit length (computed in double, so huge components do not overflow),
// or NaN in every component when `n` has no direction: zero, NaN or infinite. Loaders
// store that NaN and validate_loaded() replaces it by a face normal.
Vec3 shading_normal(Vec3 n);

// Unit normal of triangle a, b, c (right-handed), or +z if it has no area. Computed in
// double: vertices up to 1e18 apart have a cross product whose float length overflows.
Vec3 flat_normal(Vec3 a, Vec3 b, Vec3 c);

// `x` as a float: out-of-range values become +-infinity (a plain cast would be undefined
// behaviour), NaN stays NaN.
float to_float(double x);

// Largest texture decode_texture accepts: 2^28 texels (1 GiB at 4 bytes each, 16k x 16k).
constexpr uint64_t kMaxTexturePixels = uint64_t(1) << 28;

// Decodes an encoded image (JPEG, PNG, ...) with stb_image into a texture whose bytes
// mean `coding`. Returns false, leaving `out` untouched, when the data is not a
// decodable image. Its size is read from its header first and, before anything is
// decoded, passed to options.reserve_image with `what` ("<scene file>: image 'a.png'")
// naming it; that may throw InputError (the load is then refused, not the texture).
bool decode_texture(const unsigned char* bytes, size_t size, Texture* out,
                    const LoadOptions& options, const std::string& what,
                    TexelCoding coding = TexelCoding::srgb);

// " (W x H pixels)", for the `what` of LoadOptions::reserve_image.
std::string pixels_text(int64_t width, int64_t height);

}  // namespace detail
}  // namespace multiray
