// The denoiser's spatial filter (render/denoise.h, atrous) on synthetic frames whose clean
// image is known (denoise_frames.h): what it must leave alone, what it must smooth, and
// that its result depends on nothing but the frame.
#include <gtest/gtest.h>

#include <oneapi/tbb/task_arena.h>
#include <xmmintrin.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <thread>
#include <utility>

#include "render/denoise_frames.h"
#include "render/shared/denoise.h"

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

// Salt and pepper, as a dim room at a few samples per pixel: on a plane lit to 0.1, one
// pixel in 16 (every 4th of every 4th row) caught the light, at 1.6 with its variance,
// and the others are black with variance 0 (every sample returned nothing). The black
// pixels between them, whose 3x3 neighbourhood holds no lit pixel, must take some of the
// light (at least a third of the mean: measured 0.05-0.1); with a variance of 0 they
// used to shut out every neighbour and stay black. A region black throughout stays black (under 1%
// of the light seeps in: measured 6e-5 of it at its edge).
TEST(Denoise, BlackPixelsAmidSparseLightAreFilledAndBlackRegionsStayBlack) {
  DenoiseFrame f(48, 32);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      f.set(x, y, Vec3(x < 36 ? 0.1f : 0.0f), Vec3(0.5f), Vec3(0, 0, 1), 3.0f);
  f.beauty = f.clean;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const size_t i = size_t(f.index(x, y));
      const bool lit = x < 36 && x % 4 == 0 && y % 4 == 0;
      for (int c = 0; c < 3; ++c) f.beauty[3 * i + size_t(c)] = lit ? 1.6f : 0.0f;
      f.variance[i] = lit ? 0.1f : 0.0f;
    }
  f.with_variance = true;
  const std::vector<float> out = run(f);
  for (int y = 6; y < f.height - 6; y += 4)
    for (int x = 6; x < 30; x += 4)
      EXPECT_GT(out[3 * size_t(f.index(x, y))], 0.1f / 3) << "black pixel " << x << "," << y;
  for (int y = 0; y < f.height; ++y)
    for (int x = 40; x < f.width; ++x)
      ASSERT_LT(out[3 * size_t(f.index(x, y))], 0.001f) << "black region " << x << "," << y;
}

// A light in the dark (the emitter's own pixels all emission, everything else black, one
// surface throughout): with the emission buffer the filter works on the beauty minus it,
// all zeros, so the light's pixels keep their values exactly and the black pixels beside
// it stay black. Without it the light's radiance spreads into its neighbours (the check
// that the frame can tell), with or without the renderer's variance.
TEST(Denoise, ALightKeepsItsPixelsAndDoesNotSpread) {
  DenoiseFrame f(40, 30);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) f.set(x, y, Vec3(0.78f), Vec3(0.0f), Vec3(0, -1, 0), 2.0f);
  f.add_noise(0.0f, 1, false);
  f.add_light(16, 10, 24, 18, Vec3(17.0f, 12.0f, 4.0f));
  for (int y = 10; y < 18; ++y) f.variance[f.index(15, y)] = f.variance[f.index(24, y)] = 1.0f;
  for (const DenoiseMethod m : {DenoiseMethod::atrous, DenoiseMethod::svgf})
    for (const bool with_variance : {false, true}) {
      f.with_variance = with_variance;
      f.with_emission = true;
      DenoiseState state;
      std::vector<float> out(f.beauty.size());
      denoise(f.input(), m, &state, out.data());
      for (size_t k = 0; k < out.size(); ++k)
        ASSERT_EQ(out[k], f.beauty[k]) << "value " << k << ", variance " << with_variance;
      f.with_emission = false;
      state.reset();
      denoise(f.input(), m, &state, out.data());
      EXPECT_GT(out[3 * f.index(24, 14)], 0.1f) << "without emission, variance " << with_variance;
    }
}

// Noise around a light (its pixels emit 30 and reflect the light around them, 0.39, with
// the same noise): the light's pixels come out within 0.1 of their clean value (the light
// added back as it was, the reflection filtered), and its neighbours' error is no larger
// than where no light is (5% allowed): the light neither spreads into them nor shuts them
// out of each other's filtering. Without the emission buffer it is more than twice that.
TEST(Denoise, ALightLeavesItsNoisyNeighboursFiltered) {
  DenoiseFrame f(48, 36);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) f.set(x, y, Vec3(0.78f), Vec3(0.5f), Vec3(0, -1, 0), 2.0f);
  f.add_noise(0.3f, 9, false);
  DenoiseFrame plain = f;
  f.add_light(20, 14, 28, 22, Vec3(30.0f));
  const auto beside = [](int x, int y) {
    return x >= 16 && x < 32 && y >= 10 && y < 26 && !(x >= 20 && x < 28 && y >= 14 && y < 22);
  };
  const std::vector<float> out = run(f), reference = run(plain);
  for (int y = 14; y < 22; ++y)
    for (int x = 20; x < 28; ++x)
      EXPECT_NEAR(out[3 * f.index(x, y)], f.clean[3 * f.index(x, y)], 0.1f) << x << "," << y;
  EXPECT_LE(rmse(f, out, beside), 1.05 * rmse(plain, reference, beside));
  f.with_emission = false;
  EXPECT_GT(rmse(f, run(f), beside), 2.0 * rmse(plain, reference, beside));
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

// One sample a pixel: the renderer's variance is 0 throughout (render/shared/aov.h), which
// is no estimate. The filter takes such a frame as one without a variance, to the bit,
// atrous and svgf over a few frames alike, and smooths it: the error falls at least 8
// times (measured 13-16 times with atrous, up to 60 with svgf's fifth frame). Taken as a
// variance of 0 (the viewer's 1-spp frames until 2026-12-04) the luminance weight shut
// out every neighbour that differs: atrous cut the error by 1% or less, svgf's fifth frame
// by 2.2 times.
TEST(Denoise, AVarianceOfZeroThroughoutIsNoVariance) {
  DenoiseFrame f = edge_frame(EdgeKind::albedo);
  const auto all = [](int, int) { return true; };
  for (const DenoiseMethod m : {DenoiseMethod::atrous, DenoiseMethod::svgf}) {
    DenoiseState zero_state, none_state;
    for (unsigned seed = 1; seed <= 5; ++seed) {
      f.add_noise(0.3f, seed, true);
      std::fill(f.variance.begin(), f.variance.end(), 0.0f);
      std::vector<float> zero(f.beauty.size()), none(f.beauty.size());
      denoise(f.input(), m, &zero_state, zero.data());
      f.with_variance = false;
      denoise(f.input(), m, &none_state, none.data());
      ASSERT_EQ(std::memcmp(zero.data(), none.data(), zero.size() * sizeof(float)), 0)
          << "method " << int(m) << ", frame " << seed;
      EXPECT_LT(rmse(f, zero, all) * 8.0, rmse(f, f.beauty, all))
          << "method " << int(m) << ", frame " << seed;
    }
  }
}

// An adaptive frame (`--sampling adaptive`): the renderer's variance on the pixels of
// several samples, 0 on the others, which had one sample each (render/shared/aov.h). Those
// are smoothed too: their error falls at least 8 times (measured 17). Taken at their 0,
// they kept most of their noise (measured: 2.4 times, from the given pixels mixing in).
TEST(Denoise, PixelsOfOneSampleAmidSeveralAreFiltered) {
  DenoiseFrame f = edge_frame(EdgeKind::albedo);
  f.add_noise(0.3f, 31, true);
  const auto one_sample = [](int x, int y) { return (x + y) % 5 != 0; };
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      if (one_sample(x, y)) f.variance[f.index(x, y)] = 0.0f;
  const std::vector<float> out = run(f);
  EXPECT_LT(rmse(f, out, one_sample) * 8.0, rmse(f, f.beauty, one_sample));
}

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

// The filter's result does not depend on the float mode of the thread that calls it (nor
// of the TBB workers that help it): it flushes denormals to zero itself and gives the
// caller's mode back. A frame whose beauty is all denormals shows the difference: flushed,
// it is black; kept, it is not.
TEST(Denoise, SameBitsWhateverTheCallersFloatMode) {
  DenoiseFrame f = edge_frame(EdgeKind::depth, 40, 30);
  f.add_noise(0.3f, 9, true);
  for (float& v : f.beauty) v *= 1e-39f;
  const unsigned flush = 0x8040;  // MXCSR's flush-to-zero and denormals-are-zero bits
  const auto run_with = [&](bool flushing, std::vector<float>& out) {
    std::thread([&] {
      const unsigned mode = flushing ? _mm_getcsr() | flush : _mm_getcsr() & ~flush;
      _mm_setcsr(mode);
      oneapi::tbb::task_arena(1).execute([&] { out = run(f); });
      EXPECT_EQ(_mm_getcsr(), mode) << "the caller's float mode was not given back";
    }).join();
  };
  std::vector<float> kept, flushed;
  run_with(false, kept);
  run_with(true, flushed);
  ASSERT_EQ(kept.size(), flushed.size());
  EXPECT_EQ(std::memcmp(kept.data(), flushed.data(), kept.size() * sizeof(float)), 0);
}

// The normals' weight is the cosine to the power sigma_normal: by squarings for a power
// of two up to 2^10 (128, the default, among them), by pow otherwise, the same value up
// to float rounding (7 squarings: a few ulp).
TEST(Denoise, NormalWeightIsTheCosineToTheSigma) {
  for (float sigma : {1.0f, 2.0f, 8.0f, 128.0f, 1024.0f, 0.5f, 100.0f, 2048.0f}) {
    const DenoiseWeights w = denoise_weights(4.0f, sigma, 0.02f, 0.2f, 1);
    const int k = int(std::round(std::log2(sigma)));
    const bool squared = sigma >= 1.0f && sigma <= 1024.0f && std::exp2(float(k)) == sigma;
    EXPECT_EQ(w.normal_squarings, squared ? k : -1) << "sigma " << sigma;
    for (float c : {1.0f, 0.9999f, 0.999f, 0.99f, 0.9f, 0.5f}) {
      const double want = std::pow(double(c), double(sigma));
      EXPECT_NEAR(denoise_normal_weight(c, &w), want, 1e-5 * want + 1e-30)
          << "sigma " << sigma << ", cosine " << c;
    }
  }
}

// A caller's DenoiseBuffers, kept over frames of different sizes and methods, give the
// same images (and svgf the same history) as fresh buffers for every call.
TEST(Denoise, KeptBuffersGiveTheSameImages) {
  DenoiseBuffers kept;
  DenoiseState with_kept, with_fresh;
  const std::pair<int, DenoiseMethod> frames[] = {
      {40, DenoiseMethod::atrous}, {24, DenoiseMethod::atrous}, {0, DenoiseMethod::svgf},
      {0, DenoiseMethod::svgf},    {40, DenoiseMethod::atrous}, {0, DenoiseMethod::svgf}};
  for (unsigned k = 0; k < std::size(frames); ++k) {
    const auto [width, method] = frames[k];
    const bool svgf = method == DenoiseMethod::svgf;
    DenoiseFrame f = svgf ? testing::walls(testing::camera_at(0.03f * float(k)), 50 + k)
                          : edge_frame(EdgeKind::normal, width, width * 3 / 4);
    if (!svgf) f.add_noise(0.3f, k, false);
    std::vector<float> a(f.beauty.size()), b(f.beauty.size());
    denoise(f.input(), method, svgf ? &with_kept : nullptr, a.data(), {}, &kept);
    denoise(f.input(), method, svgf ? &with_fresh : nullptr, b.data());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0) << "frame " << k;
    EXPECT_EQ(with_kept.history, with_fresh.history) << "frame " << k;
    EXPECT_EQ(with_kept.moments, with_fresh.moments) << "frame " << k;
    EXPECT_EQ(with_kept.color, with_fresh.color) << "frame " << k;
  }
  EXPECT_FALSE(with_kept.empty());
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
