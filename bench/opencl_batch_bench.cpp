// The fixed cost per item and per launch of the OpenCL device (issue 30: "fewer, cheaper
// items on devices that pay per item"; target <= 0.02 ms per item on PoCL).
//
// For each batch size B (`batch=B`, opencl_device.h) the same frame is rendered as one
// item and as N items (a grid of near-equal rects, full-width strips while N <= height),
// `reps` times each, alternately; a frame's time is the device's own report (start of
// frame to last item, steady_clock inside the device). The pixel work is the same in
// both, so the extra time is the fixed cost: per item (t_N - t_1) / (n - 1) with n the
// items made, and per launch (t_N - t_1) / (launches_N - launches_1), the launches
// counted as the device plans them (batches of min(B, items a launch holds) items; null
// when N items take no more launches than one).
// Medians over the repetitions; one JSON object per (B, N) on stdout.
//
// Usage: opencl_batch_bench [--device N] [--res WxH] [--spp N] [--bounces N] [--reps N]
//                           [--tile T] [--counts 64,256,1024] [--batches 1,16]
// Run it on a quiet machine (timings under load are meaningless); e.g.
//   POCL_DEVICES=basic build/bench/opencl_batch_bench --reps 15
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "device/opencl/cl_runtime.h"
#include "device/opencl/opencl_device.h"
#include "device/work_list.h"
#include "scene/builders.h"

using namespace multiray;

namespace {

struct Options {
  int device = 0, w = 320, h = 180, spp = 1, bounces = 1, reps = 9, tile = 256;
  std::vector<int> counts{64, 256, 1024}, batches{1, 16};
};

std::vector<int> int_list(const std::string& s) {
  std::vector<int> out;
  for (size_t at = 0; at <= s.size();) {
    const size_t comma = std::min(s.find(',', at), s.size());
    out.push_back(std::stoi(s.substr(at, comma - at)));
    at = comma + 1;
  }
  return out;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--device")
      o.device = std::stoi(v);
    else if (k == "--res")
      std::sscanf(v.c_str(), "%dx%d", &o.w, &o.h);
    else if (k == "--spp")
      o.spp = std::stoi(v);
    else if (k == "--bounces")
      o.bounces = std::stoi(v);
    else if (k == "--reps")
      o.reps = std::max(1, std::stoi(v));
    else if (k == "--tile")
      o.tile = std::stoi(v);
    else if (k == "--counts")
      o.counts = int_list(v);
    else if (k == "--batches")
      o.batches = int_list(v);
    else
      throw std::invalid_argument("unknown option " + k);
  }
  return o;
}

// About `n` rects covering w x h: rows = min(n, h) strips, each cut into ceil(n / rows).
std::vector<WorkItem> grid(int w, int h, int n) {
  const int rows = std::min(n, h), cols = std::min(w, (n + rows - 1) / rows);
  std::vector<WorkItem> items;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      items.push_back(
          WorkItem{{c * w / cols, r * h / rows, (c + 1) * w / cols, (r + 1) * h / rows}, 0});
  return items;
}

// Launches the device makes for `items` with batch `b` and launches of tile^2 pixels:
// takes as OpenClDevice's (up to b items, no more than one launch holds if all were as
// large as the first), each planned by plan_launches.
size_t launches(const std::vector<WorkItem>& items, int b, int tile) {
  const int64_t capacity = int64_t(tile) * tile;
  size_t n = 0;
  for (size_t k = 0; k < items.size();) {
    const int64_t area = std::max<int64_t>(1, items[k].rect.area());
    const size_t take = std::min(
        items.size() - k, size_t(std::min<int64_t>(b, std::max<int64_t>(1, capacity / area))));
    std::vector<Rect> rects;
    for (size_t j = k; j < k + take; ++j) rects.push_back(items[j].rect);
    n += plan_launches(rects, tile).size();
    k += take;
  }
  return n;
}

double frame_ms(Device& d, const ViewSetup& view, const RenderSettings& s,
                const std::vector<WorkItem>& items) {
  ListWorkSource source(items);
  std::vector<Framebuffer> out{Framebuffer(view.width, view.height)};
  FrameJob job{{view}, s, &out};
  const DeviceReport r = d.render(job, source, 0);
  if (r.failed) throw std::runtime_error(r.error);
  return r.time_ms;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  ViewSetup view;
  view.camera = scene.cameras.at(0);
  view.width = o.w, view.height = o.h;
  const RenderSettings s{.spp = o.spp, .max_bounces = o.bounces};
  const std::vector<WorkItem> whole{WorkItem{{0, 0, o.w, o.h}, 0}};
  for (int b : o.batches) {
    OpenClDeviceOptions opts{.index = o.device, .tile = o.tile, .batch = b};
    OpenClDevice device(cache, opts, "opencl:" + std::to_string(o.device));
    frame_ms(device, view, s, whole);  // warm-up: first launch, page faults
    for (int n : o.counts) {
      const std::vector<WorkItem> items = grid(o.w, o.h, n);
      std::vector<double> t1, tn;
      for (int r = 0; r < o.reps; ++r) {
        t1.push_back(frame_ms(device, view, s, whole));
        tn.push_back(frame_ms(device, view, s, items));
      }
      const double m1 = median(t1), mn = median(tn);
      const size_t l1 = launches(whole, b, o.tile), ln = launches(items, b, o.tile);
      nlohmann::json j{{"device", device.info().name},
                       {"batch", b},
                       {"items", items.size()},
                       {"res", std::to_string(o.w) + "x" + std::to_string(o.h)},
                       {"spp", o.spp},
                       {"reps", o.reps},
                       {"t1_ms", m1},
                       {"tN_ms", mn},
                       {"per_item_ms", (mn - m1) / double(std::max<size_t>(1, items.size() - 1))},
                       {"launches_1", l1},
                       {"launches_N", ln},
                       {"per_launch_ms", nullptr}};
      if (ln > l1) j["per_launch_ms"] = (mn - m1) / double(ln - l1);
      std::printf("%s\n", j.dump().c_str());
      std::fflush(stdout);
    }
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "opencl_batch_bench: %s\n", e.what());
  return 1;
}
