// Feature buffers (AOVs, "arbitrary output variables"): what the path tracer records
// beside the beauty when asked (RenderSettings::feature_buffers), for a denoiser of ours
// or for other tools (Open Image Denoise, Blender's compositor) through the multi-layer
// EXR of core/aov_exr.h. What each value means, exactly, is render/shared/aov.h's contract
// (written once for every backend); docs/noise.md says it for users.
//
// They travel with the beauty: a Framebuffer holds them (empty when not asked for), every
// device writes the pixels of its own items, MPI workers send them with their results.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "util/rect.h"

namespace multiray {

// The path tracer's feature buffers of one view, row-major with y = 0 at the top like
// Framebuffer::pixels. All five are sized together (empty(): none asked for).
struct FeatureBuffers {
  int width = 0, height = 0;
  std::vector<float> albedo;    // 3 per pixel: R, G, B; linear, in [0, 1]; 0 where nothing
  std::vector<float> normal;    // 3 per pixel: X, Y, Z, world space, unit; 0 where nothing
  std::vector<float> depth;     // 1 per pixel: along the camera axis; +inf where nothing
  std::vector<float> variance;  // 1 per pixel: of the mean luminance over its samples
  std::vector<float> emission;  // 3 per pixel: R, G, B; emitters seen directly or via glass

  bool empty() const { return depth.empty(); }
  // Sizes all five for w x h pixels (kept when the size is right: values are overwritten
  // by the next frame's render of every pixel).
  void resize(int w, int h);
  void clear() { *this = FeatureBuffers{}; }

  // Pixel `i`'s eleven values in packed order (render/shared/aov.h: albedo R, G, B, normal
  // X, Y, Z, depth, variance, emission R, G, B): how kernels hand them over and MPI
  // workers send them.
  static constexpr int kFloats = 11;
  void set_packed(size_t i, const float* v);
  void get_packed(size_t i, float* v) const;
};

// The packed values of the pixels of `r`, row-major (what an MPI worker sends), and back
// into `f` (which must be sized; `v` must hold r.area() x kFloats values).
std::vector<float> packed_features(const FeatureBuffers& f, Rect r);
void unpack_features(const std::vector<float>& v, Rect r, FeatureBuffers& f);

// XXH3 (64 bit) over every float bit of the five buffers, each seeded with the hash so far
// (image_hash's for features).
uint64_t feature_hash(const FeatureBuffers& f, uint64_t seed = 0xcbf29ce484222325ull);

// The AOV names of --aov and Python's aov=[...], in the order of the EXR's layers.
const std::vector<std::string>& aov_names();
// "albedo,normal" -> {"albedo", "normal"} (in aov_names() order, each once). Throws
// InputError naming `option` for an empty list or an unknown name, with the nearest known
// name when one is near ("did you mean normal?").
std::vector<std::string> parse_aov_list(const std::string& list, const std::string& option);
// Checks each of `names` as parse_aov_list does; returns them in aov_names() order.
std::vector<std::string> check_aov_names(const std::vector<std::string>& names,
                                         const std::string& option);

}  // namespace multiray
