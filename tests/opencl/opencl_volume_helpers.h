// Shared by the OpenCL volume tests: synthetic and real volume scenes, volume settings and
// a per-pixel comparison of two images.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "render/volume_raycaster.h"
#include "volume/load_volume.h"

namespace multiray::testing {

// A volume scene: the volume, a scene holding it with one camera, and a style. Held by
// unique_ptr (the cache refers to the scene).
struct VolumeCase {
  std::shared_ptr<Volume> volume;
  Scene scene;
  std::unique_ptr<SceneCache> cache;
  std::shared_ptr<VolumeStyle> style;
};

// Finishes `c` around `c.volume`: the camera at `eye` looking at the centre, a style for
// `tf` with a step of 0.5 voxels on a dark-blue background.
inline void finish_case(VolumeCase& c, Vec3 eye, const TransferFunction& tf) {
  c.scene.name = c.volume->name;
  c.scene.volume = c.volume;
  Camera cam;
  cam.eye = eye;
  cam.target = Vec3(0, 0, 0);
  c.scene.cameras.push_back(cam);
  c.cache = std::make_unique<SceneCache>(c.scene);
  c.style = make_volume_style(volume_scene(*c.cache), tf, 0.5f);
  c.style->background = Vec3(0.05f, 0.05f, 0.1f);
}

// A ball of value 200 in a 48 x 40 x 36 field of zeros (partial blocks on every axis, as
// tests/render/volume_raycaster_test.cpp), with a soft shell: values fall off linearly over
// two voxels so gradients and partial opacities occur; values below 50 are invisible.
inline std::unique_ptr<VolumeCase> ball_case() {
  auto owned = std::make_unique<VolumeCase>();
  VolumeCase& c = *owned;
  c.volume = std::make_shared<Volume>();
  Volume& v = *c.volume;
  v.name = "ball";
  v.nx = 48, v.ny = 40, v.nz = 36;
  v.values.resize(v.voxel_count());
  for (int z = 0; z < v.nz; ++z)
    for (int y = 0; y < v.ny; ++y)
      for (int x = 0; x < v.nx; ++x) {
        const float dx = float(x) - 30, dy = float(y) - 18, dz = float(z) - 17;
        const float r = std::sqrt(dx * dx + dy * dy + dz * dz);
        v.values[(size_t(z) * size_t(v.ny) + size_t(y)) * size_t(v.nx) + size_t(x)] =
            200.0f * std::clamp(11.0f - r, 0.0f, 2.0f) / 2.0f;
      }
  v.min_value = 0, v.max_value = 200;
  TransferFunction tf;
  tf.name = "ball";
  tf.points = {{0, Vec3(0.0f), 0}, {50, Vec3(0.0f), 0}, {200, Vec3(1, 0.8f, 0.6f), 0.3f}};
  finish_case(c, Vec3(20, 30, 80), tf);
  return owned;
}

// The path of ../shared/data/volumes/<file>.
inline std::string shared_volume_path(const std::string& file) {
  return std::string(MULTIRAY_SHARED_DATA_DIR) + "/volumes/" + file;
}

// shared_volume_path(file) with the "angio" preset, seen from `eye`; null when the file
// is missing (the caller skips).
inline std::unique_ptr<VolumeCase> shared_case(const std::string& file, Vec3 eye) {
  const std::string path = shared_volume_path(file);
  if (!std::filesystem::exists(path)) return nullptr;
  auto c = std::make_unique<VolumeCase>();
  c->volume = std::make_shared<Volume>(load_volume(path));
  finish_case(*c, eye, transfer_preset("angio", *c->volume));
  return c;
}

inline RenderSettings volume_settings(const VolumeCase& c, int spp = 1, uint64_t seed = 0) {
  RenderSettings s;
  s.kernel = "volume";
  s.spp = spp;
  s.seed = seed;
  s.volume_style = c.style;
  return s;
}

// Per-channel absolute differences of two images of one size.
struct ImageDiff {
  double max = 0, mean = 0;
  double within_1e2 = 0;  // fraction of pixels whose channels all differ by <= 1e-2
  size_t exact = 0;       // pixels equal in every channel
};

inline ImageDiff diff(const Framebuffer& a, const Framebuffer& b) {
  ImageDiff d;
  size_t within = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    float worst = 0;
    for (int c = 0; c < 3; ++c) {
      const float e = std::abs(a.pixels[i][c] - b.pixels[i][c]);
      worst = std::max(worst, e);
      d.mean += e;
    }
    d.max = std::max(d.max, double(worst));
    within += worst <= 1e-2f;
    d.exact += worst == 0;
  }
  const double n = double(std::max<size_t>(1, a.pixels.size()));
  d.mean /= 3 * n;
  d.within_1e2 = double(within) / n;
  return d;
}

inline void print_diff(const char* what, const ImageDiff& d, size_t pixels) {
  std::printf("%s: max %.3g, mean %.3g, %.3f%% of pixels within 1e-2, %.2f%% exact\n", what, d.max,
              d.mean, 100 * d.within_1e2, 100.0 * double(d.exact) / double(pixels));
}

}  // namespace multiray::testing
