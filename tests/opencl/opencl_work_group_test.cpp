// The work-group size is fitted to each kernel (ClRuntime::build_kernel): a driver may
// allow a compiled kernel fewer work-items per group than the device (Mesa's rusticl on
// llvmpipe: 32 of 1024), and the default 64 must just work there. A `wg=` asked for above
// the limit is fitted too, with a note, never refused; no size changes a pixel.
#include <gtest/gtest.h>

#include <cstring>

#include "device/opencl/cl_runtime.h"
#include "opencl_helpers.h"
#include "scene/builders.h"

namespace multiray {
namespace opencl_work_group_test {

using testing::render_whole;
using testing::view_of;

bool same_bits(const Framebuffer& a, const Framebuffer& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Vec3)) == 0;
}

TEST(OpenClWorkGroup, FitIsTheLargestMultipleOfTheSimdWidthElseAPowerOfTwo) {
  EXPECT_EQ(fit_work_group(64, 1024, 32), 64u);  // fits: unchanged
  EXPECT_EQ(fit_work_group(64, 64, 32), 64u);
  EXPECT_EQ(fit_work_group(64, 32, 8), 32u);    // rusticl on llvmpipe
  EXPECT_EQ(fit_work_group(256, 96, 32), 96u);  // a multiple of the SIMD width
  EXPECT_EQ(fit_work_group(256, 100, 32), 96u);
  EXPECT_EQ(fit_work_group(256, 100, 1), 64u);    // no useful multiple: a power of two
  EXPECT_EQ(fit_work_group(256, 100, 128), 64u);  // the multiple is above the limit
  EXPECT_EQ(fit_work_group(7, 5, 1), 4u);
  EXPECT_EQ(fit_work_group(7, 1, 1), 1u);
}

// wg=4096 (the largest the option takes) on whatever device 0 is: set up and rendered at
// the size each kernel allows, noted when that is smaller, the same pixels as the default.
TEST(OpenClWorkGroup, ALargeWgIsFittedToEachKernelNotedAndChangesNoPixel) {
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_cornell_box();
  SceneCache rs(scene);
  const ViewSetup view = view_of(scene, 21, 13, 1);
  const RenderSettings s{.spp = 2, .max_bounces = 4, .seed = 3};
  OpenClDevice fitted(rs, {.work_group = 4096, .work_group_given = true}, "opencl:0:wg=4096");
  const size_t wg = fitted.work_group_size("path");
  ASSERT_GE(wg, 1u);
  // Within what the compiled kernel allows (rusticl 22.3 launched 64 where it allows 32
  // without an error, so only this sees a size left unfitted).
  ASSERT_LE(wg, fitted.work_group_limit("path"));
  std::vector<std::string> notes;  // about the work group (llvmpipe adds another)
  for (const std::string& n : fitted.info().notes)
    if (n.find("kernel allows") != std::string::npos) notes.push_back(n);
  if (wg < 4096) {
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("wg=4096"), std::string::npos) << notes[0];
    EXPECT_NE(notes[0].find("wg=" + std::to_string(wg)), std::string::npos) << notes[0];
    EXPECT_EQ(notes[0].find('\n'), std::string::npos) << "one line";
  } else {
    EXPECT_TRUE(notes.empty());
  }
  OpenClDevice by_default(rs, {}, "opencl:0");
  for (const std::string& n : by_default.info().notes)
    EXPECT_EQ(n.find("kernel allows"), std::string::npos)
        << "the default is fitted silently: " << n;
  EXPECT_LE(by_default.work_group_size("path"), 64u);
  EXPECT_LE(by_default.work_group_size("path"), by_default.work_group_limit("path"));
  EXPECT_TRUE(same_bits(render_whole(fitted, view, s), render_whole(by_default, view, s)));
}

}  // namespace opencl_work_group_test
}  // namespace multiray
