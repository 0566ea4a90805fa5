// The OpenCL volume raycaster on its own (on the ball of opencl_volume_helpers.h): only
// the volume kernel is built for a volume scene, images are bit-identical for any split,
// launch shape and device count, empty-space skipping never changes them, a new style is
// uploaded when the shared_ptr changes, and impossible jobs get one clear line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "core/error.h"
#include "device/opencl/opencl_volume.h"
#include "opencl_helpers.h"
#include "opencl_volume_helpers.h"
#include "scene/builders.h"

namespace multiray {
namespace opencl_volume_test {

using testing::ball_case;
using testing::render_on;
using testing::render_whole;
using testing::view_of;
using testing::volume_settings;

constexpr int kW = 41, kH = 29;

bool same_bits(const Framebuffer& a, const Framebuffer& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3)) == 0;
}

std::vector<Rect> tiles_of(int w, int h, int tw, int th) {
  std::vector<Rect> out;
  for (int y = 0; y < h; y += th)
    for (int x = 0; x < w; x += tw)
      out.push_back({x, y, std::min(w, x + tw), std::min(h, y + th)});
  return out;
}

TEST(OpenClVolume, BuildsOnlyTheVolumeKernelForAVolume) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  auto c = ball_case();
  OpenClDevice device(*c->cache, {}, "opencl:0");
  EXPECT_EQ(device.info().caps.kernels, std::vector<std::string>{"volume"});
  EXPECT_EQ(device.info().caps.representation, "opencl-volume");
  const std::vector<std::string> built = c->cache->built();
  EXPECT_EQ(std::count(built.begin(), built.end(), "embree"), 0) << "no BVH for a volume";
  const auto& caps = OpenClDevice::capabilities().kernels;
  EXPECT_NE(std::find(caps.begin(), caps.end(), "volume"), caps.end());
}

// One region or many, one launch or many small ones, any work-group size, one device or
// two pulling concurrently: the same bits, for one sample (pixel centres) and for four
// (jittered by the keyed RNG).
TEST(OpenClVolume, ImageIsBitIdenticalForAnySplit) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  auto c = ball_case();
  OpenClDevice a(*c->cache, {}, "opencl:0");
  OpenClDevice b(*c->cache, OpenClDeviceOptions{.tile = 4, .work_group = 1},
                 "opencl:0:tile=4:wg=1");
  const ViewSetup view = view_of(c->scene, kW, kH, 2);
  for (int spp : {1, 4}) {
    const RenderSettings s = volume_settings(*c, spp, 11);
    const Framebuffer whole = render_whole(a, view, s);
    float sum = 0;
    for (const Vec3& p : whole.pixels) sum += p.x;
    EXPECT_GT(sum, 10.0f) << "the ball is in view";
    EXPECT_TRUE(same_bits(render_on({&a}, view, s, tiles_of(kW, kH, 7, 5)), whole)) << spp;
    EXPECT_TRUE(same_bits(render_whole(b, view, s), whole)) << "tile=4 wg=1, spp " << spp;
    EXPECT_TRUE(same_bits(render_on({&a, &b}, view, s, tiles_of(kW, kH, 9, 4)), whole))
        << "two devices, spp " << spp;
  }
}

// Skipping empty blocks drops only samples of opacity 0 (same bits), and the device
// reports one ray per sample; a coarser step (step_scale) changes the image only slightly.
TEST(OpenClVolume, SkippingIsExactAndStatsCountRays) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  auto c = ball_case();
  OpenClDevice device(*c->cache, {}, "opencl:0");
  const ViewSetup view = view_of(c->scene, kW, kH);
  RenderSettings s = volume_settings(*c, 2);
  std::vector<Framebuffer> out{Framebuffer(kW, kH)};
  FrameJob job{{view}, s, &out};
  ListWorkSource whole({WorkItem{{0, 0, kW, kH}, 0}});
  const DeviceReport r = device.render(job, whole, 0);
  ASSERT_FALSE(r.failed) << r.error;
  EXPECT_EQ(r.samples, uint64_t(2 * kW * kH));
  EXPECT_EQ(r.rays, r.samples);

  auto unskipped = std::make_shared<VolumeStyle>(*c->style);
  unskipped->skip_empty = false;
  s.volume_style = unskipped;
  EXPECT_TRUE(same_bits(render_whole(device, view, s), out[0]));

  s.volume_style = c->style;
  s.step_scale = 2;
  const testing::ImageDiff d = testing::diff(render_whole(device, view, s), out[0]);
  EXPECT_GT(d.max, 0.0) << "step_scale reached the kernel";
  EXPECT_LT(d.mean, 0.02);
}

// A new style (another shared_ptr) is uploaded before the next launch; going back to the
// first gives its image again, bit for bit.
TEST(OpenClVolume, ChangedStyleIsUploaded) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  auto c = ball_case();
  OpenClDevice device(*c->cache, {}, "opencl:0");
  const ViewSetup view = view_of(c->scene, kW, kH);
  const Framebuffer first = render_whole(device, view, volume_settings(*c));
  TransferFunction blue;
  blue.name = "blue";
  blue.points = {{0, Vec3(0.0f), 0}, {100, Vec3(0.0f), 0}, {200, Vec3(0.1f, 0.3f, 1), 0.6f}};
  RenderSettings s = volume_settings(*c);
  s.volume_style = make_volume_style(volume_scene(*c->cache), blue, 0.5f);
  const Framebuffer second = render_whole(device, view, s);
  float red = 0, blue_sum = 0;
  for (const Vec3& p : second.pixels) red += p.x, blue_sum += p.z;
  EXPECT_GT(blue_sum, 2 * red) << "the blue table is in use";
  EXPECT_TRUE(same_bits(render_whole(device, view, volume_settings(*c)), first));
}

TEST(OpenClVolume, RefusesWhatItCannotRender) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  auto c = ball_case();
  OpenClDevice device(*c->cache, {}, "opencl:0");
  std::vector<Framebuffer> out{Framebuffer(8, 8)};
  ListWorkSource source({WorkItem{{0, 0, 8, 8}, 0}});
  FrameJob path_job{{view_of(c->scene, 8, 8)}, RenderSettings{.kernel = "path"}, &out};
  DeviceReport r = device.render(path_job, source, 0);
  EXPECT_TRUE(r.failed);
  EXPECT_NE(r.error.find("cannot run the path kernel (it runs volume)"), std::string::npos)
      << r.error;
  FrameJob no_style{{view_of(c->scene, 8, 8)}, RenderSettings{.kernel = "volume"}, &out};
  r = device.render(no_style, source, 0);
  EXPECT_TRUE(r.failed);
  EXPECT_NE(r.error.find("needs a transfer function"), std::string::npos) << r.error;

  // A mesh device builds no volume kernel.
  const Scene box = make_cornell_box();
  SceneCache rs(box);
  OpenClDevice mesh(rs, {}, "opencl:0");
  EXPECT_EQ(mesh.info().caps.kernels, std::vector<std::string>{"path"});
  EXPECT_EQ(mesh.info().caps.representation, "opencl-flat-bvh");
  FrameJob volume_job{{view_of(box, 8, 8)}, volume_settings(*c), &out};
  ListWorkSource other({WorkItem{{0, 0, 8, 8}, 0}});
  r = mesh.render(volume_job, other, 0);
  EXPECT_TRUE(r.failed);
  EXPECT_NE(r.error.find("cannot run the volume kernel (it runs path)"), std::string::npos)
      << r.error;
}

// The memory check: the values must fit one buffer and everything the global memory.
TEST(OpenClVolume, MemoryCheckSaysWhatIsNeeded) {
  auto c = ball_case();
  const ClVolumeMemory need = cl_volume_memory(volume_scene(*c->cache), 256);
  EXPECT_EQ(need.values, uint64_t(48 * 40 * 36) * 4);
  EXPECT_GT(need.total, need.values);
  EXPECT_EQ(cl_volume_memory_problem(need, need.values, need.total), "");
  const std::string too_big = cl_volume_memory_problem(need, need.values - 1, need.total);
  EXPECT_NE(too_big.find("the volume needs 2 MB of device memory (1 MB of values in one buffer)"),
            std::string::npos)
      << too_big;
  EXPECT_EQ(too_big.find('\n'), std::string::npos);
  EXPECT_NE(cl_volume_memory_problem(need, need.values, need.total - 1), "");
}

}  // namespace opencl_volume_test
}  // namespace multiray
