// The OpenCL kernel registry (device/opencl/opencl_kernels.h) against the CPU's
// (render/kernel.h): one name means one kernel on every backend, the devices' capabilities
// come from the registries, and a kernel name nobody registered is refused in one line.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "device/device_factory.h"
#include "device/opencl/opencl_kernels.h"
#include "opencl_helpers.h"
#include "render/kernel.h"
#include "scene/builders.h"

namespace multiray {
namespace {

// --integrator names a CPU kernel (the CLI checks it against cpu_kernels()), so every
// OpenCL kernel must be the CPU kernel of its name: same input, no more point sampling.
TEST(OpenClKernels, EveryNameIsACpuKernelWithTheSameInput) {
  ASSERT_FALSE(opencl_kernels().empty());
  for (const ClKernelEntry& e : opencl_kernels()) {
    const KernelEntry* cpu = find_cpu_kernel(e.name);
    ASSERT_NE(cpu, nullptr) << "OpenCL kernel '" << e.name << "' is no CPU kernel";
    EXPECT_EQ(int(e.input), int(cpu->input)) << e.name;
    EXPECT_TRUE(cpu->point_samples || !e.point_samples) << e.name;
    EXPECT_NE(e.make, nullptr) << e.name;
    EXPECT_FALSE(e.help.empty()) << e.name;
    EXPECT_EQ(find_opencl_kernel(e.name), &e);
  }
}

std::vector<std::string> names_of(const auto& registry) {
  std::vector<std::string> names;
  for (const auto& e : registry) names.push_back(e.name);
  return names;
}

TEST(OpenClKernels, CapabilitiesComeFromTheRegistries) {
  EXPECT_EQ(backend_capabilities("opencl").kernels, names_of(opencl_kernels()));
  EXPECT_EQ(backend_capabilities("cpu").kernels, names_of(cpu_kernels()));
  // No OpenCL kernel renders point samples, so the backend cannot do foveated sampling.
  const std::vector<std::string> cl_sampling = backend_capabilities("opencl").sampling;
  EXPECT_EQ(cl_sampling, sampling_modes(false));
  EXPECT_EQ(backend_capabilities("cpu").sampling, sampling_modes(true));
}

TEST(OpenClKernels, UnknownKernelIsRefusedInOneLine) {
  EXPECT_EQ(find_opencl_kernel("nosuch"), nullptr);
  DeviceInfo info;
  info.spec = "opencl";
  info.caps = backend_capabilities("opencl");
  const std::string why = unsupported_job(info, "nosuch", "uniform");
  EXPECT_NE(why.find("nosuch"), std::string::npos) << why;
  EXPECT_EQ(why.find('\n'), std::string::npos) << why;

  // A device asked for it refuses the frame before taking work, in one line.
  MULTIRAY_SKIP_WITHOUT_OPENCL();
  const Scene scene = make_lit_plane(0.5f, 2.0f);
  SceneCache scenes(scene);
  OpenClDevice device(scenes, {}, "opencl:0");
  EXPECT_EQ(device.info().caps.kernels, std::vector<std::string>{"path"});
  ListWorkSource source({WorkItem{Rect{0, 0, 8, 8}, 0}});
  std::vector<Framebuffer> out{Framebuffer(8, 8)};
  RenderSettings settings;
  settings.kernel = "nosuch";
  const DeviceReport report =
      device.render(FrameJob{{testing::view_of(scene, 8, 8)}, settings, &out}, source, 0);
  EXPECT_TRUE(report.failed);
  EXPECT_TRUE(report.items.empty());
  EXPECT_EQ(report.error.find('\n'), std::string::npos) << report.error;
  EXPECT_NE(report.error.find("nosuch"), std::string::npos) << report.error;
}

}  // namespace
}  // namespace multiray
