#include "engine/refinement.h"

#include <algorithm>

namespace multiray {

namespace {
bool same(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
}  // namespace

bool RefineKey::operator==(const RefineKey& o) const {
  return same(camera.eye, o.camera.eye) && same(camera.target, o.camera.target) &&
         same(camera.up, o.camera.up) && camera.fov_y_deg == o.camera.fov_y_deg &&
         view == o.view && generation == o.generation && image_scale == o.image_scale;
}

Refinement::Refinement(int frame_spp, int target_spp)
    : frame_spp_(std::max(1, frame_spp)), target_spp_(std::max(1, target_spp)) {}

const Framebuffer& Refinement::add(const Framebuffer& image, const RefineKey& key) {
  const bool restart = frames_ == 0 || !(key == key_) || image.width != mean_.width ||
                       image.height != mean_.height || image.alpha.size() != alpha_sum_.size() ||
                       image.features.empty() != mean_.features.empty();
  restarted_ = restart;
  if (!restart && samples() + frame_spp_ > target_spp_) return mean_;  // converged
  if (restart) {
    key_ = key;
    frames_ = 0;
    sum_.assign(image.pixels.size(), Vec3(0.0f));
    alpha_sum_.assign(image.alpha.size(), 0.0f);
    mean_ = Framebuffer(image.width, image.height);
    mean_.alpha.resize(image.alpha.size());
    if (!image.features.empty()) {
      mean_.features.resize(image.width, image.height);
      features_.restart(image.pixels.size());
    }
  }
  ++frames_;
  const float inv = 1.0f / float(frames_);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    sum_[i] = sum_[i] + image.pixels[i];
    mean_.pixels[i] = sum_[i] * inv;
  }
  // An RGBA layer's coverage is averaged like its (premultiplied) colour.
  for (size_t i = 0; i < std::min(image.alpha.size(), alpha_sum_.size()); ++i) {
    alpha_sum_[i] += image.alpha[i];
    mean_.alpha[i] = alpha_sum_[i] * inv;
  }
  if (!image.features.empty()) features_.add(image, frame_spp_, mean_.features);
  return mean_;
}

}  // namespace multiray
