#include "balance/trace.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "partition/coverage.h"
#include "partition/weight_map.h"
#include "util/parse.h"

namespace multiray::balance {

namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Reads the fields of one line, each range-checked; errors name the line.
class LineReader {
 public:
  LineReader(const std::string& line, int number) : in_(line), number_(number) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw std::invalid_argument("trace line " + std::to_string(number_) + ": " + what);
  }
  std::string word() {
    std::string w;
    if (!(in_ >> w)) fail("a field is missing");
    return w;
  }
  double number(double lo, double hi) {
    const std::string w = word();
    const std::optional<double> v = parse_number(w);
    if (!v || *v < lo || *v > hi)
      fail("'" + w + "' is not a number in [" + num(lo) + ", " + num(hi) + "]");
    return *v;
  }
  int integer(int lo, int hi) {
    const double v = number(lo, hi);
    // Appended, not "'" + num(v): GCC 12 warns (-Wrestrict, a known false positive) on
    // operator+(const char*, std::string&&) once it is inlined here.
    if (v != std::floor(v))
      fail(std::string(1, '\'').append(num(v)).append("' is not a whole number"));
    return int(v);
  }
  std::string rest() {
    std::string r;
    std::getline(in_ >> std::ws, r);
    return r;
  }
  void end() {
    std::string extra;
    if (in_ >> extra) fail("unexpected '" + extra + "'");
  }

 private:
  std::istringstream in_;
  int number_;
};

constexpr double kMaxMs = 1e12;
constexpr int kMaxSide = 1 << 20;

// Throws unless the items of frame `f` (begun on line `line`) tile it: every pixel of
// every view once. The items of all its devices count, a dropped one's too: the engine
// keeps what a failing device finished and has another re-render the rest
// (Engine::recover_failures), so our own traces tile; a device left out has none. Items
// over the same pixels, or pixels nobody rendered, would replay as a frame that never
// was (an efficiency of 3, a free half). O(n log n) in the frame's items.
void check_tiling(const FrameStats& f, int line) {
  std::vector<WorkItem> items;
  for (const DeviceFrameStats& d : f.devices)
    for (const ItemReport& r : d.items) items.push_back(r.item);
  const std::string wrong = coverage_error(items, f.shape.width, f.shape.height, f.shape.views);
  if (!wrong.empty())
    throw std::invalid_argument("trace line " + std::to_string(line) + " (frame " +
                                std::to_string(f.frame) + "): " + wrong);
}

}  // namespace

TraceWriter::TraceWriter(std::ostream& out, const std::string& balancer,
                         const std::vector<TraceDevice>& devices)
    : out_(out) {
  out_ << "multiray-trace 1\nbalancer " << balancer << "\n";
  for (size_t i = 0; i < devices.size(); ++i)
    out_ << "device " << i << " " << num(devices[i].speed) << " " << devices[i].name << "\n";
}

void TraceWriter::frame(const FrameStats& s, const std::vector<DeviceCostModel>& models) {
  out_ << "frame " << s.frame << " " << s.shape.width << " " << s.shape.height << " "
       << s.shape.views << "\n";
  for (size_t d = 0; d < s.devices.size(); ++d) {
    const DeviceFrameStats& dev = s.devices[d];
    out_ << "time " << d << " "
         << (!dev.alive   ? 0
             : dev.rested ? 2
                          : 1)
         << " " << num(dev.time_ms) << " " << num(dev.busy_ms) << "\n";
    if (d < models.size())
      out_ << "model " << d << " " << num(models[d].fixed_ms) << " " << num(models[d].fixed_sigma)
           << " " << num(models[d].speed) << " " << (models[d].determined ? 1 : 0) << "\n";
    for (const ItemReport& r : dev.items)
      out_ << "item " << d << " " << r.id << " " << r.item.view << " " << r.item.rect.x0 << " "
           << r.item.rect.y0 << " " << r.item.rect.x1 << " " << r.item.rect.y1 << " "
           << num(r.samples) << " " << num(r.time_ms) << " " << num(r.busy_ms) << "\n";
  }
}

void write_trace(std::ostream& out, const Trace& trace) {
  TraceWriter w(out, trace.balancer, trace.devices);
  for (size_t k = 0; k < trace.frames.size(); ++k)
    w.frame(trace.frames[k],
            k < trace.models.size() ? trace.models[k] : std::vector<DeviceCostModel>{});
}

Trace read_trace(std::istream& in) {
  Trace t;
  std::string line;
  int number = 0, frame_line = 0;  // frame_line: where the last frame began
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    LineReader r(line, number);
    const std::string kind = r.word();
    if (number == 1) {
      if (kind != "multiray-trace" || r.integer(1, 1) != 1) r.fail("not a multiray trace (v1)");
    } else if (kind == "balancer") {
      t.balancer = r.rest();
    } else if (kind == "device") {
      // Frames size their device lists when they start (fuzz finding F2).
      if (!t.frames.empty()) r.fail("devices must be declared before the first frame");
      if (r.integer(0, 1 << 16) != int(t.devices.size()))
        r.fail("devices must be numbered 0, 1, ...");
      TraceDevice d;
      d.speed = r.number(1e-9, 1e9);
      d.name = r.rest();
      t.devices.push_back(d);
    } else if (kind == "frame") {
      FrameStats f;
      f.frame = r.integer(0, 1 << 30);
      f.shape.width = r.integer(1, kMaxSide);
      f.shape.height = r.integer(1, kMaxSide);
      f.shape.views = r.integer(1, 1 << 16);
      r.end();
      f.devices.resize(t.devices.size());
      if (!t.frames.empty()) check_tiling(t.frames.back(), frame_line);
      frame_line = number;
      t.frames.push_back(f);
      t.models.emplace_back();
    } else if (kind == "model") {
      if (t.frames.empty()) r.fail("'model' before the first frame");
      const int d = r.integer(0, int(t.devices.size()) - 1);
      std::vector<DeviceCostModel>& m = t.models.back();
      m.resize(t.devices.size());
      m[size_t(d)].fixed_ms = r.number(0, kMaxMs);
      m[size_t(d)].fixed_sigma = r.number(0, 1e300);
      m[size_t(d)].speed = r.number(0, 1e300);
      m[size_t(d)].determined = r.integer(0, 1) == 1;
      r.end();
    } else if (kind == "time" || kind == "item") {
      if (t.frames.empty()) r.fail("'" + kind + "' before the first frame");
      FrameStats& f = t.frames.back();
      const int d = r.integer(0, int(t.devices.size()) - 1);
      DeviceFrameStats& dev = f.devices[size_t(d)];
      if (kind == "time") {
        const int state = r.integer(0, 2);  // 0 dropped, 1 alive, 2 left out (rested)
        dev.alive = state != 0;
        dev.rested = state == 2;
        dev.time_ms = r.number(0, kMaxMs);
        dev.busy_ms = r.number(0, kMaxMs);
      } else {
        ItemReport it;
        it.id = uint32_t(r.number(0, 4294967295.0));
        it.item.view = r.integer(0, f.shape.views - 1);
        it.item.rect.x0 = r.integer(0, f.shape.width);
        it.item.rect.y0 = r.integer(0, f.shape.height);
        it.item.rect.x1 = r.integer(it.item.rect.x0, f.shape.width);
        it.item.rect.y1 = r.integer(it.item.rect.y0, f.shape.height);
        it.samples = r.number(0, 1e18);
        it.time_ms = r.number(0, kMaxMs);
        it.busy_ms = r.number(0, kMaxMs);
        dev.items.push_back(it);
        dev.samples += it.samples;
        dev.pixels += double(it.item.rect.area());
      }
      r.end();
    } else {
      r.fail("unknown record '" + kind + "'");
    }
  }
  if (number == 0) throw std::invalid_argument("trace is empty");
  // Nothing to replay: `simulate` and its studies index the first frame.
  if (t.frames.empty()) throw std::invalid_argument("the trace has no frames");
  check_tiling(t.frames.back(), frame_line);
  return t;
}

CostFn trace_cost(const Trace& trace, size_t frame_index, const FrameShape& shape) {
  const FrameStats& f = trace.frames.at(frame_index);
  const WeightMap weight(shape.width, shape.height, shape.views, shape.pixel_weight);
  // Exact items first; the density map for everything else.
  using Key = std::tuple<int, int, int, int, int>;
  auto exact = std::make_shared<std::map<Key, double>>();
  std::vector<float> density(size_t(shape.pixels()), 0.0f);
  for (size_t d = 0; d < f.devices.size(); ++d)
    for (const ItemReport& r : f.devices[d].items) {
      const double cost = r.time_ms * trace.devices[d].speed;
      const Rect& q = r.item.rect;
      (*exact)[Key{r.item.view, q.x0, q.y0, q.x1, q.y1}] = cost;
      const double w = weight.sum(r.item);
      if (!(w > 0) || r.item.view >= shape.views) continue;
      for (int y = q.y0; y < std::min(q.y1, shape.height); ++y)
        for (int x = q.x0; x < std::min(q.x1, shape.width); ++x) {
          const size_t p =
              (size_t(r.item.view) * size_t(shape.height) + size_t(y)) * size_t(shape.width) +
              size_t(x);
          density[p] = float(cost / w * (shape.weighted() ? shape.pixel_weight[p] : 1.0f));
        }
    }
  auto map = std::make_shared<WeightMap>(shape.width, shape.height, shape.views, density);
  return [exact, map](const WorkItem& it) {
    const auto found = exact->find(Key{it.view, it.rect.x0, it.rect.y0, it.rect.x1, it.rect.y1});
    return found != exact->end() ? found->second : map->sum(it);
  };
}

TraceCosts::TraceCosts(const Trace& trace) : trace_(trace), costs_(trace.frames.size()) {}

const CostFn& TraceCosts::at(size_t k) {
  if (!costs_.at(k)) {
    costs_[k] = trace_cost(trace_, k, trace_.frames[k].shape);
    ++built_;
  }
  return costs_[k];
}

std::vector<SimFrame> replay_trace(
    const Trace& trace, Balancer& balancer,
    const std::function<std::vector<SimDevice>(int frame)>& devices_at, const SimLink& link,
    int frames, uint64_t seed) {
  std::vector<SimFrame> run;
  replay_trace_each(trace, balancer, devices_at, link, frames, seed,
                    [&](int, SimFrame&& sf) { run.push_back(std::move(sf)); });
  return run;
}

void replay_trace_each(const Trace& trace, Balancer& balancer,
                       const std::function<std::vector<SimDevice>(int frame)>& devices_at,
                       const SimLink& link, int frames, uint64_t seed,
                       const std::function<void(int f, SimFrame&& frame)>& each,
                       TraceCosts* shared) {
  if (trace.frames.empty()) throw std::invalid_argument("the trace has no frames");
  if (shared && &shared->trace() != &trace)
    throw std::invalid_argument("the replay's cost tables belong to another trace");
  std::optional<TraceCosts> own;  // this replay's alone when none is shared
  TraceCosts& costs = shared ? *shared : own.emplace(trace);
  std::vector<SimDevice> recorded;
  for (const TraceDevice& d : trace.devices) recorded.push_back(SimDevice{d.speed});
  if (frames <= 0) frames = int(trace.frames.size());
  for (int f = 0; f < frames; ++f) {
    const size_t k = size_t(f) % trace.frames.size();
    const FrameShape& shape = trace.frames[k].shape;
    const CostFn& cost = costs.at(k);
    const int frame = frames == int(trace.frames.size()) ? trace.frames[k].frame : f;
    SimFrame sf =
        simulate_linked(balancer.plan(shape, frame), shape,
                        devices_at ? devices_at(frame) : recorded, cost, link, frame, seed);
    balancer.update(sf.stats);
    each(f, std::move(sf));
  }
}

}  // namespace multiray::balance
