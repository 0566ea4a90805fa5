// Spatial reprojection (render/reprojection.h) on depth buffers of known geometry, where
// where each pixel must land and which pixels are disoccluded follow from the camera
// alone: a 90-degree pinhole 64 px high has a focal length of 32 px, so a view moved by s
// sees a surface at depth D shifted by 32 s / D pixels.
#include <gtest/gtest.h>

#include <cmath>

#include "render/reprojection.h"
#include "scene/camera_rig.h"

namespace multiray {
namespace reprojection_test {

constexpr int kW = 64, kH = 64;

ViewSetup view_at(Vec3 eye) {
  ViewSetup v;
  v.camera = Camera{eye, eye + Vec3(0, 0, -1), {0, 1, 0}, 90.0f};
  v.width = kW, v.height = kH;
  return v;
}

// The reference's depths of a scene given as depth(x, y) at pixel centres.
template <class F>
GBuffer depths(F depth) {
  GBuffer g;
  g.width = kW, g.height = kH;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) g.depth.push_back(depth(x, y));
  g.normal.assign(g.depth.size(), Vec3(0, 0, 1));
  return g;
}

int32_t at(int x, int y) { return y * kW + x; }

TEST(Reprojection, AWallMovesByItsDisparityAndTheUncoveredBorderIsAHole) {
  const GBuffer g = depths([](int, int) { return 4.0f; });
  // Moved right by 0.5: disparity 32 * 0.5 / 4 = 4 px, so target x sees reference x + 4.
  const ReprojectionMap m = reproject_view(g, view_at({0, 0, 0}), view_at({0.5f, 0, 0}));
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const int32_t expected = x + 4 < kW ? at(x + 4, y) : ReprojectionMap::kHole;
      ASSERT_EQ(m.source[size_t(at(x, y))], expected) << x << "," << y;
    }
  EXPECT_EQ(m.holes(), size_t(4 * kH));
  // Moved up by 0.5 instead: target row y sees reference row y - 4.
  const ReprojectionMap up = reproject_view(g, view_at({0, 0, 0}), view_at({0, 0.5f, 0}));
  EXPECT_EQ(up.source[size_t(at(10, 20))], at(10, 16));
  EXPECT_EQ(up.source[size_t(at(10, 3))], ReprojectionMap::kHole);
}

TEST(Reprojection, TheBackgroundBesideAForegroundSquareIsDisoccluded) {
  // A square at depth 2 over reference pixels [24, 40)^2 in front of a wall at depth 4.
  const auto in_square = [](int x, int y) { return x >= 24 && x < 40 && y >= 24 && y < 40; };
  const GBuffer g = depths([&](int x, int y) { return in_square(x, y) ? 2.0f : 4.0f; });
  const ReprojectionMap m = reproject_view(g, view_at({0, 0, 0}), view_at({0.5f, 0, 0}));
  // In the target the square moves 8 px to [16, 32) and the wall 4 px: the wall behind
  // the square's old place, target x in [20, 36), shows at [32, 36) and nobody saw it.
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW - 4; ++x) {
      const int32_t s = m.source[size_t(at(x, y))];
      if (y >= 24 && y < 40 && x >= 32 && x < 36) {
        EXPECT_EQ(s, ReprojectionMap::kHole) << x << "," << y;
      } else if (y >= 24 && y < 40 && x >= 16 && x < 32) {
        EXPECT_EQ(s, at(x + 8, y)) << "square at " << x << "," << y;  // in front wins
      } else {
        EXPECT_EQ(s, at(x + 4, y)) << "wall at " << x << "," << y;
      }
    }
  EXPECT_EQ(m.holes(), size_t(4 * kH + 4 * 16));
}

TEST(Reprojection, GapsOfASlantedWallAreFilledAndStepsAreNot) {
  // A wall slanted away to the right: z = -(3 + 0.3 x) in the world. Its depth at each
  // reference pixel comes from intersecting that pixel's ray with the plane.
  const auto slanted = [](int x, int) {
    const float sx = (float(x) + 0.5f) / 32.0f - 1.0f;  // direction (sx, sy, -1)
    return 3.0f / (1.0f - 0.3f * sx);
  };
  const GBuffer g = depths(slanted);
  const ViewSetup ref = view_at({0, 0, 0}), tgt = view_at({0.6f, 0, 0});
  // Seen from the right, the wall's disparity (32 * 0.6 / depth) shrinks to the right: it
  // spreads over 6% more pixels than in the reference and the forward warp alone leaves
  // one-pixel cracks, about four a row.
  const size_t border = size_t(5 * kH);  // what lies right of the reference's frustum
  ReprojectionOptions no_closing;
  no_closing.depth_tolerance = 0;
  const size_t cracked = reproject_view(g, ref, tgt, no_closing).holes();
  EXPECT_GT(cracked, border + size_t(2 * kH));
  const ReprojectionMap m = reproject_view(g, ref, tgt);
  EXPECT_EQ(m.holes(), border);
  // Every pixel that took a colour took the reference pixel that sees its point of the
  // wall (to within the pixel its centre falls into).
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const int32_t s = m.source[size_t(at(x, y))];
      if (s == ReprojectionMap::kHole) continue;
      EXPECT_EQ(s / kW, y);
      const float disparity = 32.0f * 0.6f / slanted(s % kW, y);
      EXPECT_NEAR(float(s % kW) + 0.5f - disparity, float(x) + 0.5f, 1.0f) << x << "," << y;
    }
  // Closer and seen from farther right (disparity 19-35 px, growing by 0.25-0.47 px a
  // pixel) the warp alone leaves a gap after every second or third pixel: still only the
  // border is a hole, i.e. in every row the holes are the pixels right of the last reached.
  const GBuffer near = depths([&](int x, int y) { return slanted(x, y) / 2.5f; });
  const ReprojectionMap wide = reproject_view(near, ref, view_at({1.0f, 0, 0}));
  EXPECT_GT(reproject_view(near, ref, view_at({1.0f, 0, 0}), no_closing).holes(),
            wide.holes() + size_t(2 * kH));
  for (int y = 0; y < kH; ++y) {
    int last_reached = -1, holes = 0;
    for (int x = 0; x < kW; ++x)
      if (wide.source[size_t(at(x, y))] == ReprojectionMap::kHole)
        ++holes;
      else
        last_reached = x;
    EXPECT_EQ(holes, kW - 1 - last_reached) << "row " << y;
  }
  // A step between two walls is no crack: with the tolerance the left wall's last
  // pixel and the right wall's first stay apart and the gap between them is a hole.
  const GBuffer step = depths([](int x, int) { return x < 32 ? 2.0f : 4.0f; });
  const ReprojectionMap s = reproject_view(step, ref, view_at({0.5f, 0, 0}));
  EXPECT_EQ(s.source[size_t(at(24, 5))], ReprojectionMap::kHole);  // 32 - 8 = 24 .. 28
  EXPECT_EQ(s.source[size_t(at(27, 5))], ReprojectionMap::kHole);
}

TEST(Reprojection, ASecondReferenceFillsWhatTheFirstCannotSee) {
  // The square in front of the wall as before, seen by reference A at x = 0 and by B at
  // x = 1, where the square lies 16 px left, over [8, 24). The target at x = 0.5 lies
  // between them: what A cannot see (right of the square, and the right border) B does.
  const auto square_at = [](int x0) {
    return depths(
        [=](int x, int y) { return x >= x0 && x < x0 + 16 && y >= 24 && y < 40 ? 2.0f : 4.0f; });
  };
  const GBuffer ga = square_at(24), gb = square_at(8);
  const ViewSetup a = view_at({0, 0, 0}), b = view_at({1.0f, 0, 0}), t = view_at({0.5f, 0, 0});
  const ReferenceSurface ra = prepare_reference(ga, a), rb = prepare_reference(gb, b);
  const ReprojectionMap m = reproject_view({&ra, &rb}, t);
  EXPECT_EQ(m.holes(), 0u);
  const int32_t n = kW * kH;
  EXPECT_EQ(m.source[size_t(at(33, 30))], n + at(29, 30));          // B's wall, disoccluded in A
  EXPECT_EQ(m.source[size_t(at(kW - 1, 30))], n + at(kW - 5, 30));  // A's right border
  EXPECT_EQ(m.source[size_t(at(10, 30))], at(14, 30));  // both see it: the first keeps it
  EXPECT_EQ(m.source[size_t(at(20, 30))], at(28, 30));  // the square, from A
}

TEST(Reprojection, TheSkyIsNeverMovedAndBehindTheCameraIsIgnored) {
  const GBuffer g = depths([](int x, int) { return x < 32 ? INFINITY : 4.0f; });
  const ReprojectionMap m = reproject_view(g, view_at({0, 0, 0}), view_at({0.5f, 0, 0}));
  EXPECT_EQ(m.source[size_t(at(10, 10))], ReprojectionMap::kHole);  // sky: traced
  EXPECT_EQ(m.source[size_t(at(40, 10))], at(44, 10));
  // A target far in front of everything sees nothing of the reference: all holes.
  const ReprojectionMap ahead = reproject_view(g, view_at({0, 0, 0}), view_at({0, 0, -10}));
  EXPECT_EQ(ahead.holes(), size_t(kW * kH));
}

TEST(Reprojection, FillCopiesTheSourcesAndTheSampleMapMarksHoles) {
  const GBuffer g = depths([](int, int) { return 4.0f; });
  ReprojectedFrame frame;
  frame.references = {1};
  frame.maps.push_back(reproject_view(g, view_at({0, 0, 0}), view_at({0.5f, 0, 0})));
  frame.maps.emplace_back();
  std::vector<Framebuffer> images(2, Framebuffer(kW, kH));
  for (int i = 0; i < kW * kH; ++i) images[1].pixels[size_t(i)] = Vec3(float(i), 0, 1);
  images[0].pixels.assign(size_t(kW * kH), Vec3(-1.0f));  // what the devices traced
  frame.fill(images);
  EXPECT_EQ(images[0].at(3, 7).x, float(at(7, 7)));  // reference pixel (7, 7)
  EXPECT_EQ(images[0].at(kW - 1, 7).x, -1.0f);       // a hole keeps its traced value
  EXPECT_DOUBLE_EQ(frame.hole_fraction(), 4.0 / kW);
  const std::vector<uint8_t> spp = hole_sample_map(frame.maps[0], 3);
  EXPECT_EQ(spp[size_t(at(kW - 1, 0))], 3);
  EXPECT_EQ(spp[size_t(at(0, 0))], 0);
  EXPECT_THROW(hole_sample_map(frame.maps[0], 0), std::invalid_argument);
  EXPECT_THROW(hole_sample_map(frame.maps[0], 256), std::invalid_argument);
  images.pop_back();
  EXPECT_THROW(frame.fill(images), std::invalid_argument);
  // References of a grid: every K-th view from the centre, across and down.
  EXPECT_EQ(CameraRig::grid(9, 9, 0.2f).reference_views(0), std::vector<int>{40});
  EXPECT_EQ(CameraRig::grid(9, 9, 0.2f).reference_views(3),
            (std::vector<int>{10, 13, 16, 37, 40, 43, 64, 67, 70}));
  EXPECT_EQ(CameraRig::grid(9, 9, 0.2f).reference_views(4),
            (std::vector<int>{0, 4, 8, 36, 40, 44, 72, 76, 80}));
  EXPECT_EQ(CameraRig::grid(2, 1, 0.2f).reference_views(0), std::vector<int>{1});
  EXPECT_EQ(CameraRig::grid(3, 3, 0.2f).reference_views(5), std::vector<int>{4});
}

}  // namespace reprojection_test
}  // namespace multiray
