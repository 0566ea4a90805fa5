// The CPU device's fixed cost per item (issue 30: "the CPU device avoids per-item thread
// wake-ups"), the counterpart of opencl_batch_bench.
//
// For each thread count T (`cpu:threads=T`) the same frame is rendered as one item and as
// N items (a grid of near-equal rects, full-width strips while N <= height), `reps` times
// each, alternately; a frame's time is the device's own report (start of frame to last
// item, steady_clock inside the device). The pixels are the same in both, so the extra
// time is the fixed cost: per item (t_N - t_1) / (n - 1), n the items made, from the
// medians, with a 95% interval from resampling the repetitions (percentile bootstrap,
// fixed seed). One JSON object per (T, N) on stdout.
//
// Usage: cpu_item_bench [--res WxH] [--spp N] [--bounces N] [--reps N] [--tile T]
//                       [--counts 64,256,1024] [--threads 1,2]
// Run it on a quiet machine (timings under load are meaningless), e.g.
//   build/bench/cpu_item_bench --reps 15
#include <algorithm>
#include <cstdio>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "device/cpu/cpu_device.h"
#include "device/work_list.h"
#include "scene/builders.h"

using namespace multiray;

namespace {

struct Options {
  int w = 320, h = 180, spp = 1, bounces = 1, reps = 9, tile = 16;
  std::vector<int> counts{64, 256, 1024}, threads{1, 2};
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
    if (k == "--res")
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
    else if (k == "--threads")
      o.threads = int_list(v);
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

// The device's time for one frame of `items`, rendered from one thread kept for the
// whole run (as the engine keeps one thread per device).
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

// Per item cost from the medians of one-item and n-item frame times.
double per_item(const std::vector<double>& t1, const std::vector<double>& tn, size_t n) {
  return (median(tn) - median(t1)) / double(std::max<size_t>(1, n - 1));
}

// 95% percentile-bootstrap interval of per_item(), both samples resampled.
std::pair<double, double> interval(const std::vector<double>& t1, const std::vector<double>& tn,
                                   size_t n) {
  std::mt19937 rng(12345);
  std::vector<double> est, a(t1.size()), b(tn.size());
  for (int k = 0; k < 2000; ++k) {
    for (double& x : a) x = t1[std::uniform_int_distribution<size_t>(0, t1.size() - 1)(rng)];
    for (double& x : b) x = tn[std::uniform_int_distribution<size_t>(0, tn.size() - 1)(rng)];
    est.push_back(per_item(a, b, n));
  }
  std::sort(est.begin(), est.end());
  return {est[size_t(0.025 * double(est.size()))], est[size_t(0.975 * double(est.size()))]};
}

void run(const Options& o, const Scene& scene, SceneCache& cache, int threads) {
  ViewSetup view;
  view.camera = scene.cameras.at(0);
  view.width = o.w, view.height = o.h;
  const RenderSettings s{.spp = o.spp, .max_bounces = o.bounces};
  const std::vector<WorkItem> whole{WorkItem{{0, 0, o.w, o.h}, 0}};
  CpuDevice device(cache, CpuDeviceOptions{.threads = threads, .tile = o.tile},
                   "cpu:threads=" + std::to_string(threads));
  frame_ms(device, view, s, whole);  // warm-up: thread set-up, page faults
  for (int n : o.counts) {
    const std::vector<WorkItem> items = grid(o.w, o.h, n);
    std::vector<double> t1, tn;
    for (int r = 0; r < o.reps; ++r) {
      t1.push_back(frame_ms(device, view, s, whole));
      tn.push_back(frame_ms(device, view, s, items));
    }
    const auto [lo, hi] = interval(t1, tn, items.size());
    const nlohmann::json j{{"device", device.info().name},
                           {"threads", threads},
                           {"items", items.size()},
                           {"res", std::to_string(o.w) + "x" + std::to_string(o.h)},
                           {"spp", o.spp},
                           {"tile", o.tile},
                           {"reps", o.reps},
                           {"t1_ms", median(t1)},
                           {"tN_ms", median(tn)},
                           {"per_item_ms", per_item(t1, tn, items.size())},
                           {"per_item_ms_95", {lo, hi}}};
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  const Scene scene = make_cornell_box();
  SceneCache cache(scene);
  for (int t : o.threads) {
    std::exception_ptr error;
    // Each device on a thread of its own: its first render() pins and prepares that thread.
    std::thread([&] {
      try {
        run(o, scene, cache, t);
      } catch (...) {
        error = std::current_exception();
      }
    }).join();
    if (error) std::rethrow_exception(error);
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "cpu_item_bench: %s\n", e.what());
  return 1;
}
