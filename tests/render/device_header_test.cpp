// The Device interface is free of Embree and OpenCL (DESIGN.md: "a header free of Embree
// and OpenCL"): every layer above device/ sees device/device.h, and a renderer that links
// only the engine must not need either SDK's headers. This translation unit includes the
// header first and fails to compile if it pulled either in, whatever the include path
// holds (both SDKs sit in /usr/include here, so a missing -I would prove nothing).
#include "device/device.h"

// embree3/rtcore_config.h (included by rtcore.h) defines the version macros.
#if defined(RTC_VERSION_MAJOR) || defined(RTC_VERSION)
#error "device/device.h includes Embree (embree3/rtcore*.h)"
#endif
// CL/cl_platform.h's include guard; every OpenCL header (cl.h, opencl.hpp) includes it.
#if defined(__CL_PLATFORM_H) || defined(CL_HPP_)
#error "device/device.h includes OpenCL (CL/cl_platform.h)"
#endif

#include <gtest/gtest.h>

namespace multiray {
namespace {

// The check above is the test; this only gives ctest something to run that uses the types.
TEST(DeviceHeader, IsFreeOfEmbreeAndOpenCl) {
  FrameJob job;
  job.views.push_back(ViewSetup{});
  EXPECT_EQ(job.settings.kernel, "path");
  EXPECT_EQ(job.views[0].samples_at(0, job.settings), job.settings.spp);
}

}  // namespace
}  // namespace multiray
