#include "core/exposure.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace multiray {

float metered_exposure_ev(const Framebuffer& fb) {
  if (fb.pixels.empty()) return 0.0f;
  // Metering zones: a path tracer's noise lowers a log average (the log of a noisy value
  // is below the log of its mean), by as much as the image is noisy. Averaging each zone's
  // radiance first, as a camera's zone meter does, takes most of that bias away.
  const int zone =
      std::max(1, int(std::lround(std::sqrt(double(fb.width) * fb.height / double(kMeterZones)))));
  // Black zones carry nothing for a meter to read: the background where no ray hit and no
  // environment shines (the Cornell box's). Counting them would brighten by as much as they
  // cover, so they are left out.
  std::vector<double> logs;
  for (int y0 = 0; y0 < fb.height; y0 += zone)
    for (int x0 = 0; x0 < fb.width; x0 += zone) {
      double sum = 0.0;
      int count = 0;
      for (int y = y0; y < std::min(fb.height, y0 + zone); ++y)
        for (int x = x0; x < std::min(fb.width, x0 + zone); ++x, ++count) {
          const Vec3& p = fb.at(x, y);
          const double l = 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;
          if (std::isfinite(l) && l > 0) sum += l;
        }
      const double l = sum / count;
      if (l > kMeterBlack) logs.push_back(std::log(l));
    }
  if (logs.empty()) return 0.0f;
  std::sort(logs.begin(), logs.end());
  const size_t trim = size_t(double(kMeterTrim) * double(logs.size()));
  double sum = 0.0;
  for (size_t i = trim; i < logs.size() - trim; ++i) sum += logs[i];
  const double log_average = sum / double(logs.size() - 2 * trim);
  const double ev = std::log2(double(kMeterKey)) - log_average / std::log(2.0);
  return float(std::clamp(ev, -double(kMeterMaxStops), double(kMeterMaxStops)));
}

}  // namespace multiray
