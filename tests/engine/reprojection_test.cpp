// Reprojected sampling through the engine (engine/frame_views.h, render/reprojection.h):
// the centre view and every hole are the pixels a full render of every view gives, the
// rest are the centre's, whoever rendered what; and the images are as close to a full
// render as two full renders with different seeds are to each other.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "balance/balancer.h"
#include "core/image_metrics.h"
#include "device/cpu/cpu_device.h"
#include "engine/engine.h"
#include "engine/frame_views.h"
#include "scene/builders.h"

namespace multiray {
namespace reprojection_test {

constexpr int kW = 64, kH = 48;
const CameraRig kRig = CameraRig::grid(3, 3, 0.25f);

struct Rendered {
  std::vector<Framebuffer> images;
  std::shared_ptr<const ReprojectedFrame> reprojection;
  std::vector<ViewSetup> views;
  uint64_t samples = 0;  // camera paths the devices traced
  size_t samples_per_pixel = 0;
};

Rendered render(SceneCache& scenes, Sampling mode, const std::string& balancer, int devices,
                int spp, uint64_t seed = 0, CameraRig rig = kRig, int reference_spacing = 0,
                int scale = 1) {
  SamplingSetup sampling;
  sampling.mode = mode;
  sampling.reproject_spp = spp;
  sampling.reference_spacing = reference_spacing;
  const FrameViews views(rig, kW * scale, kH * scale, sampling, &scenes.embree());
  std::vector<std::unique_ptr<CpuDevice>> owned;
  std::vector<Device*> ptrs;
  for (int i = 0; i < devices; ++i) {
    owned.push_back(std::make_unique<CpuDevice>(scenes, CpuDeviceOptions{}, "cpu"));
    ptrs.push_back(owned.back().get());
  }
  Engine engine(ptrs, balance::make_balancer(balancer, devices));
  const FrameInput in = views.make(3, scenes.scene().cameras[0]);
  Rendered out;
  const FrameRecord rec =
      engine.render_frame(3, in.views, RenderSettings{.spp = spp, .seed = seed}, out.images);
  for (const auto& d : rec.devices) out.samples += d.samples;
  out.samples_per_pixel = size_t(spp);
  in.finish(out.images);
  out.reprojection = in.reprojection;
  out.views = in.views;
  return out;
}

bool same(const Framebuffer& a, const Framebuffer& b) {
  return std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3)) == 0;
}

// Every reference and every hole is the full render's pixel; every other pixel is its
// source reference's pixel. Returns the holes and the moved pixels counted.
std::pair<size_t, size_t> expect_traced_or_moved(const Rendered& r, const Rendered& full) {
  size_t holes = 0, moved = 0;
  const ReprojectedFrame& rf = *r.reprojection;
  for (size_t v = 0; v < r.images.size(); ++v) {
    if (rf.is_reference(v)) {
      EXPECT_TRUE(same(r.images[v], full.images[v])) << "reference view " << v;
      continue;
    }
    const ReprojectionMap& m = rf.maps[v];
    const size_t n = m.source.size();
    for (size_t i = 0; i < n; ++i) {
      const int32_t s = m.source[i];
      const bool hole = s == ReprojectionMap::kHole;
      const Vec3 expected =
          hole ? full.images[v].pixels[i]
               : full.images[rf.references.at(size_t(s) / n)].pixels[size_t(s) % n];
      EXPECT_EQ(std::memcmp(&r.images[v].pixels[i], &expected, sizeof(Vec3)), 0)
          << "view " << v << " pixel " << i << (hole ? " (hole)" : "");
      (hole ? holes : moved)++;
    }
  }
  // Only the references and the holes were path-traced.
  const size_t pixels = size_t(kW) * kH;
  EXPECT_EQ(r.samples, (rf.references.size() * pixels + holes) * r.samples_per_pixel);
  return {holes, moved};
}

TEST(ReprojectedSampling, HolesAndTheCentreAreTheFullRendersPixelsTheRestTheCentres) {
  const Scene scene = make_cornell_box();
  SceneCache scenes(scene);
  const Rendered full = render(scenes, Sampling::Uniform, "uniform", 1, 4);
  const Rendered r = render(scenes, Sampling::Reprojected, "uniform", 1, 4);
  ASSERT_TRUE(r.reprojection);
  ASSERT_EQ(r.reprojection->references, std::vector<uint32_t>{4});
  const auto [holes, moved] = expect_traced_or_moved(r, full);
  // The views moved by a quarter of a unit see most of the box the centre sees (the holes
  // are mostly the black outside the box, one ray each, and the walls seen more frontally).
  EXPECT_GT(moved, holes);
  EXPECT_GT(holes, 0u);
}

TEST(ReprojectedSampling, MoreReferencesLeaveFewerHolesAndAllOfThemGiveTheFullImage) {
  const Scene scene = make_cornell_box();
  SceneCache scenes(scene);
  const CameraRig rig = CameraRig::grid(5, 5, 0.2f);
  const Rendered full = render(scenes, Sampling::Uniform, "uniform", 2, 2, 0, rig);
  const Rendered centre = render(scenes, Sampling::Reprojected, "dlb", 2, 2, 0, rig, 0);
  const Rendered nine = render(scenes, Sampling::Reprojected, "dlb", 2, 2, 0, rig, 2);
  EXPECT_EQ(nine.reprojection->references,
            (std::vector<uint32_t>{0, 2, 4, 10, 12, 14, 20, 22, 24}));
  expect_traced_or_moved(centre, full);
  expect_traced_or_moved(nine, full);
  // Holes that see the box (the black outside it is a hole for any number of references),
  // as a share of the pixels of the views that are not references.
  const auto surface_holes = [&](const Rendered& r) {
    double holes = 0, pixels = 0;
    for (size_t v = 0; v < r.views.size(); ++v) {
      if (r.reprojection->is_reference(v)) continue;
      const GBuffer g = render_gbuffer(scenes.embree(), r.views[v]);
      for (size_t i = 0; i < g.depth.size(); ++i)
        holes += std::isfinite(g.depth[i]) &&
                 r.reprojection->maps[v].source[i] == ReprojectionMap::kHole;
      pixels += double(g.depth.size());
    }
    return holes / pixels;
  };
  const double share_centre = surface_holes(centre), share_nine = surface_holes(nine);
  std::printf("holes on the box: centre alone %.1f%%, nine references %.1f%%\n",
              100 * share_centre, 100 * share_nine);
  EXPECT_LT(3 * share_nine, share_centre);
  // Every view a reference: the full render itself.
  const Rendered all = render(scenes, Sampling::Reprojected, "dlb", 2, 2, 0, rig, 1);
  for (size_t v = 0; v < all.images.size(); ++v) EXPECT_TRUE(same(all.images[v], full.images[v]));
}

TEST(ReprojectedSampling, ImagesDoNotDependOnTheSplit) {
  const Scene scene = make_cornell_box();
  SceneCache scenes(scene);
  const Rendered one = render(scenes, Sampling::Reprojected, "uniform", 1, 2);
  for (const std::string spec : {"dlb", "semi-static", "queue", "uniform:layout=views"})
    for (int devices : {2, 3}) {
      const Rendered r = render(scenes, Sampling::Reprojected, spec, devices, 2);
      for (size_t v = 0; v < r.images.size(); ++v)
        EXPECT_TRUE(same(r.images[v], one.images[v]))
            << spec << " on " << devices << " devices, view " << v;
    }
}

TEST(ReprojectedSampling, MovedPixelsAreAsFarFromAFullRenderAsAnotherSeeds) {
  // The box is diffuse but for the sphere; a moved pixel carries its reference pixel's
  // noise instead of its own, as the same pixel of a full render with another seed does.
  // Wrong pixels (a shifted map, a missed disocclusion) add error beyond that. Holes are
  // left out: they equal the full render (tested above), which would hide such error.
  // 128x96 views, so that edge pixels are a small part.
  const Scene scene = make_cornell_box();
  SceneCache scenes(scene);
  const Rendered full = render(scenes, Sampling::Uniform, "uniform", 2, 16, 0, kRig, 0, 2);
  const Rendered other_seed = render(scenes, Sampling::Uniform, "uniform", 2, 16, 1, kRig, 0, 2);
  const Rendered r = render(scenes, Sampling::Reprojected, "uniform", 2, 16, 0, kRig, 0, 2);
  const auto squared = [](const Vec3& a, const Vec3& b) {
    double e = 0;
    for (int c = 0; c < 3; ++c) {
      const double d = std::clamp(double(a[c]), 0.0, 1.0) - std::clamp(double(b[c]), 0.0, 1.0);
      e += d * d;
    }
    return e;
  };
  double moved = 0, seed = 0;
  size_t n = 0;
  for (size_t v = 0; v < r.images.size(); ++v) {
    if (r.reprojection->is_reference(v)) continue;
    for (size_t i = 0; i < r.images[v].pixels.size(); ++i) {
      if (r.reprojection->maps[v].source[i] == ReprojectionMap::kHole) continue;
      moved += squared(r.images[v].pixels[i], full.images[v].pixels[i]);
      seed += squared(other_seed.images[v].pixels[i], full.images[v].pixels[i]);
      ++n;
    }
  }
  std::printf("squared error over %zu moved pixels: reprojected %.4g, another seed %.4g\n", n,
              moved / double(n), seed / double(n));
  EXPECT_GT(n, size_t(8 * 4 * kW * kH / 2));
  // Measured 1.22x: a moved pixel also carries its reference's mix of surfaces at edges
  // and the mirror sphere's reflections as the centre sees them. Every landing one pixel
  // to the right gives 1.57x.
  EXPECT_LT(moved, 1.35 * seed);
}

}  // namespace reprojection_test
}  // namespace multiray
