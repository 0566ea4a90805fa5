#include "partition/cdf_split.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "partition/apportion.h"
#include "partition/scanline.h"

namespace multiray::balance {

std::vector<int64_t> cdf_cuts(const std::vector<double>& cell_weight, int64_t cell_size,
                              const std::vector<double>& shares) {
  const size_t devices = shares.size();
  const int64_t cells = int64_t(cell_weight.size());
  cell_size = std::max<int64_t>(cell_size, 1);
  const int64_t units = cells * cell_size;
  std::vector<int64_t> cuts(devices + 1, 0);
  if (devices == 0) return cuts;
  cuts[devices] = units;
  if (cells == 0) return cuts;

  // prefix[c] = weight of cells [0, c).
  std::vector<double> prefix(size_t(cells) + 1, 0.0);
  for (int64_t c = 0; c < cells; ++c) {
    const double w = cell_weight[size_t(c)];
    prefix[size_t(c) + 1] = prefix[size_t(c)] + (std::isfinite(w) && w > 0 ? w : 0.0);
  }
  const bool uniform = !(prefix.back() > 0) || !std::isfinite(prefix.back());
  auto weight_below = [&](int64_t c) { return uniform ? double(c) : prefix[size_t(c)]; };
  const double total = weight_below(cells);

  const std::vector<double> w = normalized_ratios(shares);
  double cumulative = 0;
  for (size_t i = 1; i < devices; ++i) {
    cumulative += w[i - 1];
    if (w[i - 1] == 0) {  // an empty range: no rounding may move this cut
      cuts[i] = cuts[i - 1];
      continue;
    }
    const double target = std::min(total, cumulative * total);
    // First cell whose end reaches the target (binary search on the prefix sums).
    int64_t lo = 0, hi = cells - 1;
    while (lo < hi) {
      const int64_t mid = lo + (hi - lo) / 2;
      if (weight_below(mid + 1) >= target)
        hi = mid;
      else
        lo = mid + 1;
    }
    const double cell_w = weight_below(lo + 1) - weight_below(lo);
    const double frac =
        cell_w > 0 ? std::clamp((target - weight_below(lo)) / cell_w, 0.0, 1.0) : 0.0;
    const int64_t pos = lo * cell_size + std::llround(frac * double(cell_size));
    cuts[i] = std::clamp(pos, cuts[i - 1], units);
  }
  return cuts;
}

std::vector<Rect> cdf_split_rows(int width, const std::vector<double>& row_weight,
                                 const std::vector<double>& shares) {
  const std::vector<int64_t> cuts = cdf_cuts(row_weight, 1, shares);
  std::vector<Rect> out(shares.size());
  for (size_t i = 0; i < shares.size(); ++i)
    out[i] = Rect{0, int(cuts[i]), std::max(width, 0), int(cuts[i + 1])};
  return out;
}

std::vector<Rect> cdf_split_columns(int height, const std::vector<double>& column_weight,
                                    const std::vector<double>& shares) {
  const std::vector<int64_t> cuts = cdf_cuts(column_weight, 1, shares);
  std::vector<Rect> out(shares.size());
  for (size_t i = 0; i < shares.size(); ++i)
    out[i] = Rect{int(cuts[i]), 0, int(cuts[i + 1]), std::max(height, 0)};
  return out;
}

std::vector<std::vector<WorkItem>> cdf_split_pixels(int width, int height, int view,
                                                    const std::vector<double>& pixel_weight,
                                                    const std::vector<double>& shares) {
  std::vector<std::vector<WorkItem>> out(shares.size());
  if (width <= 0 || height <= 0) return out;
  std::vector<double> weight = pixel_weight;
  weight.resize(size_t(width) * size_t(height), 0.0);
  const std::vector<int64_t> cuts = cdf_cuts(weight, 1, shares);
  for (size_t i = 0; i < shares.size(); ++i)
    append_scanline_rects(width, cuts[i], cuts[i + 1], view, out[i]);
  return out;
}

}  // namespace multiray::balance
