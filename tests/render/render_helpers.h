// Rendering a scene on CPU devices in tests, without the engine.
#pragma once

#include <memory>
#include <thread>
#include <vector>

#include "device/cpu/cpu_device.h"
#include "device/work_list.h"
#include "render/path_tracer.h"

namespace multiray::testing {

// Renders `regions` of one view on `device_count` CPU devices running concurrently
// (devices pull regions from one shared list); `compact`: on the compact scene.
inline Framebuffer render_regions(const Scene& scene, int w, int h, const RenderSettings& settings,
                                  const std::vector<Rect>& regions, int device_count = 1,
                                  int threads = 1, int frame = 0, bool compact = false) {
  SceneCache rs(scene);
  std::vector<std::unique_ptr<CpuDevice>> devices;
  for (int i = 0; i < device_count; ++i)
    devices.push_back(std::make_unique<CpuDevice>(
        rs, CpuDeviceOptions{.threads = threads, .compact = compact}, "cpu"));
  std::vector<WorkItem> units;
  for (const Rect& r : regions) units.push_back(WorkItem{r, 0});
  ListWorkSource source(units);
  std::vector<Framebuffer> out{Framebuffer(w, h)};
  if (settings.catcher_axis >= 0) out[0].alpha.resize(out[0].pixels.size());  // as the engine does
  if (settings.feature_buffers) out[0].features.resize(w, h);
  ViewSetup view;
  view.camera = scene.cameras.at(0);
  view.width = w, view.height = h, view.frame = uint32_t(frame);
  FrameJob job{{view}, settings, &out};
  std::vector<std::thread> threads_;
  for (int i = 0; i < device_count; ++i)
    threads_.emplace_back([&, i] { devices[size_t(i)]->render(job, source, i); });
  for (auto& t : threads_) t.join();
  return out[0];
}

}  // namespace multiray::testing
