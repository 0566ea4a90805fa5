#include "render/foveation_frame.h"

#include <algorithm>
#include <cmath>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <nanoflann.hpp>

namespace multiray {

namespace {

// nanoflann's view of the sample positions.
struct SampleCloud {
  const std::vector<Vec2>& points;
  size_t kdtree_get_point_count() const { return points.size(); }
  float kdtree_get_pt(uint32_t i, size_t dim) const {
    return dim == 0 ? points[i].x : points[i].y;
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;  // let nanoflann compute the bounding box
  }
};

using SampleTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, SampleCloud, float>,
                                        SampleCloud, 2, uint32_t>;

// Keeps the pattern's samples that land on the screen (closed rectangle: the sample at
// the gaze stays even when the gaze is on the right or bottom edge), ordered by cell.
void clip_pattern(const FoveationPattern& pattern, FoveationFrame& f) {
  const float w = float(f.width), h = float(f.height);
  std::vector<Vec2> kept;
  std::vector<uint32_t> id, cell;
  std::vector<uint32_t> start(size_t(f.cells_x) * size_t(f.cells_y) + 1, 0);
  for (size_t i = 0; i < pattern.offsets.size(); ++i) {
    const Vec2 p{f.gaze.x + pattern.offsets[i].x, f.gaze.y + pattern.offsets[i].y};
    if (!(p.x >= 0 && p.x <= w && p.y >= 0 && p.y <= h)) continue;
    kept.push_back(p);
    id.push_back(uint32_t(i));
    cell.push_back(uint32_t(f.cell_of(p)));
    ++start[cell.back() + 1];
  }
  // Counting sort by cell, stable: pattern order within a cell.
  for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  f.position.resize(kept.size());
  f.id.resize(kept.size());
  for (size_t i = 0; i < kept.size(); ++i) {
    const uint32_t to = start[cell[i]]++;
    f.position[to] = kept[i];
    f.id[to] = id[i];
  }
}

// Shepard weights of one pixel's neighbours nb[0..n), normalised, into w[0..n).
void shepard_weights(const FoveationFrame& f, float cx, float cy, uint32_t* nb, int n, float* w) {
  constexpr float kCoincident = 1e-12f;  // squared pixels: closer than 1e-6 px wins
  float total = 0;
  for (int j = 0; j < n; ++j) {
    const float d2 = distance2_to_box(f.position[nb[j]], cx, cy, cx, cy);
    if (d2 <= kCoincident) {
      std::swap(nb[0], nb[j]);
      std::fill_n(w, n, 0.0f);
      w[0] = 1.0f;
      return;
    }
    w[j] = 1.0f / d2;
    total += w[j];
  }
  for (int j = 0; j < n; ++j) w[j] /= total;
}

// The k nearest samples of every pixel centre and their weights, rows in parallel.
void find_neighbours(FoveationFrame& f) {
  const SampleCloud cloud{f.position};
  const SampleTree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  const size_t k = size_t(f.k), found_max = std::min(k, f.size());
  f.neighbours.assign(size_t(f.width) * size_t(f.height) * k, FoveationFrame::kNoSample);
  f.weights.assign(f.neighbours.size(), 0.0f);
  oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<int>(0, f.height), [&](const auto& rows) {
    std::vector<float> d2(k);
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x = 0; x < f.width; ++x) {
        const size_t at = (size_t(y) * size_t(f.width) + size_t(x)) * k;
        const float q[2] = {float(x) + 0.5f, float(y) + 0.5f};
        const size_t n = tree.knnSearch(q, found_max, &f.neighbours[at], d2.data());
        shepard_weights(f, q[0], q[1], &f.neighbours[at], int(n), &f.weights[at]);
      }
  });
}

// radius2 of every sample from the neighbour lists, the cost map and the selection grid.
void index_samples(FoveationFrame& f) {
  f.radius2.assign(f.size(), -1.0f);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const float cx = float(x) + 0.5f, cy = float(y) + 0.5f;
      const uint32_t* nb = f.neighbours_of(x, y);
      for (int j = 0; j < f.k && nb[j] != FoveationFrame::kNoSample; ++j) {
        float& r2 = f.radius2[nb[j]];
        r2 = std::max(r2, distance2_to_box(f.position[nb[j]], cx, cy, cx, cy));
      }
    }
  // Samples are in cell order already: the CSR lists keep the used ones in that order.
  f.pixel_samples.assign(size_t(f.width) * size_t(f.height), 0.0f);
  f.cell_start.assign(size_t(f.cells_x) * size_t(f.cells_y) + 1, 0);
  float max_r2 = 0;
  f.used_samples = 0;
  for (size_t s = 0; s < f.size(); ++s) {
    if (f.radius2[s] < 0) continue;
    const Vec2 p = f.position[s];
    const int px = std::min(int(p.x), f.width - 1), py = std::min(int(p.y), f.height - 1);
    f.pixel_samples[size_t(py) * size_t(f.width) + size_t(px)] += 1.0f;
    ++f.cell_start[f.cell_of(p) + 1];
    f.cell_samples.push_back(uint32_t(s));
    max_r2 = std::max(max_r2, f.radius2[s]);
    ++f.used_samples;
  }
  for (size_t c = 1; c < f.cell_start.size(); ++c) f.cell_start[c] += f.cell_start[c - 1];
  f.reach = std::sqrt(max_r2) + 1.0f;  // one pixel of slack over any rounding
}

}  // namespace

uint64_t samples_in_rect(const FoveationFrame& f, Rect rect) {
  double sum = 0;
  for (int y = std::max(rect.y0, 0); y < std::min(rect.y1, f.height); ++y)
    for (int x = std::max(rect.x0, 0); x < std::min(rect.x1, f.width); ++x)
      sum += f.pixel_samples[size_t(y) * size_t(f.width) + size_t(x)];
  return uint64_t(sum);
}

float distance2_to_box(Vec2 p, float x0, float y0, float x1, float y1) {
  const float dx = p.x < x0 ? x0 - p.x : (p.x > x1 ? p.x - x1 : 0.0f);
  const float dy = p.y < y0 ? y0 - p.y : (p.y > y1 ? p.y - y1 : 0.0f);
  return dx * dx + dy * dy;
}

FoveationFrame prepare_foveation_frame(const FoveationPattern& pattern, float gaze_x,
                                       float gaze_y) {
  FoveationFrame f;
  f.width = pattern.width, f.height = pattern.height;
  f.k = pattern.params.neighbours;
  f.cells_x = (f.width + f.cell_px - 1) / f.cell_px;
  f.cells_y = (f.height + f.cell_px - 1) / f.cell_px;
  f.gaze = Vec2{std::clamp(gaze_x, 0.0f, 1.0f) * float(f.width),
                std::clamp(gaze_y, 0.0f, 1.0f) * float(f.height)};
  clip_pattern(pattern, f);
  find_neighbours(f);
  index_samples(f);
  return f;
}

std::vector<uint32_t> select_samples(const FoveationFrame& f, Rect rect) {
  std::vector<uint32_t> out;
  rect.x0 = std::max(rect.x0, 0), rect.y0 = std::max(rect.y0, 0);
  rect.x1 = std::min(rect.x1, f.width), rect.y1 = std::min(rect.y1, f.height);
  if (rect.area() == 0) return out;
  // The box of the rect's pixel centres; candidates come from the cells within `reach`.
  const float x0 = float(rect.x0) + 0.5f, y0 = float(rect.y0) + 0.5f;
  const float x1 = float(rect.x1) - 0.5f, y1 = float(rect.y1) - 0.5f;
  const auto cell = [&](float v, int cells) {
    return std::clamp(int(std::floor(v / float(f.cell_px))), 0, cells - 1);
  };
  const int cx0 = cell(x0 - f.reach, f.cells_x), cx1 = cell(x1 + f.reach, f.cells_x);
  const int cy0 = cell(y0 - f.reach, f.cells_y), cy1 = cell(y1 + f.reach, f.cells_y);
  for (int cy = cy0; cy <= cy1; ++cy)
    for (int cx = cx0; cx <= cx1; ++cx) {
      const size_t c = size_t(cy) * size_t(f.cells_x) + size_t(cx);
      for (uint32_t j = f.cell_start[c]; j < f.cell_start[c + 1]; ++j) {
        const uint32_t s = f.cell_samples[j];
        if (distance2_to_box(f.position[s], x0, y0, x1, y1) <= f.radius2[s]) out.push_back(s);
      }
    }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace multiray
