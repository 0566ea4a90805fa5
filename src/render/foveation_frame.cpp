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
// the gaze stays even when the gaze is on the right or bottom edge).
void clip_pattern(const FoveationPattern& pattern, FoveationFrame& f) {
  const float w = float(f.width), h = float(f.height);
  for (size_t i = 0; i < pattern.offsets.size(); ++i) {
    const Vec2 p{f.gaze.x + pattern.offsets[i].x, f.gaze.y + pattern.offsets[i].y};
    if (p.x >= 0 && p.x <= w && p.y >= 0 && p.y <= h) {
      f.position.push_back(p);
      f.id.push_back(uint32_t(i));
    }
  }
}

// The k nearest samples of every pixel centre, rows in parallel.
void find_neighbours(FoveationFrame& f) {
  const SampleCloud cloud{f.position};
  const SampleTree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  const size_t k = size_t(f.k), found_max = std::min(k, f.size());
  f.neighbours.assign(size_t(f.width) * size_t(f.height) * k, FoveationFrame::kNoSample);
  oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<int>(0, f.height), [&](const auto& rows) {
    std::vector<uint32_t> idx(k);
    std::vector<float> d2(k);
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x = 0; x < f.width; ++x) {
        const float q[2] = {float(x) + 0.5f, float(y) + 0.5f};
        const size_t n = tree.knnSearch(q, found_max, idx.data(), d2.data());
        std::copy_n(idx.data(), n,
                    f.neighbours.begin() + ptrdiff_t((size_t(y) * f.width + x) * k));
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
  f.pixel_samples.assign(size_t(f.width) * size_t(f.height), 0.0f);
  f.cells_x = (f.width + f.cell_px - 1) / f.cell_px;
  f.cells_y = (f.height + f.cell_px - 1) / f.cell_px;
  f.cell_start.assign(size_t(f.cells_x) * size_t(f.cells_y) + 1, 0);
  std::vector<uint32_t> cell_of(f.size());
  float max_r2 = 0;
  f.used_samples = 0;
  for (size_t s = 0; s < f.size(); ++s) {
    if (f.radius2[s] < 0) continue;
    const Vec2 p = f.position[s];
    const int px = std::min(int(p.x), f.width - 1), py = std::min(int(p.y), f.height - 1);
    f.pixel_samples[size_t(py) * size_t(f.width) + size_t(px)] += 1.0f;
    cell_of[s] = uint32_t((py / f.cell_px) * f.cells_x + px / f.cell_px);
    ++f.cell_start[cell_of[s] + 1];
    max_r2 = std::max(max_r2, f.radius2[s]);
    ++f.used_samples;
  }
  for (size_t c = 1; c < f.cell_start.size(); ++c) f.cell_start[c] += f.cell_start[c - 1];
  f.cell_samples.resize(f.used_samples);
  std::vector<uint32_t> fill(f.cell_start.begin(), f.cell_start.end() - 1);
  for (size_t s = 0; s < f.size(); ++s)
    if (f.radius2[s] >= 0) f.cell_samples[fill[cell_of[s]]++] = uint32_t(s);
  f.reach = std::sqrt(max_r2) + 1.0f;  // one pixel of slack over any rounding
}

}  // namespace

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
  f.gaze = Vec2{std::clamp(gaze_x, 0.0f, 1.0f) * float(f.width),
                std::clamp(gaze_y, 0.0f, 1.0f) * float(f.height)};
  clip_pattern(pattern, f);
  find_neighbours(f);
  index_samples(f);
  return f;
}

std::vector<uint32_t> select_samples(const FoveationFrame& f, PixelRect rect) {
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
