// pooled_costs() (trace_calibration.h): one cost density per frame from the net items of
// several traces of the same frames.
#include <algorithm>
#include <stdexcept>

#include "balance/trace_calibration.h"

namespace multiray::balance {

namespace {

// Every edge of any item of `view` along x (or y), with the frame's borders; sorted.
std::vector<int> cuts(const std::vector<const FrameStats*>& frames, int view, bool along_x,
                      int size) {
  std::vector<int> out{0, size};
  for (const FrameStats* fs : frames)
    for (const DeviceFrameStats& dev : fs->devices)
      for (const ItemReport& r : dev.items)
        if (r.item.view == view) {
          const Rect& q = r.item.rect;
          out.push_back(along_x ? q.x0 : q.y0);
          out.push_back(along_x ? q.x1 : q.y1);
        }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

size_t index_of(const std::vector<int>& cuts, int v) {
  return size_t(std::lower_bound(cuts.begin(), cuts.end(), v) - cuts.begin());
}

// A net item over the pieces [i0, i1) x [j0, j1): its area, cost and the standard error
// taken for its cost (its recorded time, in cost units: the noise of a time grows with it).
struct Span {
  size_t i0 = 0, i1 = 0, j0 = 0, j1 = 0;
  double area = 0, cost = 0, sigma = 0;
};

// Rounds of the reconstruction: it stops earlier once every item's cost is held to kHeld
// of the frame's.
constexpr int kRounds = 300;
constexpr double kHeld = 1e-9;
constexpr double kRelax = 1.8;  // each round moves by this many times the mean correction (< 2)

// Each piece's cost density (per pixel) such that every item's pieces sum to its cost
// (SART: each round, every item spreads what its pieces miss evenly over them, and a
// piece moves by the mean of its items' corrections weighted by their precision
// (area/σ)²), from each piece's mean density over its items, weighted alike. Where the
// traces disagree this settles on a compromise in which the precise items weigh most;
// pieces no item edge separates keep their items' mean. Every trace tiles the frame, so
// each piece lies in one item of each.
std::vector<double> reconstruct(const std::vector<Span>& spans, const std::vector<int>& xs,
                                const std::vector<int>& ys) {
  const size_t nx = xs.size() - 1, pieces = nx * (ys.size() - 1);
  std::vector<double> area(pieces), rho(pieces, 0.0), sum(pieces), weight(pieces);
  for (size_t j = 0; j + 1 < ys.size(); ++j)
    for (size_t i = 0; i < nx; ++i)
      area[j * nx + i] = double(xs[i + 1] - xs[i]) * double(ys[j + 1] - ys[j]);
  // Σ w·value(span) and Σ w over the items on each piece.
  auto spread = [&](auto&& value) {
    std::fill(sum.begin(), sum.end(), 0.0), std::fill(weight.begin(), weight.end(), 0.0);
    for (const Span& s : spans) {
      if (!(s.sigma > 0)) continue;
      const double v = value(s), w = (s.area / s.sigma) * (s.area / s.sigma);
      for (size_t j = s.j0; j < s.j1; ++j)
        for (size_t i = s.i0; i < s.i1; ++i) sum[j * nx + i] += w * v, weight[j * nx + i] += w;
    }
  };
  spread([](const Span& s) { return s.cost / s.area; });
  double total = 0;
  for (size_t p = 0; p < pieces; ++p) {
    rho[p] = weight[p] > 0 ? sum[p] / weight[p] : 0.0;
    total += rho[p] * area[p];
  }
  for (int round = 0; round < kRounds; ++round) {
    double worst = 0;
    spread([&](const Span& s) {
      double held = 0;
      for (size_t j = s.j0; j < s.j1; ++j)
        for (size_t i = s.i0; i < s.i1; ++i) held += rho[j * nx + i] * area[j * nx + i];
      worst = std::max(worst, std::abs(s.cost - held));
      return (s.cost - held) / s.area;
    });
    if (worst <= kHeld * total) break;
    for (size_t p = 0; p < pieces; ++p)
      if (weight[p] > 0) rho[p] = std::max(rho[p] + kRelax * sum[p] / weight[p], 0.0);
  }
  return rho;
}

}  // namespace

Trace pooled_costs(const std::vector<const Trace*>& traces, const TraceCalibration& cal) {
  if (traces.empty()) throw std::invalid_argument("no trace to pool");
  for (size_t r = 1; r < traces.size(); ++r) {
    const std::string why = trace_mismatch(*traces[0], *traces[r], "the first");
    if (!why.empty()) throw std::invalid_argument("trace " + std::to_string(r + 1) + " " + why);
  }
  if (cal.devices.size() != traces[0]->devices.size())
    throw std::invalid_argument("the calibration is of another number of devices");
  std::vector<Trace> nets;
  for (const Trace* t : traces) nets.push_back(net_trace(*t, cal));
  Trace out;
  out.balancer = traces[0]->balancer;
  for (const TraceDevice& d : traces[0]->devices) out.devices.push_back({d.name, 1.0});
  for (size_t f = 0; f < traces[0]->frames.size(); ++f) {
    std::vector<const FrameStats*> frames;
    for (const Trace& t : nets) frames.push_back(&t.frames[f]);
    FrameStats pooled;
    pooled.frame = frames[0]->frame;
    pooled.shape = frames[0]->shape;
    pooled.devices.resize(out.devices.size());
    DeviceFrameStats& dev = pooled.devices[0];
    for (int view = 0; view < pooled.shape.views; ++view) {
      const std::vector<int> xs = cuts(frames, view, true, pooled.shape.width);
      const std::vector<int> ys = cuts(frames, view, false, pooled.shape.height);
      const size_t nx = xs.size() - 1;
      std::vector<Span> spans;
      std::vector<double> spp((ys.size() - 1) * nx, 0.0);
      for (size_t r = 0; r < nets.size(); ++r)
        for (size_t d = 0; d < nets[r].devices.size(); ++d) {
          const double speed = nets[r].devices[d].speed;
          const auto& gross = traces[r]->frames[f].devices[d].items;
          const auto& net = frames[r]->devices[d].items;
          for (size_t k = 0; k < net.size(); ++k) {
            const Rect& q = net[k].item.rect;
            if (net[k].item.view != view || q.empty()) continue;
            Span s{index_of(xs, q.x0), index_of(xs, q.x1), index_of(ys, q.y0), index_of(ys, q.y1)};
            s.area = double(q.area());
            s.cost = net[k].time_ms * speed;
            s.sigma = gross[k].time_ms * speed;
            spans.push_back(s);
            for (size_t j = s.j0; j < s.j1; ++j)
              for (size_t i = s.i0; i < s.i1; ++i) spp[j * nx + i] = net[k].samples / s.area;
          }
        }
      const std::vector<double> rho = reconstruct(spans, xs, ys);
      for (size_t j = 0; j + 1 < ys.size(); ++j)
        for (size_t i = 0; i < nx; ++i) {
          ItemReport piece;
          piece.item.view = view;
          piece.item.rect = Rect{xs[i], ys[j], xs[i + 1], ys[j + 1]};
          piece.id = uint32_t(dev.items.size());
          const double area = double(piece.item.rect.area());
          piece.time_ms = piece.busy_ms = rho[j * nx + i] * area;
          piece.samples = spp[j * nx + i] * area;
          dev.time_ms += piece.time_ms;
          dev.samples += piece.samples;
          dev.pixels += area;
          dev.items.push_back(piece);
        }
    }
    dev.busy_ms = dev.time_ms;
    out.frames.push_back(std::move(pooled));
    out.models.emplace_back();
  }
  return out;
}

}  // namespace multiray::balance
