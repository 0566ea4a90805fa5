#include "partition/bands.h"

#include <cstddef>

#include "partition/apportion.h"

namespace multiray::balance {

std::vector<Rect> split_bands(int width, int height, const std::vector<double>& ratios,
                              Axis axis) {
  std::vector<Rect> out(ratios.size());
  if (width <= 0 || height <= 0) return out;
  const int extent = axis == Axis::Rows ? height : width;
  const std::vector<int64_t> counts = apportion(ratios, extent);
  int begin = 0;
  for (size_t i = 0; i < counts.size(); ++i) {
    const int end = begin + int(counts[i]);
    out[i] = axis == Axis::Rows ? Rect{0, begin, width, end} : Rect{begin, 0, end, height};
    begin = end;
  }
  return out;
}

}  // namespace multiray::balance
