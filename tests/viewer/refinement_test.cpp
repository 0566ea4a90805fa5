// Progressive refinement (engine/refinement.h): while the key stands, the shown image
// is the mean of the frames so far, up to the target's samples; a change starts again.
// And smaller frames while the camera moves (app/viewer/motion.h).
#include <gtest/gtest.h>

#include <chrono>
#include <memory>

#include "app/viewer/motion.h"
#include "engine/refinement.h"

namespace refinement_test {

using multiray::Camera;
using multiray::Framebuffer;
using multiray::RefineKey;
using multiray::Refinement;
using multiray::Vec3;

Framebuffer flat(float v) {
  Framebuffer fb(4, 2);
  for (Vec3& p : fb.pixels) p = Vec3(v, 2 * v, 0);
  return fb;
}

TEST(Refinement, AStillCameraShowsTheMeanOfItsFramesUpToTheTarget) {
  Refinement r(2, 6);  // three frames of 2 spp make the 6-spp image
  const RefineKey key{Camera{}, 0, 0};
  EXPECT_EQ(r.add(flat(3), key).pixels[0].x, 3.0f);
  EXPECT_EQ(r.samples(), 2);
  EXPECT_EQ(r.add(flat(5), key).pixels[5].y, 8.0f);  // mean of 6 and 10
  EXPECT_EQ(r.add(flat(7), key).pixels[0].x, 5.0f);
  EXPECT_EQ(r.samples(), 6);
  // Converged: further frames of the same view add nothing.
  EXPECT_EQ(r.add(flat(100), key).pixels[0].x, 5.0f);
  EXPECT_EQ(r.samples(), 6);
}

// An RGBA layer's coverage is averaged with its colour; a layer after a plain image starts
// again.
TEST(Refinement, AlphaIsAveragedWithTheColour) {
  Refinement r(1, 4);
  const RefineKey key{Camera{}, 0, 0};
  Framebuffer a = flat(1), b = flat(3);
  a.alpha.assign(a.pixels.size(), 0.0f);
  b.alpha.assign(b.pixels.size(), 1.0f);
  r.add(flat(9), key);
  EXPECT_EQ(r.add(a, key).alpha.size(), a.pixels.size());
  EXPECT_EQ(r.samples(), 1);  // the plain image before it does not count
  const Framebuffer& mean = r.add(b, key);
  EXPECT_EQ(mean.alpha[3], 0.5f);
  EXPECT_EQ(mean.pixels[3].x, 2.0f);
}

// Feature buffers: albedo averaged, and the variance pooled as all the samples' would be:
// frames of 2 samples with luminance {1, 3} and {5, 7} (means 2 and 6, each a variance of
// its mean of 1) are the samples {1, 3, 5, 7}: sum of squared deviations 20, variance of
// the mean 20 / (3 x 4).
TEST(Refinement, FeatureBuffersArePooled) {
  Refinement r(2, 4);
  const RefineKey key{Camera{}, 0, 0};
  const auto frame = [](float y, float albedo) {
    Framebuffer fb(4, 2);
    for (Vec3& p : fb.pixels) p = Vec3(y, y, y);
    fb.features.resize(4, 2);
    for (size_t i = 0; i < fb.pixels.size(); ++i) {
      const float v[multiray::FeatureBuffers::kFloats] = {albedo, albedo, albedo, 0,
                                                          0,      1,      2.0f,   1.0f};
      fb.features.set_packed(i, v);
    }
    return fb;
  };
  r.add(flat(9), key);  // a frame without them: the next one starts again
  EXPECT_FLOAT_EQ(r.add(frame(2, 0.25f), key).features.variance[0], 1.0f);
  const Framebuffer& mean = r.add(frame(6, 0.75f), key);
  EXPECT_EQ(r.samples(), 4);
  EXPECT_NEAR(mean.features.variance[7], 20.0f / 12.0f, 1e-5f);
  EXPECT_EQ(mean.features.albedo[3], 0.5f);
  EXPECT_EQ(mean.features.normal[5], 1.0f);
  EXPECT_EQ(mean.features.depth[0], 2.0f);
}

TEST(Refinement, AnyChangeStartsAgainFromOneFrame) {
  Refinement r(1, 16);
  RefineKey key{Camera{}, 0, 0};
  r.add(flat(1), key);
  r.add(flat(3), key);
  EXPECT_EQ(r.samples(), 2);
  key.camera.eye.x += 0.001f;  // the camera moved
  EXPECT_EQ(r.add(flat(9), key).pixels[0].x, 9.0f);
  EXPECT_EQ(r.samples(), 1);
  key.view = 1;  // another view of a light field
  EXPECT_EQ(r.add(flat(4), key).pixels[0].x, 4.0f);
  key.generation = 1;  // anything else that changes the image
  EXPECT_EQ(r.add(flat(2), key).pixels[0].x, 2.0f);
  Framebuffer larger(8, 2);  // the frame's size changed
  EXPECT_EQ(r.add(larger, key).width, 8);
  EXPECT_EQ(r.samples(), 1);
  // Frames rendered smaller and enlarged (while the camera moves) and full-size ones under
  // the same camera are never averaged: each change of scale starts again.
  key.image_scale = 0.5;
  r.add(larger, key);
  r.add(larger, key);
  EXPECT_EQ(r.samples(), 2);
  key.image_scale = 1.0;
  r.add(larger, key);
  EXPECT_EQ(r.samples(), 1);
}

}  // namespace refinement_test

namespace motion_test {

using multiray::app::viewer::kMotionHoldSeconds;
using multiray::app::viewer::MotionAdvisor;
using multiray::app::viewer::MotionClock;

// A move lasts kMotionHoldSeconds after the last camera message; meanwhile the advisor
// asks for the reduced scale, then for full size again.
TEST(Motion, FramesAreSmallerOnlyWhileTheCameraMoves) {
  auto clock = std::make_shared<MotionClock>();
  const auto t0 = MotionClock::Clock::now();
  EXPECT_FALSE(clock->moving(t0)) << "moving before any move";
  clock->moved(t0);
  EXPECT_TRUE(clock->moving(t0 + std::chrono::milliseconds(100)));
  EXPECT_FALSE(clock->moving(t0 + std::chrono::milliseconds(int(kMotionHoldSeconds * 1000) + 50)));
  MotionAdvisor advisor(clock, 0.5);
  clock->moved();
  EXPECT_EQ(advisor.advise(0, {}, {}).quality.image_scale, 0.5);
  clock->moved(MotionClock::Clock::now() - std::chrono::seconds(1));
  EXPECT_EQ(advisor.advise(1, {}, {}).quality.image_scale, 1.0);
}

}  // namespace motion_test
