// SVGF's temporal accumulation (render/denoise.h, svgf) over frames of an analytic scene
// seen through a real camera (denoise_frames.h's walls), each frame with fresh noise from
// its own seed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "render/denoise_frames.h"
#include "render/path_tracer.h"
#include "render/shared/denoise.h"
#include "render/shared/denoise_atrous.h"
#include "render/shared/denoise_temporal.h"

namespace multiray {
namespace denoise_temporal_test {

using testing::DenoiseFrame;

using testing::camera_at;
using testing::walls;
constexpr int kW = testing::kWallsWidth, kH = testing::kWallsHeight;

double mean_of(const std::vector<float>& v, size_t stride, size_t k) {
  double s = 0;
  for (size_t i = k; i < v.size(); i += stride) s += v[i];
  return s / double(v.size() / stride);
}

// A still camera: the accumulated colour's variance falls frame after frame (as 1 / n,
// then towards alpha / (2 - alpha) of a frame's), and after 8 frames the image is closer
// to the clean one than the spatial filter alone makes that frame.
TEST(DenoiseTemporal, StillCameraAccumulates) {
  DenoiseState state;
  std::vector<float> out(3 * kW * kH), alone(out.size());
  double last = INFINITY;
  DenoiseFrame f = walls(camera_at(0), 0);
  for (unsigned k = 0; k < 8; ++k) {
    f = walls(camera_at(0), 100 + k);
    denoise(f.input(), DenoiseMethod::svgf, &state, out.data());
    const double v = mean_of(state.history, 2, 1);
    EXPECT_LT(v, last) << "frame " << k;
    last = v;
    EXPECT_EQ(mean_of(state.history, 2, 0), std::min(k + 1.0, 1024.0)) << "frame " << k;
  }
  denoise(f.input(), DenoiseMethod::atrous, nullptr, alone.data());
  const auto all = [](int, int) { return true; };
  EXPECT_LT(testing::rmse(f, out, all), 0.7 * testing::rmse(f, alone, all));
}

// The history the next frame accumulates onto (Schied et al. 2017: the first à-trous
// iteration's output): with one iteration, the filtered frame is that history multiplied
// back by albedo, to the bit, on the second frame too; without the feedback (ours until
// 2026-12-04) the history is the unfiltered accumulation, noisier than the filtered one.
TEST(DenoiseTemporal, TheHistoryIsTheFirstIterationsOutput) {
  DenoiseParams one;
  one.iterations = 1;
  DenoiseState state;
  std::vector<float> out(3 * kW * kH), back(out.size());
  for (unsigned k = 0; k < 2; ++k) {
    const DenoiseFrame f = walls(camera_at(0.01f * float(k)), 300 + k);
    denoise(f.input(), DenoiseMethod::svgf, &state, out.data(), one);
    const DenoiseInput in = f.input();
    for (int i = 0; i < kW * kH; ++i)
      denoise_remodulate(state.color.data(), in.emission, in.emission != nullptr, in.albedo,
                         in.depth, back.data(), i);
    EXPECT_EQ(0, std::memcmp(out.data(), back.data(), out.size() * sizeof(float))) << k;
  }
  DenoiseParams ours;
  ours.history_filtered = false;
  DenoiseState filtered, unfiltered;
  const DenoiseFrame f = walls(camera_at(0), 400);
  denoise(f.input(), DenoiseMethod::svgf, &filtered, out.data());
  denoise(f.input(), DenoiseMethod::svgf, &unfiltered, out.data(), ours);
  const auto roughness = [](const std::vector<float>& c) {  // mean step between neighbours
    double sum = 0;
    for (size_t i = 3; i < c.size(); ++i) sum += std::abs(c[i] - c[i - 3]);
    return sum / double(c.size());
  };
  EXPECT_LT(roughness(filtered.color), 0.8 * roughness(unfiltered.color));
}

// Without the renderer's variance the first three frames use the spatial estimate, then
// the moments: the variance still ends well below the first frame's.
TEST(DenoiseTemporal, StillCameraAccumulatesWithEstimatedVariance) {
  DenoiseState state;
  std::vector<float> out(3 * kW * kH);
  double first = 0, v = 0;
  for (unsigned k = 0; k < 8; ++k) {
    DenoiseFrame f = walls(camera_at(0), 200 + k);
    f.with_variance = false;
    denoise(f.input(), DenoiseMethod::svgf, &state, out.data());
    v = mean_of(state.history, 2, 1);
    if (k == 0) first = v;
  }
  EXPECT_LT(v, first / 3);
}

// Something appears in front of the near wall (depth 1 where it was 2 or 4): those pixels
// start a new history; the others keep theirs.
TEST(DenoiseTemporal, DisocclusionResetsTheHistory) {
  DenoiseState state;
  std::vector<float> out(3 * kW * kH);
  for (unsigned k = 0; k < 3; ++k)
    denoise(walls(camera_at(0), k).input(), DenoiseMethod::svgf, &state, out.data());
  DenoiseFrame f = walls(camera_at(0), 9);
  const auto inside = [](int x, int y) { return x >= 20 && x < 40 && y >= 10 && y < 30; };
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      if (inside(x, y)) f.depth[f.index(x, y)] = 1.0f;
  denoise(f.input(), DenoiseMethod::svgf, &state, out.data());
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      ASSERT_EQ(state.history[2 * f.index(x, y)], inside(x, y) ? 1.0f : 4.0f) << x << "," << y;
}

// The camera moves right by 0.04 a frame: the near wall's edge moves across the image and
// uncovers the far wall. Pixels within two of the edge keep their own wall's value (no
// bright history smeared onto the dark wall): mean error under 5% of the contrast, none
// over 20%.
TEST(DenoiseTemporal, MovingCameraDoesNotSmearAnEdge) {
  DenoiseState state;
  std::vector<float> out(3 * kW * kH);
  DenoiseFrame f = walls(camera_at(0), 0);
  for (unsigned k = 0; k < 10; ++k) {
    f = walls(camera_at(0.04f * float(k)), 300 + k, 0.2f);
    denoise(f.input(), DenoiseMethod::svgf, &state, out.data());
  }
  const float contrast = 0.8f - 0.08f;
  double sum = 0;
  int count = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 1; x < kW; ++x) {
      const bool edge_here = (f.depth[f.index(x - 1, y)] < 3) != (f.depth[f.index(x, y)] < 3);
      if (!edge_here) continue;
      for (int dx = -2; dx < 2; ++dx) {
        const int px = x + dx;
        const float err = std::abs(out[3 * f.index(px, y) + 1] - f.clean_at(px, y).y);
        EXPECT_LT(err, 0.2f * contrast) << "pixel " << px << "," << y;
        sum += err;
        ++count;
      }
    }
  ASSERT_GT(count, 0);
  EXPECT_LT(sum / count, 0.05 * contrast);
}

// Without a given variance the spatial estimate is made only for the pixels whose history
// is young (under four frames: SVGF, section 4.2), after the temporal step. The history it
// leaves is, to the bit, that of the temporal step given every pixel's estimate first
// (computed here pixel by pixel with the shared functions), over frames of a moving camera
// with something appearing in the fifth, so that young and old pixels meet.
TEST(DenoiseTemporal, AYoungHistorysVarianceIsTheSpatialEstimates) {
  const DenoiseParams p;
  const DenoiseWeights w = denoise_weights(p.sigma_luminance, p.sigma_normal, p.sigma_depth,
                                           p.sigma_albedo, p.normal_turn ? 1 : 0);
  const TemporalParams t{p.alpha, p.moments_alpha, p.depth_tolerance, p.normal_tolerance, 0};
  const int n = kW * kH;
  DenoiseState state;
  std::vector<float> out(3 * size_t(n));
  int young_beside_old = 0;
  for (unsigned k = 0; k < 6; ++k) {
    DenoiseFrame f = walls(camera_at(0.04f * float(k)), 500 + k);
    f.with_variance = false;
    if (k == 4)
      for (int y = 10; y < 30; ++y)
        for (int x = 20; x < 40; ++x) f.depth[f.index(x, y)] = 1.0f;
    const DenoiseInput in = f.input();
    const size_t np = size_t(n);
    std::vector<float> color(3 * np), lum(np), var(np), spatial(np);
    std::vector<float> guides(MR_DENOISE_GUIDE_FLOATS * size_t(n));
    std::vector<float> slopes(MR_DENOISE_SLOPE_FLOATS * size_t(n));
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        denoise_pack_guides(in.albedo, in.normal, in.depth, kW, kH, x, y, guides.data(),
                            slopes.data());
        denoise_demodulate(in.beauty, nullptr, 0, in.albedo, in.depth, nullptr, 0, color.data(),
                           lum.data(), var.data(), y * kW + x);
      }
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x)
        spatial[size_t(y * kW + x)] = denoise_start_variance(
            0, var.data(), lum.data(), guides.data(), slopes.data(), kW, kH, x, y, &w);
    const CameraBlock cur = PinholeCamera(*in.camera, kW, kH).block();
    const bool has_prev = !state.empty();
    const float* none = color.data();  // not read without a previous frame
    std::vector<float> acc(3 * size_t(n)), moments(2 * size_t(n)), history(2 * size_t(n));
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x)
        denoise_temporal_pixel(
            &cur, &state.camera, has_prev, color.data(), spatial.data(), in.depth, in.normal,
            has_prev ? state.color.data() : none, has_prev ? state.moments.data() : none,
            has_prev ? state.history.data() : none, has_prev ? state.depth.data() : none,
            has_prev ? state.normal.data() : none, acc.data(), moments.data(), history.data(), kW,
            kH, x, y, &t);
    denoise(in, DenoiseMethod::svgf, &state, out.data());
    ASSERT_EQ(std::memcmp(state.history.data(), history.data(), history.size() * sizeof(float)), 0)
        << "frame " << k;
    ASSERT_EQ(std::memcmp(state.moments.data(), moments.data(), moments.size() * sizeof(float)), 0)
        << "frame " << k;
    int young = 0;
    for (int i = 0; i < n; ++i) young += history[2 * size_t(i)] < 4.0f;
    if (young > 0 && young < n) ++young_beside_old;
  }
  EXPECT_GE(young_beside_old, 2);
}

// A new size starts a new history.
TEST(DenoiseTemporal, ANewSizeStartsOver) {
  DenoiseState state;
  std::vector<float> out(3 * kW * kH);
  for (unsigned k = 0; k < 2; ++k)
    denoise(walls(camera_at(0), k).input(), DenoiseMethod::svgf, &state, out.data());
  DenoiseFrame small(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) small.set(x, y, Vec3(0.5f), Vec3(1.0f), Vec3(0, 0, 1), 2.0f);
  small.add_noise(0.1f, 1, true);
  small.camera = camera_at(0);
  denoise(small.input(), DenoiseMethod::svgf, &state, out.data());
  EXPECT_EQ(state.width, 8);
  EXPECT_EQ(mean_of(state.history, 2, 0), 1.0);
}

}  // namespace denoise_temporal_test
}  // namespace multiray
