// The feature buffers (core/feature_buffers.h) of the frames a Refinement averages
// (engine/refinement.h): while the viewer's camera stands, its shown image is the mean of
// progressive frames, and a denoiser guided by features needs them for that image too.
// Albedo and emission are the frames' means; the normal their normalised sum; depth the
// mean over the frames that met a surface (+inf when none did); the variance is pooled
// exactly, as one render of all the frames' samples would estimate it
// (render/shared/aov.h): each frame of S samples gives its mean luminance y_k (the
// beauty's, luminance being linear) and its sum of squared deviations m2_k = v_k S (S - 1),
// and all N S samples have M2 = sum m2_k + S (sum y_k^2 - (sum y_k)^2 / N), variance of
// the mean M2 / ((NS - 1) NS). Albedo, normal and depth equal one render's where every
// frame's samples met a surface (or none did); at silhouettes they weigh frames rather
// than samples.
#pragma once

#include <vector>

#include "core/image.h"

namespace multiray {

class FeatureRefinement {
 public:
  // Forgets the frames so far; the next add() is the first of `pixels` pixels.
  void restart(size_t pixels);
  // Adds the feature buffers of `image` (which must have them), rendered with `spp`
  // samples a pixel, and writes the mean of the frames so far into `out`.
  void add(const Framebuffer& image, int spp, FeatureBuffers& out);

 private:
  int frames_ = 0;
  // Per pixel: sums of albedo (3), normal (3), emission (3), finite depth and the frames
  // that had one, the frames' mean luminance and its square, and their m2.
  std::vector<double> albedo_, normal_, emission_, depth_, y_, y2_, m2_;
  std::vector<int> depth_frames_;
};

}  // namespace multiray
