#include "balance/bruder.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "partition/kd_tiles.h"

namespace multiray::balance {

namespace {
constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();

// The frame's tiles: each view cut into tile×tile tiles (clipped at the right and bottom),
// the views' grids side by side in one grid of columns × rows tiles.
struct TileLayout {
  int tile = 1, width = 0, height = 0;
  int per_view = 0;  // tile columns of one view
  int columns = 0, rows = 0;

  TileLayout(const FrameShape& shape, int tile_px)
      : tile(tile_px), width(shape.width), height(shape.height) {
    per_view = int((int64_t(width) + tile - 1) / tile);
    columns = per_view * shape.views;
    rows = int((int64_t(height) + tile - 1) / tile);
  }
  // The pixels of tile (tx, ty) of the combined grid.
  WorkItem item(int tx, int ty) const {
    const int x0 = (tx % per_view) * tile, y0 = ty * tile;
    const Rect r{x0, y0, int(std::min<int64_t>(width, int64_t(x0) + tile)),
                 int(std::min<int64_t>(height, int64_t(y0) + tile))};
    return WorkItem{r, tx / per_view};
  }
};

// The work items of a rectangle of tiles (tile units): per view it spans, one item
// ("rect"), one per tile row ("rows") or one per tile ("tiles"), row-major.
std::vector<WorkItem> items_of(const TileLayout& layout, const Rect& tiles,
                               const std::string& mode) {
  std::vector<WorkItem> out;
  if (mode == "tiles") {
    for (int ty = tiles.y0; ty < tiles.y1; ++ty)
      for (int tx = tiles.x0; tx < tiles.x1; ++tx) out.push_back(layout.item(tx, ty));
    return out;
  }
  // Pixel rect of tiles [x0, x1) x [y0, y1) within one view.
  auto span = [&](int x0, int x1, int y0, int y1) {
    const WorkItem a = layout.item(x0, y0), b = layout.item(x1 - 1, y1 - 1);
    return WorkItem{Rect{a.rect.x0, a.rect.y0, b.rect.x1, b.rect.y1}, a.view};
  };
  const int step = mode == "rect" ? std::max(tiles.y1 - tiles.y0, 1) : 1;
  for (int ty = tiles.y0; ty < tiles.y1; ty += step)
    for (int x = tiles.x0; x < tiles.x1;) {
      const int view_end = (x / layout.per_view + 1) * layout.per_view;
      const int x1 = std::min(tiles.x1, view_end);
      out.push_back(span(x, x1, ty, std::min(ty + step, tiles.y1)));
      x = x1;
    }
  return out;
}

TileCosts tile_costs(const TileLayout& layout, const WeightMap& weights) {
  TileCosts grid{layout.columns, layout.rows, {}};
  grid.cost.reserve(size_t(layout.columns) * size_t(layout.rows));
  for (int ty = 0; ty < layout.rows; ++ty)
    for (int tx = 0; tx < layout.columns; ++tx)
      grid.cost.push_back(weights.sum(layout.item(tx, ty)));
  return grid;
}
}  // namespace

std::vector<double> prediction_shares(const std::vector<double>& sigma, double zeta,
                                      const std::vector<bool>& alive) {
  if (!(zeta >= 0 && zeta <= 1))
    throw std::invalid_argument("prediction_shares: zeta not in [0, 1]");
  if (!alive.empty() && alive.size() != sigma.size())
    throw std::invalid_argument("prediction_shares: one alive flag per device expected");
  const size_t n = sigma.size();
  auto is_alive = [&](size_t i) { return alive.empty() || alive[i]; };
  // Weights 1/σ_i scaled by the smallest σ: in [0, 1], so their sum cannot overflow.
  double lowest = std::numeric_limits<double>::infinity();
  int count = 0, known = 0;
  for (size_t i = 0; i < n; ++i)
    if (is_alive(i)) {
      ++count;
      if (usable(sigma[i])) lowest = std::min(lowest, sigma[i]), ++known;
    }
  std::vector<double> w(n, 0.0);
  double known_sum = 0;
  for (size_t i = 0; i < n; ++i)
    if (is_alive(i) && usable(sigma[i])) known_sum += w[i] = lowest / sigma[i];
  const double fill = known > 0 ? known_sum / known : 1.0;  // for devices without σ
  double sum = 0;
  for (size_t i = 0; i < n; ++i)
    if (is_alive(i)) sum += w[i] = usable(sigma[i]) ? w[i] : fill;
  for (size_t i = 0; i < n; ++i)
    if (is_alive(i)) w[i] = zeta * w[i] / sum + (1 - zeta) / count;
  return w;
}

BruderBalancer::BruderBalancer(int device_count, Options options)
    : BalancerBase(device_count), options_(options) {
  if (!(options_.zeta >= 0 && options_.zeta <= 1))
    throw std::invalid_argument("bruder: zeta must lie in [0, 1]");
  if (options_.tile < 1) throw std::invalid_argument("bruder: tile must be >= 1");
  if (!options_.fixed_cost.empty() && options_.fixed_cost.size() != size_t(device_count))
    throw std::invalid_argument("bruder: sigma needs one cost per device");
  for (double s : options_.fixed_cost)
    if (!usable(s)) throw std::invalid_argument("bruder: every sigma must be finite and > 0");
  measured_.assign(size_t(device_count), kUnknown);
}

std::string BruderBalancer::spec() const {
  std::ostringstream s;
  s << "bruder:zeta=" << options_.zeta << ":tile=" << options_.tile
    << ":steal=" << (options_.steal ? 1 : 0) << ":items=" << options_.items;
  for (size_t i = 0; i < options_.fixed_cost.size(); ++i)
    s << (i == 0 ? ":sigma=" : "/") << options_.fixed_cost[i];
  return s.str();
}

std::vector<double> BruderBalancer::costs_for(const FrameShape& shape) const {
  if (!options_.fixed_cost.empty()) return options_.fixed_cost;  // §7.5's static: σ̄_i
  std::vector<double> sigma = measured_;
  for (size_t i = 0; i < sigma.size() && i < shape.device_cost.size(); ++i)
    if (usable(shape.device_cost[i])) sigma[i] = shape.device_cost[i];
  return sigma;
}

Plan BruderBalancer::plan(const FrameShape& shape, int /*frame*/) {
  validate_shape(shape);
  planned_ = false;
  if (alive_count() == 0 || shape.pixels() == 0) return empty_plan();
  std::vector<bool> alive_now(static_cast<size_t>(device_count()));
  for (int i = 0; i < device_count(); ++i) alive_now[size_t(i)] = alive(i);
  shares_ = prediction_shares(costs_for(shape), options_.zeta, alive_now);

  last_weights_ = WeightMap(shape.width, shape.height, shape.views, shape.pixel_weight);
  const TileLayout layout(shape, options_.tile);
  const TileCosts grid = tile_costs(layout, last_weights_);
  const std::vector<Rect> rects = kd_split_tiles(grid, shares_);

  Plan plan;
  plan.assigned.resize(size_t(device_count()));
  plan.steal = options_.steal;
  plan.ratios = shares_;
  planned_work_.assign(size_t(device_count()), 0.0);
  for (size_t i = 0; i < rects.size(); ++i) {
    for (int ty = rects[i].y0; ty < rects[i].y1; ++ty)
      for (int tx = rects[i].x0; tx < rects[i].x1; ++tx)
        planned_work_[i] += grid.cost[size_t(ty) * size_t(grid.width) + size_t(tx)];
    plan.assigned[i] = items_of(layout, rects[i], options_.items);
  }
  last_size_ = FrameShape{shape.width, shape.height, shape.views, {}, {}};
  planned_ = true;
  return plan;
}

double BruderBalancer::work_of(const DeviceFrameStats& d, int i) const {
  if (d.items.empty()) return planned_work_[size_t(i)];  // exact unless it stole or lost
  double work = 0;
  for (const ItemReport& r : d.items) work += last_weights_.sum(r.item);
  return work;
}

void BruderBalancer::update(const FrameStats& stats) {
  drop_reported_dead(stats);
  // Costs per unit of work are only comparable with the weights of the frame planned.
  if (!planned_ || !stats.shape.same_size(last_size_)) return;
  for (int i = 0; i < device_count(); ++i) {
    const DeviceFrameStats* d = device_stats(stats, i);
    if (!d || !valid_time(d->time_ms)) continue;
    const double sigma = d->time_ms / work_of(*d, i);
    if (usable(sigma)) measured_[size_t(i)] = sigma;
  }
}

}  // namespace multiray::balance
