// The Session seam: a kernel that is not the path tracer runs through it on two devices;
// finished frames stay valid while later frames render; the camera can be changed between
// frames; the plan's quality is applied by the engine.
#include <gtest/gtest.h>

#include <cmath>

#include "balance/balancer.h"
#include "core/resample.h"
#include "device/cpu/cpu_device.h"
#include "engine/refinement.h"
#include "engine/session.h"
#include "scene/builders.h"

namespace multiray {
namespace session_test {

constexpr int kW = 40, kH = 30;

// Keeps every finished frame, and its image hash taken at the moment it was handed over.
struct Keeper : FrameObserver {
  std::vector<std::shared_ptr<const FrameResult>> results;
  std::vector<uint64_t> hash_at_delivery;
  void on_frame(const std::shared_ptr<const FrameResult>& r) override {
    results.push_back(r);
    hash_at_delivery.push_back(image_hash(r->images.at(0)));
  }
};

std::vector<std::unique_ptr<balance::Balancer>> lanes(std::vector<std::string> specs) {
  std::vector<std::unique_ptr<balance::Balancer>> out;
  for (const auto& s : specs) out.push_back(balance::make_balancer(s, 2));
  return out;
}

// Distance from the camera at height `h` above the plane y = 0, looking straight down,
// to the plane through the centre of pixel (x, y): |d| / |d.y| for the pixel's ray d.
float expected_depth(int x, int y, float h, float fov_deg) {
  const float sy_scale = std::tan(0.5f * fov_deg * kPi / 180.0f);
  const float sx = ((float(x) + 0.5f) * 2.0f / kW - 1.0f) * sy_scale * kW / kH;
  const float sy = (1.0f - (float(y) + 0.5f) * 2.0f / kH) * sy_scale;
  return h * std::sqrt(1.0f + sx * sx + sy * sy);
}

TEST(Session, DepthKernelOnTwoDevicesGivesTheAnalyticDepth) {
  const Scene scene = make_lit_plane(0.5f, 1.0f);  // camera 1 above the plane, fov 60
  SceneCache cache(scene);
  CpuDevice a(cache, {}, "cpu"), b(cache, CpuDeviceOptions{.speed = 0.5}, "cpu:speed=0.5");
  RenderSettings settings;
  settings.kernel = "depth";
  // Static splits, so that each device renders a part of every frame however fast the
  // other one is.
  Session session({&a, &b}, lanes({"uniform", "static:ratios=1/2"}),
                  FrameViews(CameraRig::single(), kW, kH, {}), CameraPath::fixed(scene.cameras[0]),
                  settings);
  Keeper keep;
  ASSERT_EQ(session.run(0, 3, keep), 3);
  ASSERT_EQ(keep.results.size(), 6u);  // 3 frames x 2 lanes
  for (const auto& r : keep.results) {
    EXPECT_GT(r->record.devices[0].pixels, 0u);  // both devices took part
    EXPECT_GT(r->record.devices[1].pixels, 0u);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x)
        ASSERT_NEAR(r->images[0].at(x, y).x, expected_depth(x, y, 1.0f, 60.0f), 1e-4f)
            << x << "," << y << " lane " << r->lane << " frame " << r->frame;
  }
}

TEST(Session, FinishedFramesStayValidWhileLaterFramesRender) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  CpuDevice a(cache, {}, "cpu"), b(cache, {}, "cpu");
  Session session({&a, &b}, lanes({"hybrid"}), FrameViews(CameraRig::single(), kW, kH, {}),
                  CameraPath::orbit(scene.cameras[0], 8), RenderSettings{.spp = 1});
  Keeper keep;
  session.run(0, 4, keep);
  ASSERT_EQ(keep.results.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(image_hash(keep.results[i]->images[0]), keep.hash_at_delivery[i]) << i;
    for (size_t j = 0; j < i; ++j)
      EXPECT_NE(keep.results[i].get(), keep.results[j].get());  // separate buffers
  }
  // An observer that lets go of each frame gets the same buffer back: no copying.
  struct Forget : FrameObserver {
    std::vector<const FrameResult*> seen;
    void on_frame(const std::shared_ptr<const FrameResult>& r) override {
      seen.push_back(r.get());
    }
  } forget;
  keep.results.clear();
  session.run(4, 3, forget);
  EXPECT_EQ(forget.seen[1], forget.seen[0]);
  EXPECT_EQ(forget.seen[2], forget.seen[0]);
}

TEST(Session, CameraSetBetweenFramesTakesEffectAtTheNextFrame) {
  const Scene scene = make_lit_plane(0.5f, 1.0f);
  SceneCache cache(scene);
  CpuDevice a(cache, {}, "cpu");
  RenderSettings settings;
  settings.kernel = "depth";
  std::vector<std::unique_ptr<balance::Balancer>> one;
  one.push_back(balance::make_balancer("uniform", 1));
  Session session({&a}, std::move(one), FrameViews(CameraRig::single(), kW, kH, {}),
                  CameraPath::fixed(scene.cameras[0]), settings);
  struct SetOnFirst : Keeper {
    Session* s = nullptr;
    void on_frame(const std::shared_ptr<const FrameResult>& r) override {
      Keeper::on_frame(r);
      if (r->frame == 0) s->set_camera(Camera{{0, 2, 0}, {0, 0, 0}, {0, 0, -1}, 60.0f});
    }
  } keep;
  keep.s = &session;
  session.run(0, 2, keep);
  EXPECT_NEAR(keep.results[0]->images[0].at(kW / 2, kH / 2).x,
              expected_depth(kW / 2, kH / 2, 1, 60), 1e-4f);
  EXPECT_NEAR(keep.results[1]->images[0].at(kW / 2, kH / 2).x,
              expected_depth(kW / 2, kH / 2, 2, 60), 1e-4f);
  session.set_camera(std::nullopt);  // back to the path
  session.run(2, 1, keep);
  EXPECT_NEAR(keep.results[2]->images[0].at(0, 0).x, expected_depth(0, 0, 1, 60), 1e-4f);
}

// A Ctrl-C that arrives before run() starts (the viewer prints its address first) used to
// be forgotten, and the viewer ran on: a stop asked between runs stops the next one.
TEST(Session, StopRequestedBeforeRunIsKeptForOneRun) {
  const Scene scene = make_lit_plane(0.5f, 1.0f);
  SceneCache cache(scene);
  CpuDevice a(cache, {}, "cpu");
  std::vector<std::unique_ptr<balance::Balancer>> one;
  one.push_back(balance::make_balancer("uniform", 1));
  Session session({&a}, std::move(one), FrameViews(CameraRig::single(), kW, kH, {}),
                  CameraPath::fixed(scene.cameras[0]), RenderSettings{.spp = 1});
  Keeper keep;
  session.request_stop();
  EXPECT_EQ(session.run(0, 1000000, keep), 0);
  EXPECT_TRUE(keep.results.empty());
  EXPECT_EQ(session.run(0, 2, keep), 2) << "the request stops one run, not every later one";
}

// Plans a frame at a reduced quality, as frame-time targeting will.
class ReducedQuality : public balance::Balancer {
 public:
  ReducedQuality(double scale, double step) : inner_(balance::make_balancer("queue:tile=4", 2)) {
    q_.image_scale = scale, q_.step_scale = step;
  }
  std::string name() const override { return "reduced"; }
  balance::Plan plan(const balance::FrameShape& shape, int frame) override {
    balance::Plan p = inner_->plan(balance::scaled_shape(shape, q_.image_scale), frame);
    p.quality = q_;
    return p;
  }
  void update(const balance::FrameStats& s) override { inner_->update(s); }
  void drop_device(int i) override { inner_->drop_device(i); }

 private:
  std::unique_ptr<balance::Balancer> inner_;
  balance::Quality q_;
};

// Records what it was asked to render, then lets a CPU device render it.
class Recording : public Device {
 public:
  explicit Recording(SceneCache& c) : inner_(c, {}, "cpu") {}
  const DeviceInfo& info() const override { return inner_.info(); }
  void set_emulated_speed(double s) override { inner_.set_emulated_speed(s); }
  DeviceReport render(const FrameJob& job, WorkSource& source, int index) override {
    step_scale = job.settings.step_scale;
    width = job.views[0].width, height = job.views[0].height;
    return inner_.render(job, source, index);
  }
  float step_scale = 0;
  int width = 0, height = 0;

 private:
  CpuDevice inner_;
};

TEST(Engine, AppliesThePlansQuality) {
  const Scene scene = make_lit_plane(0.5f, 1.0f);
  SceneCache cache(scene);
  Recording a(cache), b(cache);
  RenderSettings settings;
  settings.kernel = "depth";
  Engine engine({&a, &b}, std::make_unique<ReducedQuality>(0.5, 2.0));
  ViewSetup v;
  v.camera = scene.cameras[0];
  v.width = kW, v.height = kH;
  const FrameRecord rec = engine.render_frame(0, {v}, settings);
  EXPECT_EQ(rec.quality.image_scale, 0.5);
  EXPECT_EQ(a.step_scale, 2.0f);
  EXPECT_EQ(a.width, kW / 2);
  EXPECT_EQ(a.height, kH / 2);
  EXPECT_EQ(rec.devices[0].pixels + rec.devices[1].pixels, uint64_t(kW / 2 * kH / 2));
  // The output is the half-size render enlarged bilinearly: the depth of each half-size
  // pixel's centre, interpolated at the output's pixel centres.
  const Framebuffer& img = engine.images()[0];
  ASSERT_EQ(img.width, kW);
  ASSERT_EQ(img.height, kH);
  Framebuffer half(kW / 2, kH / 2), expected(kW, kH);
  const float sy_scale = std::tan(kPi / 6);
  for (int hy = 0; hy < kH / 2; ++hy)
    for (int hx = 0; hx < kW / 2; ++hx) {
      const float sx = ((hx + 0.5f) * 2.0f / (kW / 2) - 1.0f) * sy_scale * kW / kH;
      const float sy = (1.0f - (hy + 0.5f) * 2.0f / (kH / 2)) * sy_scale;
      half.at(hx, hy).x = std::sqrt(1 + sx * sx + sy * sy);
    }
  upscale_bilinear(half, expected);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      ASSERT_NEAR(img.at(x, y).x, expected.at(x, y).x, 1e-4f) << x << "," << y;
  // Not the nearest half-size pixel: between two half-size centres the value differs.
  EXPECT_GT(std::abs(img.at(kW / 2, kH / 2).x - half.at(kW / 4, kH / 4).x), 1e-5f);
  // A plan whose items do not cover its scaled shape, or a bad quality, is refused.
  balance::Plan bad = balance::make_balancer("uniform", 1)->plan({kW, kH, 1, {}}, 0);
  bad.quality.image_scale = 0.5;
  EXPECT_NE(balance::check_plan(bad, {kW, kH, 1, {}}, 1), "");
  bad.quality.image_scale = 1.5;
  EXPECT_NE(balance::check_plan(bad, {kW, kH, 1, {}}, 1), "");
}

// Progressive sampling (Session::set_progressive): what each frame's views say of the
// sample sequence, as the devices are handed them.
struct SequenceLog : FrameObserver {
  std::vector<std::pair<uint32_t, uint32_t>> seen;  // (first_sample, seed_frame) per frame
  void before_frame(int, const FrameInput& in) override {
    seen.push_back({in.views.at(0).first_sample, in.views.at(0).seed_frame()});
  }
  void on_frame(const std::shared_ptr<const FrameResult>&) override {}
};

TEST(Session, ProgressiveFramesContinueOneSequenceUntilTheCameraOrTheSettingsChange) {
  const Scene scene = make_lit_plane(0.5f, 1.0f);
  SceneCache cache(scene);
  CpuDevice cpu(cache, {}, "cpu");
  RenderSettings settings{.spp = 2};
  settings.kernel = "depth";  // cheap: the bookkeeping is under test
  Session session({&cpu}, lanes({"uniform"}), FrameViews(CameraRig::single(), 8, 6, {}),
                  CameraPath::fixed(scene.cameras[0]), settings);
  SequenceLog log;
  session.run(0, 2, log);  // off by default: each frame its own sequence
  session.set_progressive(true);
  session.run(2, 3, log);  // a still camera: 2 samples a frame, seeded by frame 2
  Camera moved = scene.cameras[0];
  moved.eye.x += 0.25f;
  session.set_camera(moved);
  session.run(5, 2, log);  // moved: frame 5 begins again
  session.set_settings_schedule([](int frame, RenderSettings& s) { s.seed = frame >= 8 ? 1 : 0; });
  session.run(7, 3, log);  // the seed changes at frame 8: it begins again there
  const std::vector<std::pair<uint32_t, uint32_t>> expected = {
      {0, 0}, {0, 1}, {0, 2}, {2, 2}, {4, 2}, {0, 5}, {2, 5}, {4, 5}, {0, 8}, {2, 8}};
  EXPECT_EQ(log.seen, expected);
}

// Frames rendered smaller (the viewer's while the camera moves) do not lead into the
// sequence of the full-size frames after them: the first full-size frame begins one, at
// sample 0.
struct SmallFirst : FrameAdvisor {
  FrameAdvice advise(int frame, const std::vector<ViewSetup>&, const RenderSettings&) override {
    FrameAdvice a;
    a.quality.image_scale = frame < 2 ? 0.5 : 1.0;
    return a;
  }
  void measured(const FrameAdvice&, const FrameRecord&, const balance::FrameStats&) override {}
};

TEST(Session, AFrameAfterASmallerOneBeginsTheSequenceAgain) {
  const Scene scene = make_lit_plane(0.5f, 1.0f);
  SceneCache cache(scene);
  CpuDevice cpu(cache, {}, "cpu");
  RenderSettings settings{.spp = 1};
  settings.kernel = "depth";
  Session session({&cpu}, lanes({"uniform"}), FrameViews(CameraRig::single(), 8, 6, {}),
                  CameraPath::fixed(scene.cameras[0]), settings);
  session.set_progressive(true);
  session.set_advisors([](size_t) { return std::make_unique<SmallFirst>(); });
  SequenceLog log;
  session.run(0, 5, log);
  // Frames 0 and 1 are small: each frame after a small one begins again.
  const std::vector<std::pair<uint32_t, uint32_t>> expected = {
      {0, 0}, {0, 1}, {0, 2}, {1, 2}, {2, 2}};
  EXPECT_EQ(log.seen, expected);
}

// The mean of N progressive frames of S samples, as the viewer's refinement
// (engine/refinement.h) takes it, is bit for bit the render of N x S samples (it sums
// frames as the kernel sums samples, first to last, and scales once), whatever the
// devices' split; N frames that each begin their own sequence are a different, noisier
// image.
uint64_t refined_hash(const std::vector<std::shared_ptr<const FrameResult>>& frames) {
  Refinement refine(1, int(frames.size()));
  const Framebuffer* shown = nullptr;
  for (const auto& f : frames) shown = &refine.add(f->images.at(0), RefineKey{});
  EXPECT_EQ(refine.samples(), int(frames.size()));
  return image_hash(*shown);
}

TEST(Session, TheMeanOfProgressiveFramesIsOneRenderOfAllTheirSamples) {
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  CpuDevice a(cache, {}, "cpu"), b(cache, {}, "cpu");
  const auto frames = [&](bool progressive, int spp, int count) {
    Session session({&a, &b}, lanes({"static:ratios=1/2"}),
                    FrameViews(CameraRig::single(), kW, kH, {}),
                    CameraPath::fixed(scene.cameras[0]), RenderSettings{.spp = spp});
    session.set_progressive(progressive);
    Keeper keep;
    session.run(0, count, keep);
    return keep.results;
  };
  const uint64_t one_render = image_hash(frames(false, 4, 1).at(0)->images.at(0));
  EXPECT_EQ(refined_hash(frames(true, 1, 4)), one_render);
  EXPECT_NE(refined_hash(frames(false, 1, 4)), one_render);
}

// Plans like `uniform` and notes its lane's number in `log` at each plan, i.e. in the
// order the lanes render.
class OrderLog : public balance::Balancer {
 public:
  OrderLog(size_t lane, std::vector<size_t>& log)
      : lane_(lane), log_(log), inner_(balance::make_balancer("uniform", 2)) {}
  std::string name() const override { return "order-log"; }
  balance::Plan plan(const balance::FrameShape& shape, int frame) override {
    log_.push_back(lane_);
    return inner_->plan(shape, frame);
  }
  void update(const balance::FrameStats& s) override { inner_->update(s); }
  void drop_device(int i) override { inner_->drop_device(i); }

 private:
  size_t lane_;
  std::vector<size_t>& log_;
  std::unique_ptr<balance::Balancer> inner_;
};

// With rotation every lane renders first equally often (the first lane of a frame runs on
// colder caches), and the observer still gets each frame's lanes in lane order; without
// it, lane 0 is always first.
TEST(Session, RotatedLanesTakeTurnsToRenderFirstAndAreHandedOverInLaneOrder) {
  const Scene scene = make_lit_plane(0.5f, 1.0f);
  SceneCache cache(scene);
  CpuDevice a(cache, {}, "cpu"), b(cache, {}, "cpu");
  RenderSettings settings;
  settings.kernel = "depth";
  for (const bool rotate : {false, true}) {
    std::vector<size_t> log;
    std::vector<std::unique_ptr<balance::Balancer>> three;
    for (size_t k = 0; k < 3; ++k) three.push_back(std::make_unique<OrderLog>(k, log));
    Session session({&a, &b}, std::move(three), FrameViews(CameraRig::single(), kW, kH, {}),
                    CameraPath::fixed(scene.cameras[0]), settings);
    session.set_rotate_lanes(rotate, 1);
    Keeper keep;
    ASSERT_EQ(session.run(0, 6, keep), 6);
    ASSERT_EQ(log.size(), 18u);
    ASSERT_EQ(keep.results.size(), 18u);
    std::vector<int> first(3, 0);
    for (size_t f = 0; f < 6; ++f) {
      ++first[log[3 * f]];
      for (size_t k = 0; k < 3; ++k) {
        EXPECT_EQ(keep.results[3 * f + k]->lane, k) << "frame " << f;
        EXPECT_EQ(keep.results[3 * f + k]->frame, int(f));
        if (rotate) {
          EXPECT_EQ(log[3 * f + k], (f + 1 + k) % 3) << "frame " << f;
        }
      }
      // The images do not depend on the order (the same depth everywhere).
      EXPECT_EQ(image_hash(keep.results[3 * f]->images[0]),
                image_hash(keep.results[3 * f + 2]->images[0]));
    }
    const std::vector<int> expected =
        rotate ? std::vector<int>{2, 2, 2} : std::vector<int>{6, 0, 0};
    EXPECT_EQ(first, expected);
  }
}

}  // namespace session_test
}  // namespace multiray
