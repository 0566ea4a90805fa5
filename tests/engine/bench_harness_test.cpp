// The bench harness's bit-identity check: every view of every frame is compared between
// the balancers' lanes, so one wrong pixel in one view of one early frame is caught.
#include <gtest/gtest.h>

#include "balance/balancer.h"
#include "device/cpu/cpu_device.h"
#include "engine/bench_harness.h"
#include "scene/builders.h"
#include "scene/camera_rig.h"

namespace multiray {
namespace bench_harness_test {

constexpr int kW = 24, kH = 16;

// A CPU device that, on its `nth` render of frame `frame` (0-based, counting the ideal
// timings too), changes the first pixel of the first item of view `view` it rendered: a
// lane whose image differs from the others in that view of that frame only.
class TamperingDevice : public Device {
 public:
  TamperingDevice(SceneCache& cache, int frame, int nth, int view)
      : cpu_(cache, {}, "cpu"), frame_(frame), nth_(nth), view_(view) {}
  const DeviceInfo& info() const override { return cpu_.info(); }
  void set_emulated_speed(double speed) override { cpu_.set_emulated_speed(speed); }
  DeviceReport render(const FrameJob& job, WorkSource& source, int index) override {
    DeviceReport r = cpu_.render(job, source, index);
    if (int(job.views.at(0).frame) != frame_ || calls_++ != nth_) return r;
    for (const ItemReport& item : r.items)
      if (item.item.view == view_) {
        (*job.outputs)[size_t(view_)].at(item.item.rect.x0, item.item.rect.y0).x += 1.0f;
        tampered_ = true;
        break;
      }
    return r;
  }
  bool tampered() const { return tampered_; }

 private:
  CpuDevice cpu_;
  int frame_, nth_, view_, calls_ = 0;
  bool tampered_ = false;
};

BenchResult bench(SceneCache& cache, TamperingDevice& tamper, const BenchConfig& config) {
  CpuDevice other(cache, {}, "cpu");
  std::vector<Device*> devices{&tamper, &other};
  std::vector<std::unique_ptr<balance::Balancer>> lanes;
  for (const char* spec : {"uniform", "static:ratios=1/2", "uniform:layout=columns"})
    lanes.push_back(balance::make_balancer(spec, 2));
  Session session(devices, std::move(lanes), FrameViews(CameraRig::grid(2, 1, 0.2f), kW, kH, {}),
                  CameraPath::orbit(cache.scene().cameras[0], 8), RenderSettings{.spp = 1});
  return run_bench(session, devices, {1, 1}, {}, session.settings(), config);
}

TEST(BenchHarness, ComparesEveryViewOfEveryFrame) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  BenchConfig config;
  config.frames = 4, config.warmup = 0, config.ideal_frames = 1;  // ideal timed on frame 0
  // Frame 1 of 4 (not the last), view 1 (not view 0), lane 1 (its second render of the
  // frame: no ideal timing on frame 1).
  TamperingDevice tamper(cache, 1, 1, 1);
  const BenchResult r = bench(cache, tamper, config);
  ASSERT_TRUE(tamper.tampered());
  ASSERT_EQ(r.mismatched_frames.size(), 3u);
  EXPECT_TRUE(r.mismatched_frames[0].empty());
  EXPECT_EQ(r.mismatched_frames[1], std::vector<int>{1});
  EXPECT_TRUE(r.mismatched_frames[2].empty());  // lane 2 agrees with lane 0
  for (const BenchLane& lane : r.lanes) EXPECT_EQ(lane.image_hashes.size(), 4u);
  EXPECT_NE(r.lanes[1].image_hashes[1], r.lanes[0].image_hashes[1]);
  EXPECT_EQ(r.lanes[2].image_hashes[1], r.lanes[0].image_hashes[1]);
}

TEST(BenchHarness, UntamperedLanesAgreeOnEveryFrame) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  BenchConfig config;
  config.frames = 3, config.warmup = 0, config.ideal_frames = 1;
  TamperingDevice untouched(cache, -1, 0, 0);  // frame -1 never comes
  const BenchResult r = bench(cache, untouched, config);
  for (const std::vector<int>& m : r.mismatched_frames) EXPECT_TRUE(m.empty());
  for (int f = 0; f < 3; ++f)
    EXPECT_EQ(r.lanes[2].image_hashes[size_t(f)], r.lanes[0].image_hashes[size_t(f)]) << f;
}

}  // namespace bench_harness_test
}  // namespace multiray
