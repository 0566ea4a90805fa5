// Shared by the OpenCL tests: skipping without a device, rendering on any devices without
// the engine, and per-pixel statistics over independent renders for z-tests.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "device/cpu/cpu_device.h"
#include "device/opencl/opencl_device.h"
#include "device/opencl/opencl_platform.h"
#include "device/work_list.h"

namespace multiray::testing {

// MULTIRAY_TEST_OPENCL_ICD=FILE runs these tests on the implementation of that ICD file
// alone (tests/opencl/CMakeLists.txt registers a run on Mesa's rusticl): set before main,
// so before the ICD loader reads it, and inherited by the multiray processes tests start.
// rusticl lists llvmpipe only when RUSTICL_ENABLE names it; LP_NUM_THREADS=1 keeps it to
// one thread beside the other tests (neither changes another implementation or the CPU).
inline const std::string kTestOpenClIcd = [] {
  const char* icd = std::getenv("MULTIRAY_TEST_OPENCL_ICD");
  if (!icd || !*icd) return std::string();
  setenv("OCL_ICD_VENDORS", icd, 1);
  setenv("RUSTICL_ENABLE", "llvmpipe", 0);
  setenv("LP_NUM_THREADS", "1", 0);
  return std::string(icd);
}();

#define MULTIRAY_SKIP_WITHOUT_OPENCL()                                                       \
  if (list_opencl_devices().empty())                                                         \
  GTEST_SKIP() << (::multiray::testing::kTestOpenClIcd.empty()                               \
                       ? std::string("no OpenCL device on this machine (install "            \
                                     "pocl-opencl-icd to run the OpenCL tests)")             \
                       : "no OpenCL device through " + ::multiray::testing::kTestOpenClIcd + \
                             " (this run of the OpenCL tests is for that implementation; "   \
                             "install it, e.g. mesa-opencl-icd for rusticl)")

inline ViewSetup view_of(const Scene& scene, int w, int h, int frame = 0) {
  ViewSetup v;
  v.camera = scene.cameras.at(0);
  v.width = w, v.height = h, v.frame = uint32_t(frame);
  return v;
}

// Renders `regions` of one view with `devices` running concurrently, each pulling from
// one shared list. Fails the test when a device reports a failure.
inline Framebuffer render_on(const std::vector<Device*>& devices, const ViewSetup& view,
                             const RenderSettings& settings, const std::vector<Rect>& regions) {
  std::vector<WorkItem> units;
  for (const Rect& r : regions) units.push_back(WorkItem{r, 0});
  ListWorkSource source(units);
  std::vector<Framebuffer> out{Framebuffer(view.width, view.height)};
  if (settings.feature_buffers) out[0].features.resize(view.width, view.height);  // as the engine
  FrameJob job{{view}, settings, &out};
  std::vector<DeviceReport> reports(devices.size());
  std::vector<std::thread> threads;
  for (size_t i = 0; i < devices.size(); ++i)
    threads.emplace_back([&, i] { reports[i] = devices[i]->render(job, source, int(i)); });
  for (auto& t : threads) t.join();
  for (const DeviceReport& r : reports) EXPECT_FALSE(r.failed) << r.error;
  return out[0];
}

inline Framebuffer render_whole(Device& device, const ViewSetup& view, const RenderSettings& s) {
  return render_on({&device}, view, s, {{0, 0, view.width, view.height}});
}

// Per pixel and channel: mean and sample variance of independent estimates (Welford).
struct PixelStats {
  int n = 0;
  std::vector<double> mean, m2;
  void add(const Framebuffer& fb) {
    if (mean.empty()) mean.assign(fb.pixels.size() * 3, 0.0), m2.assign(mean.size(), 0.0);
    ++n;
    for (size_t i = 0; i < fb.pixels.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        const double x = fb.pixels[i][c], d = x - mean[3 * i + size_t(c)];
        mean[3 * i + size_t(c)] += d / n;
        m2[3 * i + size_t(c)] += d * (x - mean[3 * i + size_t(c)]);
      }
  }
  double var_of_mean(size_t k) const { return m2[k] / double(n - 1) / double(n); }
};

// Two-sample z statistics (Welch) of every pixel channel. A channel where both samples
// have zero variance gets z = 0 if the means agree to 1e-5 (relative) and +inf if not.
inline std::vector<double> z_scores(const PixelStats& a, const PixelStats& b) {
  std::vector<double> z(a.mean.size());
  for (size_t k = 0; k < z.size(); ++k) {
    const double diff = a.mean[k] - b.mean[k], se = std::sqrt(a.var_of_mean(k) + b.var_of_mean(k));
    if (se > 0) {
      z[k] = diff / se;
    } else {
      z[k] = std::abs(diff) <= 1e-5 * std::max(1.0, std::abs(a.mean[k])) ? 0.0 : INFINITY;
    }
  }
  return z;
}

}  // namespace multiray::testing
