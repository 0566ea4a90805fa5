#include "partition/kd_tiles.h"

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace multiray::balance {

namespace {
double usable(double x) { return std::isfinite(x) && x > 0 ? x : 0.0; }

// The recursion of kd_split_tiles over one grid: O(1) rectangle costs from a summed-area
// table, O(1) share sums from prefix sums.
class KdSplitter {
 public:
  KdSplitter(const TileCosts& grid, const std::vector<double>& shares)
      : width_(grid.width), out_(shares.size()) {
    table_.assign(size_t(grid.width + 1) * size_t(grid.height + 1), 0.0);
    for (int y = 0; y < grid.height; ++y)
      for (int x = 0; x < grid.width; ++x)
        table_[at(x + 1, y + 1)] = usable(grid.cost[size_t(y) * size_t(grid.width) + size_t(x)]) +
                                   table_[at(x, y + 1)] + table_[at(x + 1, y)] - table_[at(x, y)];
    prefix_.assign(shares.size() + 1, 0.0);
    bool any = false;
    for (double s : shares) any = any || usable(s) > 0;
    for (size_t i = 0; i < shares.size(); ++i)
      prefix_[i + 1] = prefix_[i] + (any ? usable(shares[i]) : 1.0);
  }

  std::vector<Rect> run(const Rect& whole) {
    split(whole, 0, int(out_.size()));
    return out_;
  }

 private:
  size_t at(int x, int y) const { return size_t(y) * size_t(width_ + 1) + size_t(x); }
  double cost(const Rect& r) const {
    if (r.empty()) return 0;
    return table_[at(r.x1, r.y1)] - table_[at(r.x0, r.y1)] - table_[at(r.x1, r.y0)] +
           table_[at(r.x0, r.y0)];
  }
  double share(int a, int b) const { return prefix_[size_t(b)] - prefix_[size_t(a)]; }

  // The first `k` columns (or rows) of `r`.
  static Rect head(const Rect& r, bool columns, int k) {
    return columns ? Rect{r.x0, r.y0, r.x0 + k, r.y1} : Rect{r.x0, r.y0, r.x1, r.y0 + k};
  }

  // Number of columns (or rows) of `r` whose cost best matches `fraction` of r's cost;
  // tile counts stand in for costs when r costs nothing.
  int best_cut(const Rect& r, bool columns, double fraction) const {
    const bool by_cost = cost(r) > 0;
    auto measure = [&](const Rect& part) { return by_cost ? cost(part) : double(part.area()); };
    const double target = fraction * measure(r);
    const int length = columns ? r.width() : r.height();
    int best = 0;
    double best_error = std::abs(target);
    for (int k = 1; k <= length; ++k) {
      const double error = std::abs(measure(head(r, columns, k)) - target);
      if (error < best_error) best = k, best_error = error;
    }
    return best;
  }

  // Gives rectangle `r` to devices [a, b).
  void split(const Rect& r, int a, int b) {
    if (b - a == 1) {
      out_[size_t(a)] = r;
      return;
    }
    const int mid = a + (b - a) / 2;
    const double left = share(a, mid), right = share(mid, b);
    const bool columns = r.width() >= r.height();
    const int length = columns ? r.width() : r.height();
    int k = 0;  // neither side has a share: r is empty (see the constructor)
    if (left <= 0 && right > 0) k = 0;
    if (right <= 0 && left > 0) k = length;
    if (left > 0 && right > 0) k = best_cut(r, columns, left / (left + right));
    const Rect first = head(r, columns, k);
    const Rect second =
        columns ? Rect{first.x1, r.y0, r.x1, r.y1} : Rect{r.x0, first.y1, r.x1, r.y1};
    split(first, a, mid);
    split(second, mid, b);
  }

  int width_;
  std::vector<double> table_;   // [(y)·(width+1) + x] = cost of tiles [0,x)×[0,y)
  std::vector<double> prefix_;  // prefix_[i] = sum of the first i usable shares
  std::vector<Rect> out_;
};
}  // namespace

std::vector<Rect> kd_split_tiles(const TileCosts& grid, const std::vector<double>& shares) {
  if (shares.empty()) throw std::invalid_argument("kd_split_tiles: no shares");
  if (grid.width < 0 || grid.height < 0)
    throw std::invalid_argument("kd_split_tiles: negative grid size");
  if (grid.cost.size() != size_t(grid.width) * size_t(grid.height))
    throw std::invalid_argument("kd_split_tiles: " + std::to_string(grid.cost.size()) +
                                " costs for a " + std::to_string(grid.width) + "x" +
                                std::to_string(grid.height) + " grid");
  return KdSplitter(grid, shares).run(Rect{0, 0, grid.width, grid.height});
}

}  // namespace multiray::balance
