// Batched launches of the OpenCL device (`batch=`, kernels/batch_rects.h): how rects are
// packed into launches (host only), images bit-identical for any batch size (path tracer
// and volume raycaster, sample maps, two views), one report per item with the batch's
// time split by samples, and the option's range.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <set>

#include "core/error.h"
#include "device/device_factory.h"
#include "device/opencl/cl_runtime.h"
#include "opencl_helpers.h"
#include "opencl_volume_helpers.h"
#include "scene/builders.h"

namespace multiray {
namespace opencl_batch_test {

using testing::view_of;

bool same_bits(const Framebuffer& a, const Framebuffer& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3)) == 0;
}

// `n` full-width strips of a w x h view, their heights differing by at most one row.
std::vector<Rect> strips(int w, int h, int n) {
  std::vector<Rect> out;
  for (int k = 0; k < n; ++k) out.push_back({0, k * h / n, w, (k + 1) * h / n});
  return out;
}

struct Rendered {
  std::vector<Framebuffer> images;
  DeviceReport report;
};

// Renders `items` (of `views`) on `device` alone.
Rendered render_items(Device& device, const std::vector<ViewSetup>& views, const RenderSettings& s,
                      const std::vector<WorkItem>& items) {
  ListWorkSource source(items);
  Rendered r;
  for (const ViewSetup& v : views) r.images.emplace_back(v.width, v.height);
  FrameJob job{views, s, &r.images};
  r.report = device.render(job, source, 0);
  EXPECT_FALSE(r.report.failed) << r.report.error;
  return r;
}

std::vector<WorkItem> items_of(const std::vector<Rect>& rects, int view = 0) {
  std::vector<WorkItem> items;
  for (const Rect& r : rects) items.push_back(WorkItem{r, view});
  return items;
}

OpenClDeviceOptions with_batch(int batch, int tile = 256) {
  return OpenClDeviceOptions{.tile = tile, .batch = batch};
}

// Host only: pieces in order, each rect whole (split into tiles only when larger than a
// launch), no launch over the pixel capacity or MR_BATCH_MAX pieces, the last rect kept.
TEST(OpenClBatchPlan, PacksRectsInOrderWithinTheCapacity) {
  std::vector<Rect> rects = strips(16, 30, 30);  // 16 x 1 each
  rects.push_back({0, 0, 25, 17});               // larger than a 16 x 16 launch
  rects.push_back({3, 4, 5, 6});
  const auto launches = plan_launches(rects, 16);
  std::vector<size_t> pixels_of(rects.size(), 0);
  size_t last = 0;
  for (const auto& launch : launches) {
    ASSERT_FALSE(launch.empty());
    EXPECT_LE(launch.size(), size_t(MR_BATCH_MAX));
    size_t pixels = 0;
    for (const ClLaunchRect& p : launch) {
      EXPECT_GE(p.rect, last) << "rects in order";
      last = p.rect;
      pixels += p.pixels();
      pixels_of.at(p.rect) += p.pixels();
    }
    EXPECT_LE(pixels, 256u);
  }
  for (size_t k = 0; k < rects.size(); ++k)
    EXPECT_EQ(pixels_of[k], size_t(rects[k].area())) << "rect " << k;
  // 16 strips, 14 strips; a full 16 x 16 tile; the other 3 tiles and the 5 x 6 rect.
  EXPECT_EQ(launches.size(), 4u);
  EXPECT_EQ(plan_launches(rects, 16, 1).size(), 30u + 4u + 1u) << "one piece a launch";
  EXPECT_EQ(plan_launches(strips(4, 200, 200), 64, 1000).front().size(), size_t(MR_BATCH_MAX));
}

// The path tracer: 64 strips of a 320 x 180 frame, any batch size (and tile, so launches
// fill up on pixels, not on rects) gives the bits of one item at a time.
TEST(OpenClBatch, PathImagesAreBitIdenticalForAnyBatch) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const ViewSetup view = view_of(scene, 320, 180, 3);
  const RenderSettings s{.spp = 1, .max_bounces = 3, .seed = 5};
  const std::vector<WorkItem> items = items_of(strips(320, 180, 64));
  OpenClDevice one(rs, with_batch(1), "opencl:0:batch=1");
  const Framebuffer ref = render_items(one, {view}, s, items).images[0];
  for (const auto& [batch, tile] : {std::pair{16, 256}, {64, 256}, {16, 40}}) {
    OpenClDevice d(rs, with_batch(batch, tile), "opencl:0");
    const Rendered r = render_items(d, {view}, s, items);
    EXPECT_TRUE(same_bits(r.images[0], ref)) << "batch " << batch << " tile " << tile;
    EXPECT_EQ(r.report.items.size(), items.size());
  }
}

// Sample maps (adaptive sampling) follow each rect into its place in the batch, and
// items of two views taken together go to launches of their own view.
TEST(OpenClBatch, SampleMapsAndTwoViewsAreBitIdentical) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const int w = 64, h = 48;
  std::vector<uint8_t> map(size_t(w) * size_t(h));
  for (size_t i = 0; i < map.size(); ++i) map[i] = uint8_t((i * 7 + i / size_t(w)) % 4);
  ViewSetup a = view_of(scene, w, h, 1), b = view_of(scene, w, h, 1);
  a.spp_map = &map;
  b.view = 1;
  b.camera.eye = b.camera.eye + Vec3(0.1f, 0, 0);
  std::vector<WorkItem> items;
  for (const Rect& r : strips(w, h, 24)) {
    items.push_back(WorkItem{r, 0});
    if (items.size() % 3 == 0) items.push_back(WorkItem{r, 1});
  }
  const RenderSettings s{.spp = 2, .max_bounces = 3, .seed = 9};
  OpenClDevice one(rs, with_batch(1), "opencl:0:batch=1");
  OpenClDevice many(rs, with_batch(16), "opencl:0:batch=16");
  const Rendered x = render_items(one, {a, b}, s, items);
  const Rendered y = render_items(many, {a, b}, s, items);
  EXPECT_TRUE(same_bits(x.images[0], y.images[0])) << "view 0, sample map";
  EXPECT_TRUE(same_bits(x.images[1], y.images[1])) << "view 1";
  EXPECT_EQ(x.report.samples, y.report.samples);
  EXPECT_EQ(x.report.rays, y.report.rays);
}

// The volume raycaster shares the launch path: the same bits for any batch.
TEST(OpenClBatch, VolumeImagesAreBitIdenticalForAnyBatch) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  auto c = testing::ball_case();
  const ViewSetup view = view_of(c->scene, 96, 64, 2);
  const RenderSettings s = testing::volume_settings(*c, 2, 11);
  const std::vector<WorkItem> items = items_of(strips(96, 64, 64));
  OpenClDevice one(*c->cache, with_batch(1), "opencl:0:batch=1");
  OpenClDevice many(*c->cache, with_batch(16), "opencl:0:batch=16");
  const Rendered x = render_items(one, {view}, s, items);
  const Rendered y = render_items(many, {view}, s, items);
  EXPECT_TRUE(same_bits(x.images[0], y.images[0]));
  EXPECT_EQ(x.report.items.size(), y.report.items.size());
}

// One ItemReport per item, each with its own samples (summing to the frame's); a batch's
// time is split over its items by samples, so the items' times add up to no more than
// the frame's and items of one batch share one time per sample.
TEST(OpenClBatch, ReportsEachItemWithItsShareOfTheBatchTime) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const int w = 160, h = 90;
  const ViewSetup view = view_of(scene, w, h);
  const RenderSettings s{.spp = 2, .max_bounces = 2};
  const std::vector<WorkItem> items = items_of(strips(w, h, 64));  // 1 or 2 rows each
  OpenClDevice d(rs, with_batch(16), "opencl:0:batch=16");
  const DeviceReport r = render_items(d, {view}, s, items).report;
  ASSERT_EQ(r.items.size(), items.size());
  std::set<uint32_t> ids;
  double samples = 0, time = 0;
  std::vector<double> per_sample;
  for (const ItemReport& it : r.items) {
    ids.insert(it.id);
    EXPECT_EQ(it.samples, double(it.item.rect.area() * s.spp)) << it.id;
    EXPECT_EQ(it.item.rect, items.at(it.id).rect);
    samples += it.samples, time += it.time_ms;
    per_sample.push_back(it.time_ms / it.samples);
  }
  EXPECT_EQ(ids.size(), items.size());
  EXPECT_EQ(samples, double(w * h * s.spp));
  EXPECT_EQ(r.samples, uint64_t(w * h * s.spp));
  EXPECT_LE(time, r.time_ms * (1 + 1e-9));
  // 64 items in batches of 16 (all fit one launch): 4 distinct times per sample at most.
  std::sort(per_sample.begin(), per_sample.end());
  size_t distinct = 0;
  for (size_t k = 0; k < per_sample.size(); ++k)
    if (k == 0 || per_sample[k] > per_sample[k - 1] * (1 + 1e-9)) ++distinct;
  EXPECT_LE(distinct, 4u);
}

// A source whose items are not the device's own (a shared queue, other devices' lists):
// the device takes them one at a time, whatever `batch` says.
class SharedOnlySource : public WorkSource {
 public:
  explicit SharedOnlySource(std::vector<WorkItem> items) : list_(std::move(items)) {}
  bool next(int device, uint32_t& id) override { return list_.next(device, id); }
  size_t next(int device, size_t max, std::vector<uint32_t>& ids) override {
    ++batch_requests;
    return WorkSource::next(device, max, ids);
  }
  size_t pending(int) const override { return 0; }
  const WorkItem& item(uint32_t id) const override { return list_.item(id); }
  int batch_requests = 0;

 private:
  ListWorkSource list_;
};

TEST(OpenClBatch, BatchesOnlyItemsAlreadyItsOwn) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const ViewSetup view = view_of(scene, 64, 32);
  const RenderSettings s{.spp = 1, .max_bounces = 1};
  const std::vector<WorkItem> items = items_of(strips(64, 32, 16));
  OpenClDevice d(rs, with_batch(16), "opencl:0:batch=16");
  SharedOnlySource shared(items);
  std::vector<Framebuffer> images{Framebuffer(64, 32)};
  const FrameJob job{{view}, s, &images};
  const DeviceReport r = d.render(job, shared, 0);
  ASSERT_FALSE(r.failed) << r.error;
  EXPECT_EQ(r.items.size(), items.size());
  EXPECT_EQ(shared.batch_requests, 0);  // never more than one shared item at a time
  // Its own list (ListWorkSource: all pending) is taken in batches: 16 strips, one launch.
  EXPECT_EQ(render_items(d, {view}, s, items).report.items.size(), items.size());
}

// batch= is checked where it is parsed and where the device is made.
TEST(OpenClBatch, OptionRangeIsEnforced) {
  EXPECT_NO_THROW(parse_device_specs("opencl:0:batch=1"));
  EXPECT_NO_THROW(parse_device_specs("opencl:0:batch=64"));
  EXPECT_THROW(parse_device_specs("opencl:0:batch=0"), InputError);
  EXPECT_THROW(parse_device_specs("opencl:0:batch=65"), InputError);
  EXPECT_THROW(parse_device_specs("opencl:0:batch=2.5"), InputError);
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  EXPECT_THROW(OpenClDevice(rs, with_batch(0), "opencl:0"), InputError);
  EXPECT_THROW(OpenClDevice(rs, with_batch(MR_BATCH_MAX + 1), "opencl:0"), InputError);
}

}  // namespace opencl_batch_test
}  // namespace multiray
