// The viewer's denoiser (app/viewer/view_denoise.h), without a server: a frame shown alone
// is the session's denoised one; a still camera's refined image is filtered here, once
// when it has converged, and auto leaves it as it is from 256 samples per pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "app/viewer/view_denoise.h"

namespace multiray::app::viewer {
namespace view_denoise_test {

// A noisy grey image of a plane (albedo 0.5, normal +y, depth 1) with its features.
Framebuffer noisy(unsigned seed) {
  Framebuffer fb(32, 24);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (Vec3& p : fb.pixels) p = Vec3(u(rng));
  fb.features.resize(fb.width, fb.height);
  for (size_t i = 0; i < fb.pixels.size(); ++i) {
    const float v[FeatureBuffers::kFloats] = {0.5f, 0.5f, 0.5f, 0, 1, 0, 1.0f, 1.0f / 12};
    fb.features.set_packed(i, v);
  }
  return fb;
}

double spread(const Framebuffer& fb) {  // mean squared difference of neighbours in x
  double sum = 0;
  for (int y = 0; y < fb.height; ++y)
    for (int x = 1; x < fb.width; ++x) sum += std::pow(fb.at(x, y).x - fb.at(x - 1, y).x, 2);
  return sum / double(fb.height * (fb.width - 1));
}

TEST(ViewDenoise, AFrameShownAloneIsTheSessionsDenoisedOne) {
  FrameResult r;
  r.images = {noisy(1)};
  r.denoised = {noisy(2)};
  r.denoised_with = DenoiseMethod::svgf;
  ViewDenoise d(DenoiseChoice::automatic);
  EXPECT_EQ(d.session_method(true), DenoiseMethod::svgf);
  EXPECT_EQ(d.session_method(false), DenoiseMethod::none) << "a still image is filtered here";
  DenoiseMethod used = DenoiseMethod::none;
  const auto shown = d.shown(r, 0, r.images[0], 1, true, &used);
  EXPECT_EQ(used, DenoiseMethod::svgf);
  EXPECT_EQ(image_hash(*shown), image_hash(r.denoised[0]));
  d.choose(DenoiseChoice::atrous);
  EXPECT_EQ(d.session_method(true), DenoiseMethod::atrous);
  d.choose(DenoiseChoice::none);
  EXPECT_EQ(d.session_method(true), DenoiseMethod::none);
  FrameResult raw;
  raw.images = {noisy(3)};
  EXPECT_EQ(image_hash(*d.shown(raw, 0, raw.images[0], 1, true, &used)),
            image_hash(raw.images[0]));
  EXPECT_EQ(used, DenoiseMethod::none);
}

TEST(ViewDenoise, AStillImageIsFilteredOnceConvergedAndAutoStopsAt256Samples) {
  FrameResult r;  // a still frame: the session filtered nothing
  r.images = {noisy(4)};
  const Framebuffer refined = noisy(5);
  ViewDenoise d(DenoiseChoice::automatic);
  DenoiseMethod used = DenoiseMethod::none;
  const auto first = d.shown(r, 0, refined, 16, false, &used);
  EXPECT_EQ(used, DenoiseMethod::atrous);
  EXPECT_LT(spread(*first), 0.2 * spread(refined)) << "not filtered";
  EXPECT_EQ(d.shown(r, 0, refined, 16, false, &used), first) << "converged: filtered once";
  EXPECT_NE(d.shown(r, 0, refined, 16, true, &used), first) << "a new image: filtered again";
  EXPECT_EQ(image_hash(*d.shown(r, 0, refined, 256, false, &used)), image_hash(refined));
  EXPECT_EQ(used, DenoiseMethod::none);
  d.choose(DenoiseChoice::svgf);  // named: at any count, and spatially (the refinement is
  d.shown(r, 0, refined, 1024, false, &used);  // the history)
  EXPECT_EQ(used, DenoiseMethod::atrous);
}

// auto filters a moving frame only while the filter costs at most 15% of a moving frame's
// time (issue 52: the frame rate with svgf within 15% of the raw one): learnt from a
// frame the session filtered, it then shows moving frames raw; a method named is followed.
TEST(ViewDenoise, AutoShowsMovingFramesRawWhereTheFilterIsTooDear) {
  for (const double denoise_ms : {1.0, 5.0}) {  // 10% and 50% of a 10 ms frame
    FrameResult r;
    r.images = {noisy(1)};
    r.denoised = {noisy(2)};
    r.denoised_with = DenoiseMethod::svgf;
    r.record.frame_ms = 10, r.record.denoise_ms = denoise_ms;
    ViewDenoise d(DenoiseChoice::automatic);
    ASSERT_EQ(d.session_method(true), DenoiseMethod::svgf) << "the first is filtered, to learn";
    DenoiseMethod used = DenoiseMethod::none;
    d.shown(r, 0, r.images[0], 1, true, &used);
    const bool dear = denoise_ms > 1.5;
    EXPECT_EQ(d.session_method(true), dear ? DenoiseMethod::none : DenoiseMethod::svgf)
        << denoise_ms << " ms";
    FrameResult next;  // the next moving frame, as the session then renders it
    next.images = {noisy(3)};
    next.record.frame_ms = 10;
    const auto shown = d.shown(next, 0, next.images[0], 1, true, &used);
    if (dear) {
      EXPECT_EQ(image_hash(*shown), image_hash(next.images[0])) << "shown raw";
      EXPECT_EQ(used, DenoiseMethod::none);
    }
    d.choose(DenoiseChoice::svgf);
    EXPECT_EQ(d.session_method(true), DenoiseMethod::svgf) << "named: always followed";
  }
}

}  // namespace view_denoise_test
}  // namespace multiray::app::viewer
