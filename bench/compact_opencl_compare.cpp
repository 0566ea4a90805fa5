#include "compact_opencl_compare.h"

#include <algorithm>
#include <stdexcept>

#include "core/image_metrics.h"

#ifdef MULTIRAY_HAS_OPENCL
#include "device/opencl/opencl_device.h"
#include "device/opencl/opencl_platform.h"
#include "device/work_list.h"
#endif

namespace multiray {

namespace {

[[maybe_unused]] double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

#ifdef MULTIRAY_HAS_OPENCL
// One whole frame on `device`; returns its busy time (ms, measured by the device).
double render_frame(Device& device, const ViewSetup& view, const RenderSettings& settings,
                    Framebuffer& out) {
  ListWorkSource source({WorkItem{{0, 0, view.width, view.height}, 0}});
  std::vector<Framebuffer> outputs{Framebuffer(view.width, view.height)};
  const FrameJob job{{view}, settings, &outputs};
  const DeviceReport r = device.render(job, source, 0);
  if (r.failed) throw std::runtime_error(r.error);
  out = outputs[0];
  return r.busy_ms;
}

nlohmann::json opencl_comparison(const Scene& scene, const ViewSetup& view,
                                 const RenderSettings& settings, int reps) {
  if (list_opencl_devices().empty()) return {{"skipped", "no OpenCL device"}};
  SceneCache cache(scene);
  OpenClDevice flat(cache, {}, "opencl:0");
  OpenClDevice compact(cache, {.compact = true}, "opencl:0:compact=1");
  Framebuffer a(view.width, view.height), b(view.width, view.height);
  std::vector<double> tf, tc;
  for (int r = 0; r < reps; ++r) {
    tf.push_back(render_frame(flat, view, settings, a));
    tc.push_back(render_frame(compact, view, settings, b));
  }
  return {{"device", flat.info().name},
          {"scene_bytes",
           {{"flat", flat.info().scene_bytes}, {"compact", compact.info().scene_bytes}}},
          {"scene_ratio", double(flat.info().scene_bytes) / double(compact.info().scene_bytes)},
          {"busy_ms", {{"flat", median(tf)}, {"compact", median(tc)}}},
          {"render_time_increase", median(tc) / median(tf) - 1.0},
          {"psnr_db", image_error(b, a).psnr_db}};
}
#else
nlohmann::json opencl_comparison(const Scene&, const ViewSetup&, const RenderSettings&, int) {
  return {{"skipped", "built without OpenCL"}};
}
#endif

}  // namespace multiray
