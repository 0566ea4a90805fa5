// The denoiser's spatial filter (render/denoise.h, atrous) on synthetic frames whose clean
// image is known (denoise_frames.h): what it must leave alone, what it must smooth, and
// that its result depends on nothing but the frame.
#include <gtest/gtest.h>

#include <oneapi/tbb/task_arena.h>

#include <cstring>

#include "render/denoise_frames.h"

namespace multiray {
namespace denoise_test {

using testing::DenoiseFrame;
using testing::edge_frame;
using testing::EdgeKind;
using testing::rmse;

std::vector<float> run(const DenoiseFrame& f, DenoiseMethod m = DenoiseMethod::atrous) {
  std::vector<float> out(f.beauty.size());
  denoise(f.input(), m, nullptr, out.data());
  return out;
}

TEST(Denoise, ConstantImageIsUnchanged) {
  DenoiseFrame f(40, 30);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      f.set(x, y, Vec3(0.5f, 0.6f, 0.7f), Vec3(0.6f, 0.8f, 1.0f), Vec3(0, 0, 1), 3.0f);
  f.beauty = f.clean;
  for (bool with_variance : {false, true}) {
    f.with_variance = with_variance;
    const std::vector<float> out = run(f);
    for (size_t k = 0; k < out.size(); ++k)
      ASSERT_NEAR(out[k], f.clean[k], 1e-6f) << "value " << k << ", variance " << with_variance;
  }
}

// A miss (the environment: depth +inf, normal 0) filters among misses only, and an image
// of misses alone passes unchanged where it is constant.
TEST(Denoise, MissesMixOnlyWithMisses) {
  DenoiseFrame f(32, 24);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      if (x >= 16) f.set(x, y, Vec3(0.5f), Vec3(0.2f), Vec3(0, 0, 1), 2.0f);
  for (size_t i = 0; i < f.depth.size(); ++i)
    if (!std::isfinite(f.depth[i]))
      for (int c = 0; c < 3; ++c) f.clean[3 * i + size_t(c)] = 2.0f;  // a bright sky
  f.add_noise(0.0f, 1, false);
  const std::vector<float> out = run(f);
  for (int y = 0; y < f.height; ++y) {
    EXPECT_NEAR(out[3 * f.index(15, y)], 2.0f, 1e-5f) << "sky beside the surface, row " << y;
    EXPECT_NEAR(out[3 * f.index(16, y)], 0.1f, 1e-6f) << "surface beside the sky, row " << y;
  }
}

class DenoiseEdge : public ::testing::TestWithParam<std::tuple<EdgeKind, bool>> {};

// Noise of 30% on two flat regions: the filter cuts the error against the clean image by
// a factor of at least 8 on each side (measured 15-20), while the columns on either
// side of the edge keep their own side's value: their mean within 5% of the contrast
// across the edge, no pixel off by more than a third of it.
TEST_P(DenoiseEdge, KeepsTheEdgeAndSmoothsTheNoise) {
  const auto [kind, with_variance] = GetParam();
  DenoiseFrame f = edge_frame(kind);
  f.add_noise(0.3f, 7, with_variance);
  const std::vector<float> out = run(f);
  const int mid = f.width / 2;
  for (bool left : {true, false}) {
    const auto side = [&](int x, int) { return (x < mid) == left; };
    const double before = rmse(f, f.beauty, side), after = rmse(f, out, side);
    EXPECT_LT(after * 8.0, before)
        << (left ? "left" : "right") << ": " << before << " -> " << after;
  }
  const float contrast = std::abs(f.clean_at(0, 0).y - f.clean_at(f.width - 1, 0).y);
  for (int x : {mid - 2, mid - 1, mid, mid + 1}) {
    const float want = f.clean_at(x, 0).y;
    double mean = 0;
    for (int y = 0; y < f.height; ++y) {
      const float v = out[3 * f.index(x, y) + 1];
      EXPECT_LT(std::abs(v - want), contrast / 3) << "pixel " << x << "," << y;
      mean += v / f.height;
    }
    EXPECT_LT(std::abs(mean - want), 0.05 * contrast) << "column " << x << ": " << mean;
  }
}

std::string edge_case_name(const ::testing::TestParamInfo<std::tuple<EdgeKind, bool>>& info) {
  const char* names[] = {"Normal", "Depth", "Albedo"};
  return std::string(names[int(std::get<0>(info.param))]) +
         (std::get<1>(info.param) ? "GivenVariance" : "EstimatedVariance");
}

INSTANTIATE_TEST_SUITE_P(Guides, DenoiseEdge,
                         ::testing::Combine(::testing::Values(EdgeKind::normal, EdgeKind::depth,
                                                              EdgeKind::albedo),
                                            ::testing::Bool()),
                         edge_case_name);

// A fine texture (every pixel its own albedo in 0.2..0.8) under even light: the filter
// works on the light alone (the beauty divided by albedo) and multiplies the texture back,
// so the texture is kept while the noise goes: the error falls by a factor of at least 3
// (measured 3.7; 1.6 without demodulation; the albedo weight, which keeps materials
// apart, also keeps a texture this fine from being filtered much).
TEST(Denoise, TextureSurvivesDemodulation) {
  DenoiseFrame f(64, 48);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> albedo(0.2f, 0.8f);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      f.set(x, y, Vec3(albedo(rng), albedo(rng), albedo(rng)), Vec3(1.0f), Vec3(0, 0, 1), 2.0f);
  f.add_noise(0.3f, 11, true);
  const std::vector<float> out = run(f);
  const auto all = [](int, int) { return true; };
  EXPECT_LT(rmse(f, out, all) * 3.0, rmse(f, f.beauty, all));
}

// The result is a function of the frame alone: the same bits on one thread as on all.
TEST(Denoise, SameBitsOnAnyNumberOfThreads) {
  DenoiseFrame f = edge_frame(EdgeKind::depth, 80, 60);
  f.add_noise(0.3f, 3, false);
  std::vector<float> one, all = run(f);
  oneapi::tbb::task_arena(1).execute([&] { one = run(f); });
  ASSERT_EQ(one.size(), all.size());
  EXPECT_EQ(std::memcmp(one.data(), all.data(), one.size() * sizeof(float)), 0);
}

TEST(Denoise, NoneCopiesAndBadInputIsRefused) {
  DenoiseFrame f = edge_frame(EdgeKind::albedo, 8, 8);
  f.add_noise(0.3f, 1, false);
  EXPECT_EQ(run(f, DenoiseMethod::none), f.beauty);
  DenoiseInput in = f.input();
  in.normal = nullptr;
  std::vector<float> out(f.beauty.size());
  EXPECT_THROW(denoise(in, DenoiseMethod::atrous, nullptr, out.data()), std::invalid_argument);
  EXPECT_THROW(denoise(f.input(), DenoiseMethod::svgf, nullptr, out.data()),
               std::invalid_argument);
}

TEST(Denoise, RegistryNamesEveryChoiceAndAutoFollowsTheIssue) {
  std::vector<std::string> names;
  for (const DenoiseMethodInfo& m : denoise_methods()) {
    names.push_back(m.name);
    EXPECT_GT(std::strlen(m.help), 20u) << m.name;
    DenoiseChoice c{};
    ASSERT_TRUE(parse_denoise(m.name, c));
    EXPECT_EQ(c, m.choice);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"none", "atrous", "svgf", "auto"}));
  DenoiseChoice c{};
  EXPECT_FALSE(parse_denoise("oidn", c));
  const DenoiseChoice a = DenoiseChoice::automatic;
  EXPECT_EQ(resolve_denoise(a, {.png_output = true, .spp = 16}), DenoiseMethod::atrous);
  EXPECT_EQ(resolve_denoise(a, {.png_output = true, .spp = 256}), DenoiseMethod::none);
  EXPECT_EQ(resolve_denoise(a, {.png_output = false, .spp = 16}), DenoiseMethod::none);
  EXPECT_EQ(resolve_denoise(a, {.viewer = true, .camera_moving = true}), DenoiseMethod::svgf);
  EXPECT_EQ(resolve_denoise(a, {.viewer = true, .spp = 16}), DenoiseMethod::svgf);
  EXPECT_EQ(resolve_denoise(a, {.viewer = true, .spp = 256}), DenoiseMethod::none);
  EXPECT_EQ(resolve_denoise(DenoiseChoice::svgf, {}), DenoiseMethod::svgf);
}

}  // namespace denoise_test
}  // namespace multiray
