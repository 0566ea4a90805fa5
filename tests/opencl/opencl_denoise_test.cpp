// The denoiser's à-trous filter on an OpenCL device (device/opencl/opencl_denoise.h)
// against the CPU's (render/denoise.h): the same shared per-pixel steps, so the same
// image within float tolerance (the libraries' exp and pow may differ in the last ulp),
// and the same bits whatever the work-group size and launch size.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "device/opencl/opencl_denoise.h"
#include "opencl_helpers.h"
#include "render/denoise_frames.h"

namespace multiray {
namespace opencl_denoise_test {

using testing::DenoiseFrame;
using testing::EdgeKind;

// The largest difference between the images, relative to the brightest value of `a`.
float max_relative_difference(const std::vector<float>& a, const std::vector<float>& b) {
  float diff = 0, peak = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    diff = std::max(diff, std::abs(a[k] - b[k]));
    peak = std::max(peak, std::abs(a[k]));
  }
  return diff / peak;
}

TEST(OpenClDenoise, MatchesTheCpu) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  // Launches of 32 x 32 work-items: the frame takes three, the last one partly outside
  // it, and rows do not divide them.
  OpenClDenoiser gpu(0, 64, 32);
  for (EdgeKind kind : {EdgeKind::normal, EdgeKind::depth, EdgeKind::albedo})
    for (bool with_variance : {false, true})
      for (bool with_light : {false, true}) {
        DenoiseFrame f = testing::edge_frame(kind, 60, 45);
        for (int x = 0; x < 12; ++x)  // some sky: misses
          for (int y = 0; y < 9; ++y) f.depth[f.index(x, y)] = INFINITY;
        f.add_noise(0.3f, 17, with_variance);
        // A light across the edge, in the emission buffer (filtered out, added back).
        if (with_light) f.add_light(25, 20, 36, 26, Vec3(6.0f, 4.0f, 2.0f));
        std::vector<float> cpu(f.beauty.size()), cl(f.beauty.size(), -1.0f);
        denoise(f.input(), DenoiseMethod::atrous, nullptr, cpu.data());
        gpu.atrous(f.input(), cl.data());
        EXPECT_LT(max_relative_difference(cpu, cl), 1e-4f)
            << "kind " << int(kind) << ", variance " << with_variance << ", light " << with_light;
      }
}

// A variance of 0 throughout (one sample a pixel, render/shared/aov.h) is no variance on
// the device too: the same bits as without one, and the CPU's image within tolerance.
TEST(OpenClDenoise, AVarianceOfZeroThroughoutIsNoVariance) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  OpenClDenoiser gpu(0, 64, 32);
  DenoiseFrame f = testing::edge_frame(EdgeKind::albedo, 60, 45);
  f.add_noise(0.3f, 23, true);
  std::fill(f.variance.begin(), f.variance.end(), 0.0f);
  std::vector<float> zero(f.beauty.size()), none(f.beauty.size()), cpu(f.beauty.size());
  gpu.atrous(f.input(), zero.data());
  f.with_variance = false;
  gpu.atrous(f.input(), none.data());
  denoise(f.input(), DenoiseMethod::atrous, nullptr, cpu.data());
  EXPECT_EQ(std::memcmp(zero.data(), none.data(), zero.size() * sizeof(float)), 0);
  EXPECT_LT(max_relative_difference(cpu, zero), 1e-4f);
}

// Both forms of the normal term (--denoise-normal) on domes whose normal turns 15 degrees
// a pixel, half of whose pixels caught no light: the device's image is the CPU's within
// float tolerance for each, and the two forms differ (the form reaches the kernel).
TEST(OpenClDenoise, BothNormalTermsMatchTheCpu) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  OpenClDenoiser gpu(0, 64, 32);
  DenoiseFrame f(48, 36);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const float ax = float(x % 11 - 5) * 0.26f, ay = float(y % 11 - 5) * 0.26f;
      const Vec3 n(std::sin(ax) * std::cos(ay), std::sin(ay), std::cos(ax) * std::cos(ay));
      f.set(x, y, Vec3(0.5f), Vec3(((x * 7 + y * 3) % 2) ? 1.0f : 0.0f), n, 2.0f);
    }
  f.add_noise(0.2f, 4, true);
  std::vector<std::vector<float>> images;
  for (const char* form : {"turn", "svgf"}) {
    DenoiseParams p;
    ASSERT_TRUE(parse_denoise_normal(form, p));
    std::vector<float> cpu(f.beauty.size()), cl(f.beauty.size(), -1.0f);
    denoise(f.input(), DenoiseMethod::atrous, nullptr, cpu.data(), p);
    gpu.atrous(f.input(), cl.data(), p);
    EXPECT_LT(max_relative_difference(cpu, cl), 1e-4f) << form;
    images.push_back(cl);
  }
  EXPECT_GT(max_relative_difference(images[0], images[1]), 0.05f);
}

// svgf over six frames of a moving camera, with and without the renderer's variance:
// the same images as the CPU's within float tolerance and the same history lengths, and
// a history either driver continues.
TEST(OpenClDenoise, SvgfMatchesTheCpu) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  OpenClDenoiser gpu(0, 64, 32);
  for (bool with_variance : {false, true}) {
    DenoiseState on_cpu, on_cl;
    for (unsigned k = 0; k < 6; ++k) {
      DenoiseFrame f = testing::walls(testing::camera_at(0.03f * float(k)), 40 + k);
      f.with_variance = with_variance;
      f.add_light(30, 20, 38 + int(k), 26, Vec3(8.0f));  // emission: kept out of the history
      std::vector<float> cpu(f.beauty.size()), cl(f.beauty.size(), -1.0f);
      denoise(f.input(), DenoiseMethod::svgf, &on_cpu, cpu.data());
      gpu.svgf(f.input(), on_cl, cl.data());
      EXPECT_LT(max_relative_difference(cpu, cl), 1e-4f)
          << "frame " << k << ", variance " << with_variance;
      ASSERT_EQ(on_cl.history.size(), on_cpu.history.size());
      for (size_t i = 0; i < on_cpu.history.size(); i += 2)
        ASSERT_EQ(on_cl.history[i], on_cpu.history[i]) << "frame " << k << ", pixel " << i / 2;
    }
  }
}

TEST(OpenClDenoise, SameBitsForAnyLaunchShape) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  DenoiseFrame f = testing::edge_frame(EdgeKind::depth, 70, 50);
  f.add_noise(0.3f, 5, false);
  std::vector<float> a(f.beauty.size()), b(f.beauty.size());
  OpenClDenoiser(0, 1, 16).atrous(f.input(), a.data());
  OpenClDenoiser(0, 64, 256).atrous(f.input(), b.data());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
}

TEST(OpenClDenoise, BadInputIsRefused) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  DenoiseFrame f = testing::edge_frame(EdgeKind::depth, 8, 8);
  f.add_noise(0.3f, 5, false);
  DenoiseInput in = f.input();
  in.depth = nullptr;
  std::vector<float> out(f.beauty.size());
  EXPECT_THROW(OpenClDenoiser(0).atrous(in, out.data()), std::invalid_argument);
  DenoiseState state;
  EXPECT_THROW(OpenClDenoiser(0).svgf(in, state, out.data()), std::invalid_argument);
  EXPECT_THROW(OpenClDenoiser(1 << 20), InputError);
  EXPECT_THROW(OpenClDenoiser(0, 64, 0), InputError);
}

}  // namespace opencl_denoise_test
}  // namespace multiray
