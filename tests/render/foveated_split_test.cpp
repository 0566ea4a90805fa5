// Foveated images do not depend on how the screen was split: one rect, many rects, many
// devices through the engine with work-splitting balancers all give the same bits, and
// the engine hands balancers the foveated sample counts so areas follow the samples.
#include <gtest/gtest.h>

#include <cstring>
#include <thread>

#include "balance/balancer.h"
#include "device/cpu/cpu_device.h"
#include "device/work_list.h"
#include "engine/engine.h"
#include "render/foveated.h"
#include "scene/builders.h"

namespace multiray {
namespace foveated_split_test {

constexpr int kW = 61, kH = 37;

ViewSetup foveated_view(const Scene& scene, const FoveationFrame& f, int frame) {
  ViewSetup v;
  v.camera = scene.cameras[0];
  v.width = f.width, v.height = f.height, v.frame = uint32_t(frame), v.foveation = &f;
  return v;
}

bool same_bits(const Framebuffer& a, const Framebuffer& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3)) == 0;
}

// Renders `rects` one after the other with the kernel (each rect renders its own samples).
Framebuffer render_rects(SceneCache& rs, const ViewSetup& v, const RenderSettings& s,
                         const std::vector<Rect>& rects) {
  const std::unique_ptr<Kernel> sampled = find_cpu_kernel(s.kernel)->make(rs, false);
  const FoveatedKernel kernel(*sampled);
  Framebuffer fb(v.width, v.height);
  std::vector<Vec3> scratch;
  for (const Rect& r : rects) kernel.render_rect(v, s, r, fb, scratch);
  return fb;
}

TEST(FoveatedSampling, ImageIsIndependentOfRectsAndDevicesBitForBit) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const FoveationPattern pattern = make_foveation_pattern(kW, kH, {});
  for (const char* kernel_name : {"ao", "path"}) {
    RenderSettings s;
    s.kernel = kernel_name;
    s.max_bounces = 3;
    const FoveationFrame f = prepare_foveation_frame(pattern, 0.35f, 0.6f);
    const ViewSetup v = foveated_view(scene, f, 2);
    const Framebuffer whole = render_rects(rs, v, s, {{0, 0, kW, kH}});
    // Uneven pieces: thin strips, a single pixel, a column through the fovea.
    const std::vector<Rect> pieces = {{0, 0, kW, 3},   {0, 3, 20, 30},  {20, 3, 21, 4},
                                      {21, 3, 22, 30}, {20, 4, 21, 30}, {22, 3, kW, 30},
                                      {0, 30, kW, kH}};
    EXPECT_TRUE(same_bits(whole, render_rects(rs, v, s, pieces)));
    // Three CPU devices of two threads each pulling the pieces concurrently.
    CpuDeviceOptions two_threads;
    two_threads.threads = 2, two_threads.tile = 5;
    std::vector<std::unique_ptr<CpuDevice>> devices;
    for (int i = 0; i < 3; ++i)
      devices.push_back(std::make_unique<CpuDevice>(rs, two_threads, "cpu:threads=2"));
    std::vector<WorkItem> units;
    for (const Rect& r : pieces) units.push_back(WorkItem{r, 0});
    ListWorkSource source(units);
    std::vector<Framebuffer> out{Framebuffer(kW, kH)};
    const FrameJob job{{v}, s, &out};
    std::vector<std::thread> threads;
    for (int i = 0; i < 3; ++i)
      threads.emplace_back([&, i] { devices[size_t(i)]->render(job, source, i); });
    for (auto& t : threads) t.join();
    EXPECT_TRUE(same_bits(whole, out[0]));
  }
}

// Foveation data made for another image size is refused: the device reports a failed
// frame instead of reading out of bounds.
TEST(FoveatedSampling, DeviceRefusesDataOfAnotherSize) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const FoveationFrame f = prepare_foveation_frame(make_foveation_pattern(12, 12, {}), 0.5f, 0.5f);
  ViewSetup v = foveated_view(scene, f, 0);
  v.width = 10, v.height = 10;
  CpuDevice device(rs, {}, "cpu");
  ListWorkSource source({WorkItem{{0, 0, 10, 10}, 0}});
  std::vector<Framebuffer> out{Framebuffer(10, 10)};
  const DeviceReport r = device.render(FrameJob{{v}, RenderSettings{}, &out}, source, 0);
  EXPECT_TRUE(r.failed);
  EXPECT_NE(r.error.find("12x12"), std::string::npos) << r.error;
}

// Frames with a moving gaze through the engine: every work-splitting balancer on 1-3
// devices of different emulated speeds reproduces the single-rect image of each frame.
TEST(FoveatedSampling, EngineImagesMatchForEveryBalancerAndDeviceCount) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const FoveationPattern pattern = make_foveation_pattern(kW, kH, {});
  RenderSettings s;
  s.kernel = "ao";
  std::vector<FoveationFrame> frames;
  std::vector<Framebuffer> reference;
  for (int f = 0; f < 3; ++f) {
    frames.push_back(prepare_foveation_frame(pattern, 0.2f + 0.3f * f, 0.7f - 0.2f * f));
    reference.push_back(
        render_rects(rs, foveated_view(scene, frames.back(), f), s, {{0, 0, kW, kH}}));
  }
  for (const std::string spec : {"semi-static", "hybrid", "queue:tile=8", "uniform"})
    for (int n : {1, 2, 3}) {
      std::vector<std::unique_ptr<CpuDevice>> owned;
      std::vector<Device*> ptrs;
      for (int i = 0; i < n; ++i) {
        CpuDeviceOptions o;
        o.speed = 1.0 / (i + 1);
        owned.push_back(std::make_unique<CpuDevice>(rs, o, "cpu"));
        ptrs.push_back(owned.back().get());
      }
      Engine engine(ptrs, balance::make_balancer(spec, n));
      for (int f = 0; f < 3; ++f) {
        const FrameRecord rec =
            engine.render_frame(f, {foveated_view(scene, frames[size_t(f)], f)}, s);
        // Every pixel once; the samples reported are the frame's, however it was cut
        // (a unit reports the samples positioned in it, not those of its borders).
        uint64_t pixels = 0, samples = 0;
        for (const auto& d : rec.devices) pixels += d.pixels, samples += d.samples;
        EXPECT_EQ(pixels, uint64_t(kW) * kH);
        EXPECT_EQ(samples, frames[size_t(f)].used_samples) << spec << " on " << n << " devices";
        EXPECT_TRUE(same_bits(engine.images()[0], reference[size_t(f)]))
            << spec << " on " << n << " devices, frame " << f;
      }
    }
}

// The balancers see the samples positioned in each pixel: semi-static's first split of
// an even pair (multiray's form, which reads the frame's own sample map) gives both
// devices the same samples, so the band with the fovea is smaller in area than the other.
TEST(FoveatedSampling, SemiStaticSplitsBySamplesNotArea) {
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const int w = 64, h = 64;
  const FoveationFrame f = prepare_foveation_frame(make_foveation_pattern(w, h, {}), 0.5f, 0.2f);
  CpuDevice a(rs, {}, "cpu"), b(rs, {}, "cpu");
  Engine engine({&a, &b}, balance::make_balancer("semi-static:split=rows:cdf=frame", 2));
  RenderSettings s;
  s.kernel = "ao";
  engine.render_frame(0, {foveated_view(scene, f, 0)}, s);
  const balance::Plan& plan = engine.last_plan();
  int64_t area[2] = {0, 0};
  double samples[2] = {0, 0};
  for (int d = 0; d < 2; ++d)
    for (const balance::WorkItem& it : plan.assigned[size_t(d)]) {
      area[d] += it.rect.area();
      for (int y = it.rect.y0; y < it.rect.y1; ++y)
        for (int x = it.rect.x0; x < it.rect.x1; ++x)
          samples[d] += f.pixel_samples[size_t(y * w + x)];
    }
  EXPECT_EQ(area[0] + area[1], int64_t(w) * h);
  EXPECT_LT(area[0], area[1] / 2);  // the gaze is in the top band
  EXPECT_NEAR(samples[0], samples[1], 0.02 * double(f.used_samples));
}

}  // namespace foveated_split_test
}  // namespace multiray
