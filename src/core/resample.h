// Enlarging a view rendered at a reduced image scale back to the output's size (frame-time
// targeting in image space, Bruder et al. 2017 §6, and the viewer while the camera moves).
#pragma once

#include "core/image.h"

namespace multiray {

// Bilinear interpolation of `from` at the centres of `to`'s pixels (any sizes, both at
// least 1 x 1): output pixel (x, y) samples `from` at ((x + 0.5) w_from / w_to - 0.5, the
// same in y), clamped to the outermost pixel centres. A function linear in x and y is
// reproduced exactly between those centres; equal sizes copy. The result depends only on
// the whole smaller image, so it is the same however the frame was split. An alpha channel
// is interpolated the same way (premultiplied colour stays premultiplied); none, none.
// Feature buffers are enlarged by upscale_features (none in `from`: none in `to`).
void upscale_bilinear(const Framebuffer& from, Framebuffer& to);

// `from`'s feature buffers (core/feature_buffers.h) at the same pixel centres as
// upscale_bilinear, into `to` sized to_width x to_height, so that they describe the
// enlarged beauty the denoiser filters:
// - albedo bilinear, normal bilinear and then unit again (0 stays 0: nothing was hit);
// - depth: 1/depth bilinear where the four taps saw one surface (every pair of them runs
//   on smoothly: 1/depth continued from beside the pair predicts it within 5%): on a plane
//   1/depth is affine in the image coordinates, so it is reproduced exactly, where depth
//   itself would bend. Elsewhere (a silhouette, the sky among the taps) the nearest tap's
//   depth: an interpolated one would lie between two surfaces, or be finite beside a
//   miss, and the denoiser's depth weight would join what it must keep apart and svgf's
//   reprojection accept a history from neither surface. (The nearest depth everywhere
//   would make a slanted plane a staircase, whose steps the denoiser's planar depth test
//   takes for edges);
// - variance: sum of w^2 v over the taps, the variance of the enlarged pixel
//   sum w c of independent pixel means (what the denoiser's luminance weight needs; the
//   source pixels' own variance would overstate it by up to 4x where w is 1/4 each).
void upscale_features(const FeatureBuffers& from, int to_width, int to_height, FeatureBuffers& to);

}  // namespace multiray
