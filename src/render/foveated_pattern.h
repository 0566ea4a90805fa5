// The sample pattern of foveated sampling (Harada & Fujita 2014; Harada, GPU Pro 7 ch. 4):
// sample positions whose density is highest at the viewer's gaze point and falls off
// towards the periphery, where it stays well below one sample per pixel. The pattern is
// generated once per run, deterministically, as offsets from the gaze; every frame shifts
// it to that frame's gaze and clips it to the screen (foveation_frame.h), so a moving gaze
// costs no regeneration.
//
// | parameter     | default | meaning                                                    |
// |---------------|---------|------------------------------------------------------------|
// | fovea_spp     | 4       | density at the gaze point, samples per pixel, (0, 64]      |
// | fovea_radius  | 0.1     | r0 as a fraction of the image height: density halves at r0 |
// | periphery_spp | 1/16    | floor of the density, samples per pixel, (0, fovea_spp]    |
// | neighbours    | 8       | k: each pixel is interpolated from its k nearest samples   |
// | seed          | fixed   | the pattern's random numbers (not --seed: same every run)  |
//
// density(r) = max(periphery_spp, fovea_spp / (1 + (r / r0)^2)), r in pixels from the gaze.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"

namespace multiray {

struct FoveationParams {
  float fovea_spp = 4.0f;
  float fovea_radius = 0.1f;
  float periphery_spp = 1.0f / 16.0f;
  int neighbours = 8;
  uint64_t seed = 0x666f7665615eedull;
};

// Empty when the parameters are usable, else one line naming the bad one.
std::string check_foveation_params(const FoveationParams& p);

// Samples per pixel at `r_px` pixels from the gaze, for fovea radius `r0_px` pixels.
float foveation_density(const FoveationParams& p, float r_px, float r0_px);

struct FoveationPattern {
  int width = 0, height = 0;  // the image size the pattern was made for
  FoveationParams params;
  // Offsets from the gaze in pixels (x right, y down), covering [-width, width) x
  // [-height, height), so the screen is covered wherever the gaze is. offsets[0] is
  // (0, 0): a sample exactly at the gaze, which every frame keeps, so no frame is empty.
  // A sample's index here is its identity: its random numbers are keyed by it.
  std::vector<Vec2> offsets;
};

// Generates the pattern for images of width x height pixels. Pure function of its
// arguments. The offset plane is cut into blocks of B x B pixel cells, B ~ 1/sqrt(floor),
// so that a block of the periphery expects about one sample; block b gets
// floor(E_b) or floor(E_b) + 1 samples (E_b = its integrated density, the fractional part
// decided by a random number), placed by stratified inverse-CDF choice of a cell
// weighted by density and uniform jitter inside it. Stratifying per block keeps the
// sparse periphery free of the large holes a purely random pattern would leave.
// Throws InputError for a non-positive size or bad parameters.
FoveationPattern make_foveation_pattern(int width, int height, const FoveationParams& p);

}  // namespace multiray
