// The denoiser's normal term on curved surfaces (render/shared/denoise_normal.h): a
// pixel's turn of the normal per pixel, the cosine its taps are weighted by, and on whole
// frames that a surface whose normal turns steadily lets its dark pixels take the light
// of their neighbours while a crease between planes still stops the filter.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "render/denoise_frames.h"
#include "render/shared/denoise.h"

namespace multiray {
namespace denoise_normal_test {

using testing::DenoiseFrame;

constexpr float kDegree = 0.01745329252f;

// A unit normal turned by `angle` (radians) from +z about the y axis.
Vec3 turned(float angle) { return Vec3(std::sin(angle), 0.0f, std::cos(angle)); }

float chord_of(float angle) { return 2.0f * std::sin(0.5f * angle); }

// A row of normals turning 12 degrees a pixel, then a crease of 50 degrees, then a plane,
// then a miss: each pixel's turn is the smaller of its one-sided chords, the image's
// border and a miss counting as no neighbour.
TEST(DenoiseNormal, TurnIsTheSmallerOneSidedChord) {
  const float a = 12.0f * kDegree;
  // pixels 0..4 turn steadily (0, 12, 24, 36, 48 degrees), 5..7 a plane at 98, 8 a miss
  const float angles[] = {0.0f, a, 2 * a, 3 * a, 4 * a, 98 * kDegree, 98 * kDegree, 98 * kDegree};
  std::vector<float> normal(3 * 9, 0.0f), depth(9, 2.0f);
  for (int i = 0; i < 8; ++i) {
    const Vec3 n = turned(angles[i]);
    for (int c = 0; c < 3; ++c) normal[size_t(3 * i + c)] = n[c];
  }
  depth[8] = INFINITY;
  const auto turn = [&](int i) {
    return denoise_normal_turn(normal.data(), depth.data(), i, 1, i > 0, i < 8);
  };
  EXPECT_NEAR(turn(0), chord_of(a), 1e-6f) << "the border: one side";
  EXPECT_NEAR(turn(2), chord_of(a), 1e-6f) << "a steady turn";
  EXPECT_NEAR(turn(4), chord_of(a), 1e-6f) << "beside the crease: its own surface's turn";
  EXPECT_LT(turn(5), 1e-3f) << "the plane beside the crease: no turn";
  EXPECT_LT(turn(6), 1e-3f);
  EXPECT_LT(turn(7), 1e-3f) << "beside a miss: the plane's side";
  EXPECT_EQ(turn(8), 0.0f) << "a miss";
  // A hit whose only neighbour is a miss (normal 0): no turn.
  EXPECT_EQ(denoise_normal_turn(normal.data() + 3 * 7, depth.data() + 7, 0, 1, 0, 1), 0.0f);
  // Along y (stride 3 in a 3x3 frame): the same function.
  EXPECT_NEAR(denoise_normal_turn(normal.data(), depth.data(), 4, 3, 1, 1), chord_of(3 * a),
              1e-6f);
}

// The tap's cosine: its own where nothing is predicted (to the bit), 1 within the
// predicted turn, the cosine of the angle beyond the prediction past it (the turn along
// y counting as along x), and its own where it is not positive.
TEST(DenoiseNormal, CosineAllowsOnlyTheTurnBeyondThePrediction) {
  for (float c : {1.0f, 0.9999f, 0.99f, 0.9f, 0.5f, 0.1f})
    EXPECT_EQ(denoise_normal_cosine(c, 0.0f, 0.0f, 3, -2), c) << c;
  const float a = 10.0f * kDegree, t = chord_of(a);
  // 3 pixels along x, 2 along y, at 10 degrees a pixel either way: a chord of 5 t.
  for (float angle : {0.0f, 20.0f, 45.0f}) {
    const float c = std::cos(angle * kDegree);
    EXPECT_EQ(denoise_normal_cosine(c, t, t, 3, -2), 1.0f) << angle << " degrees";
    EXPECT_EQ(denoise_normal_cosine(c, 0.0f, t, 0, 5), 1.0f) << angle << " degrees, along y";
  }
  for (float angle : {60.0f, 75.0f, 89.0f}) {
    const float c = std::cos(angle * kDegree);
    const float beyond = chord_of(angle * kDegree) - 5.0f * t;
    const float want = 1.0f - 0.5f * beyond * beyond;
    EXPECT_NEAR(denoise_normal_cosine(c, t, t, -3, 2), want, 1e-5f) << angle << " degrees";
    EXPECT_NEAR(denoise_normal_cosine(c, t, 0.0f, 5, 7), want, 1e-5f) << angle << " degrees";
    EXPECT_LT(denoise_normal_cosine(c, t, t, 1, 0), want) << "less predicted, less weight";
  }
  for (float c : {0.0f, -0.5f}) EXPECT_EQ(denoise_normal_cosine(c, 1.0f, 1.0f, 4, 4), c);
}

// Curved surfaces seen face on, at one depth and albedo, all lit alike, in cells of 11x11
// pixels whose normal turns 15 degrees a pixel (-75..75): flutes turning along x or along
// y, and domes turning along both. Each pixel's samples caught the light with probability
// 1/2: a lit pixel holds twice the light, with its variance, a dark one nothing with
// variance 0 (a dim room at a few samples per pixel). With cos^128 alone (0.012 a pixel
// away, 1e-8 two away) the darkest pixel kept 0.16-0.20 of the clean 0.5 on the flutes
// (the pixels along the flutes' axis share its normal) and 2.4e-5 on the domes (black);
// allowing for the turn, every dark pixel takes at least half of the light (measured
// 0.32-0.35).
enum class Curve { flutes_x, flutes_y, domes };

DenoiseFrame curved(Curve curve, unsigned seed) {
  DenoiseFrame f(60, 45);
  std::mt19937 rng(seed);
  std::bernoulli_distribution lit(0.5);
  f.beauty.assign(f.clean.size(), 0.0f);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const float ax = float(x % 11 - 5) * 15.0f * kDegree;
      const float ay = float(y % 11 - 5) * 15.0f * kDegree;
      const Vec3 n = curve == Curve::flutes_x   ? turned(ax)
                     : curve == Curve::flutes_y ? Vec3(0.0f, std::sin(ay), std::cos(ay))
                                                : Vec3(std::sin(ax) * std::cos(ay), std::sin(ay),
                                                       std::cos(ax) * std::cos(ay));
      f.set(x, y, Vec3(0.5f), Vec3(1.0f), n, 2.0f);
      const size_t i = f.index(x, y);
      const bool caught = lit(rng);
      for (int c = 0; c < 3; ++c) f.beauty[3 * i + size_t(c)] = caught ? 1.0f : 0.0f;
      f.variance[i] = caught ? 0.25f : 0.0f;
    }
  f.with_variance = true;
  return f;
}

TEST(DenoiseNormal, CurvedSurfaceFillsItsDarkPixels) {
  const char* names[] = {"flutes along x", "flutes along y", "domes"};
  for (Curve curve : {Curve::flutes_x, Curve::flutes_y, Curve::domes}) {
    const DenoiseFrame f = curved(curve, 3);
    std::vector<float> out(f.beauty.size());
    denoise(f.input(), DenoiseMethod::atrous, nullptr, out.data());
    float darkest = 1.0f;
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        const size_t i = f.index(x, y);
        if (f.beauty[3 * i] == 0.0f) darkest = std::min(darkest, out[3 * i]);
      }
    EXPECT_GT(darkest, 0.5f * 0.5f)
        << names[int(curve)] << ": the darkest " << darkest << " of the clean 0.5";
  }
}

// `--denoise-normal svgf`, the papers' term: the normals' cosine alone, so the domes'
// dark pixels stay as dark as the old term left them (2.4e-5 of the light measured),
// while on a plane, where no turn is predicted, both forms give the same bits.
TEST(DenoiseNormal, PapersTermIsTheNormalsCosineAlone) {
  DenoiseParams papers;
  ASSERT_TRUE(parse_denoise_normal("svgf", papers));
  EXPECT_FALSE(papers.normal_turn);
  const DenoiseFrame domes = curved(Curve::domes, 3);
  std::vector<float> out(domes.beauty.size());
  denoise(domes.input(), DenoiseMethod::atrous, nullptr, out.data(), papers);
  float darkest = 1.0f;
  for (size_t i = 0; i < domes.variance.size(); ++i)
    if (domes.beauty[3 * i] == 0.0f) darkest = std::min(darkest, out[3 * i]);
  EXPECT_LT(darkest, 0.01f * 0.5f) << "the darkest of the clean 0.5";

  DenoiseFrame plane(40, 30);
  for (int y = 0; y < plane.height; ++y)
    for (int x = 0; x < plane.width; ++x)
      plane.set(x, y, Vec3(0.6f), Vec3(x < 20 ? 1.0f : 0.3f), turned(0.3f), 2.0f + 0.01f * y);
  plane.add_noise(0.3f, 9, true);
  std::vector<float> ours(plane.beauty.size()), theirs(plane.beauty.size());
  denoise(plane.input(), DenoiseMethod::atrous, nullptr, ours.data());
  denoise(plane.input(), DenoiseMethod::atrous, nullptr, theirs.data(), papers);
  EXPECT_EQ(0, std::memcmp(ours.data(), theirs.data(), ours.size() * sizeof(float)));
  EXPECT_FALSE(parse_denoise_normal("cosine", papers));
}

// Two planes meeting at a crease of 30 or 90 degrees, at one depth and albedo, one lit 1
// and the other 0.25, noise of 30%: the columns on either side of the crease keep their
// own plane's light (mean within 5% of the contrast, no pixel off by a third of it), as
// with cos^128 alone: a plane predicts no turn, nor does a pixel beside the crease.
TEST(DenoiseNormal, CreaseStillStopsTheFilter) {
  for (float crease : {30.0f, 90.0f}) {
    DenoiseFrame f(64, 48);
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x)
        f.set(x, y, Vec3(0.7f), Vec3(x < 32 ? 1.0f : 0.25f),
              turned(x < 32 ? 0.0f : crease * kDegree), 2.0f);
    f.add_noise(0.3f, 5, true);
    std::vector<float> out(f.beauty.size());
    denoise(f.input(), DenoiseMethod::atrous, nullptr, out.data());
    const float contrast = 0.7f * 0.75f;
    for (int x : {30, 31, 32, 33}) {
      const float want = f.clean_at(x, 0).y;
      double mean = 0;
      for (int y = 0; y < f.height; ++y) {
        const float v = out[3 * f.index(x, y) + 1];
        EXPECT_LT(std::abs(v - want), contrast / 3) << crease << " degrees, " << x << "," << y;
        mean += v / f.height;
      }
      EXPECT_LT(std::abs(mean - want), 0.05 * contrast) << crease << " degrees, column " << x;
    }
  }
}

}  // namespace denoise_normal_test
}  // namespace multiray
