// The first pass of adaptive edge sampling (Harada, GPU Pro 7 ch. 4, after Mitchell 1987,
// "Generating antialiased images at low sampling densities"): primary hits through pixel
// centres give depth and normal, an edge detector marks pixels on geometric edges, and
// those get more samples. The map changes every frame as the camera moves.
#pragma once

#include <cstdint>
#include <vector>

#include "render/render_types.h"

namespace multiray {

struct GBuffer {
  int width = 0, height = 0;
  std::vector<float> depth;  // view-space depth (along the camera axis); infinity on a miss
  std::vector<Vec3> normal;  // unit geometric normal facing the camera (0 on a miss)
};

// One ray per pixel centre, rows spread over the calling thread's TBB arena.
GBuffer render_gbuffer(const RenderScene& rs, const ViewSetup& view);

struct EdgeOptions {
  float depth_tolerance = 0.05f;  // relative second difference of 1/depth that is an edge
  float normal_tolerance = 0.9f;  // cosine below which neighbouring normals are an edge
};

// True for pixels on a geometric edge: a 4-neighbour differs in hit/miss or in normal
// beyond the tolerance, or 1/depth bends (second difference along x or y above
// depth_tolerance times its value). 1/depth is affine in screen space on any plane, so
// surfaces seen at grazing angles are not edges, while depth steps and creases are.
// Pure function of the buffer.
std::vector<uint8_t> detect_edges(const GBuffer& g, const EdgeOptions& o = {});

// Samples per pixel: `edge_spp` on edges, `base_spp` elsewhere.
std::vector<uint8_t> edge_sample_map(const std::vector<uint8_t>& edges, int edge_spp,
                                     int base_spp);

}  // namespace multiray
