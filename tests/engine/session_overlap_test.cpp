// Session::set_denoise_overlap: frame N's denoiser runs beside frame N+1's rendering and
// the observer is handed frame N after frame N+1 began; the images, the frames and their
// order are those of the session without it (a moving camera, svgf's history, method
// switches, frames rendered smaller), and a stop still hands over every frame it counts.
// Also BackgroundJob, the thread the filter runs on.
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "balance/balancer.h"
#include "device/cpu/cpu_device.h"
#include "engine/background_job.h"
#include "engine/frame_advisor.h"
#include "engine/half_scale_advisor.h"
#include "engine/session.h"
#include "scene/builders.h"

namespace multiray {
namespace session_overlap_test {

constexpr int kW = 24, kH = 16;

// Keeps every frame's hashes and what the session told it, in order ("b3": before frame
// 3, "f3": frame 3 handed over); asks for the methods of `plan` and stops after `stop_at`.
struct Recorder : FrameObserver {
  Session* session = nullptr;
  std::map<int, DenoiseMethod> plan;
  int stop_at = -1;
  std::vector<std::string> events;
  std::vector<int> frames;
  std::vector<uint64_t> raw, denoised;
  void before_frame(int frame, const FrameInput&) override {
    events.push_back("b" + std::to_string(frame));
    if (plan.count(frame)) session->set_denoise(plan[frame]);
  }
  void on_frame(const std::shared_ptr<const FrameResult>& r) override {
    events.push_back("f" + std::to_string(r->frame));
    frames.push_back(r->frame);
    raw.push_back(image_hash(r->images.at(0)));
    denoised.push_back(r->denoised.empty() ? 0 : image_hash(r->denoised.at(0)));
    if (r->frame == stop_at) session->request_stop();
  }
};

using testing::HalfScale;

struct RunSpec {
  bool overlap = false;
  int lanes = 1;
  bool half_scale = false;
  std::map<int, DenoiseMethod> plan;  // empty: svgf throughout
  int frames = 6;
  int stop_at = -1;
};

// A box orbit of `s.frames` frames, 1 spp, two CPU threads; returns what the observer saw
// and, in *done, what run() returned.
Recorder run(const RunSpec& s, int* done = nullptr) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  CpuDevice cpu(cache, CpuDeviceOptions{.threads = 2}, "cpu");
  RenderSettings settings{.spp = 1, .max_bounces = 2};
  settings.feature_buffers = true;
  std::vector<std::unique_ptr<balance::Balancer>> lanes;
  for (int l = 0; l < s.lanes; ++l) lanes.push_back(balance::make_balancer("uniform", 1));
  Session session({&cpu}, std::move(lanes), FrameViews(CameraRig::single(), kW, kH, {}),
                  CameraPath::orbit(scene.cameras[0], 48.0f), settings);
  if (s.half_scale) session.set_advisors([](size_t) { return std::make_unique<HalfScale>(); });
  session.set_denoise(DenoiseMethod::svgf);
  session.set_denoise_overlap(s.overlap);
  Recorder r;
  r.session = &session;
  r.plan = s.plan;
  r.stop_at = s.stop_at;
  const int n = session.run(0, s.frames, r);
  if (done) *done = n;
  return r;
}

void expect_same_frames(const Recorder& a, const Recorder& b) {
  EXPECT_EQ(a.frames, b.frames);
  EXPECT_EQ(a.raw, b.raw);
  EXPECT_EQ(a.denoised, b.denoised);
}

TEST(SessionOverlap, FrameNIsHandedOverAfterFrameNPlus1Began) {
  RunSpec s;
  s.frames = 3;
  EXPECT_EQ(run(s).events, (std::vector<std::string>{"b0", "f0", "b1", "f1", "b2", "f2"}));
  s.overlap = true;
  EXPECT_EQ(run(s).events, (std::vector<std::string>{"b0", "b1", "f0", "b2", "f1", "f2"}));
}

TEST(SessionOverlap, TheSameImagesInTheSameOrderAsWithout) {
  RunSpec s;
  const Recorder plain = run(s);
  s.overlap = true;
  const Recorder overlapped = run(s);
  ASSERT_EQ(overlapped.frames.size(), 6u);
  expect_same_frames(plain, overlapped);
  // A moving camera: six different images.
  EXPECT_NE(overlapped.denoised[4], overlapped.denoised[5]);
}

TEST(SessionOverlap, MethodSwitchesGiveTheSameImagesAsWithout) {
  using M = DenoiseMethod;
  RunSpec s;
  s.plan = {{0, M::svgf}, {1, M::svgf}, {2, M::atrous}, {3, M::none}, {4, M::svgf}, {5, M::svgf}};
  const Recorder plain = run(s);
  s.overlap = true;
  const Recorder overlapped = run(s);
  expect_same_frames(plain, overlapped);
  EXPECT_EQ(overlapped.denoised[3], 0u);  // frame 3 not denoised
  EXPECT_NE(overlapped.denoised[4], 0u);
}

TEST(SessionOverlap, FramesRenderedSmallerGiveTheSameImagesAsWithout) {
  RunSpec s;
  s.half_scale = true;
  const Recorder plain = run(s);
  s.overlap = true;
  expect_same_frames(plain, run(s));
}

TEST(SessionOverlap, AStopHandsOverEveryFrameItCounts) {
  RunSpec s;
  s.overlap = true;
  s.stop_at = 1;
  int done = 0;
  const Recorder r = run(s, &done);
  // Frame 1 is handed over after frame 2 began: frame 2 completes and is handed over too.
  EXPECT_EQ(done, 3);
  EXPECT_EQ(r.frames, (std::vector<int>{0, 1, 2}));
}

TEST(SessionOverlap, SeveralLanesDoNotOverlap) {
  RunSpec s;
  s.overlap = true;
  s.lanes = 2;
  s.frames = 2;
  EXPECT_EQ(run(s).events, (std::vector<std::string>{"b0", "f0", "f0", "b1", "f1", "f1"}));
}

TEST(BackgroundJob, RunsOneJobAtATimeAndRethrowsItsError) {
  BackgroundJob job;
  std::vector<int> order;
  job.start([&] { order.push_back(1); });
  EXPECT_THROW(job.start([] {}), std::logic_error);  // the job before was not waited for
  job.wait();
  job.start([&] { order.push_back(2); });
  job.wait();
  EXPECT_EQ(order, (std::vector<int>{1, 2}));
  job.start([] { throw std::runtime_error("filter failed"); });
  EXPECT_THROW(job.wait(), std::runtime_error);
  job.wait();  // nothing runs: returns, throws nothing
  job.start([&] { order.push_back(3); });
  job.wait();
  EXPECT_EQ(order.back(), 3);
}

}  // namespace session_overlap_test
}  // namespace multiray
