#include "util/result_encoding.h"

#include <stdexcept>

namespace multiray {

namespace {
constexpr const char* kNames[kResultEncodings] = {"float", "half", "float+zstd", "half+zstd"};
}  // namespace

std::string result_encoding_name(ResultEncoding e) {
  const auto i = size_t(e);
  return i < size_t(kResultEncodings) ? kNames[i] : "unknown";
}

ResultEncoding parse_result_encoding(const std::string& text) {
  for (int i = 0; i < kResultEncodings; ++i)
    if (text == kNames[i]) return ResultEncoding(i);
  throw std::invalid_argument("'" + text + "' must be float, half, float+zstd or half+zstd");
}

double measured_zstd_ratio(ResultEncoding e) {
  // Sponza, 640x360, 1 spp, one whole-frame item (docs/distributed.md): compressed bytes
  // over raw bytes (2,764,800 as floats, 1,382,400 as halves). Most pixels of one sample
  // are black, which compresses well; more samples compress less.
  switch (e) {
    case ResultEncoding::float_zstd:
      return 565267.0 / 2764800;
    case ResultEncoding::half_zstd:
      return 268968.0 / 1382400;
    default:
      return 1;
  }
}

double result_bytes_per_pixel(ResultEncoding e, double ratio) {
  if (!uses_zstd(e)) return raw_bytes_per_pixel(e);
  if (ratio < 0) ratio = measured_zstd_ratio(e);
  if (!(ratio > 0 && ratio <= 1))
    throw std::invalid_argument("a compression ratio must be in (0, 1]");
  return raw_bytes_per_pixel(e) * ratio;
}

}  // namespace multiray
