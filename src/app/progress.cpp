#include "app/progress.h"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

namespace multiray::app {

double eta_seconds(const ProgressSnapshot& p) {
  const double done = p.frames_done + std::clamp(p.current, 0.0, 1.0);
  if (done < 0.02 || p.elapsed_s <= 0) return -1;
  return std::max(0.0, p.elapsed_s / done * (p.frames_total - done));
}

std::string format_clock(double seconds) {
  if (!(seconds >= 0)) return "--:--";
  const long long s = std::llround(std::min(seconds, 1e9));
  if (s >= 3600) return fmt::format("{}:{:02d}:{:02d}", s / 3600, int(s / 60 % 60), int(s % 60));
  return fmt::format("{}:{:02d}", s / 60, int(s % 60));
}

std::string progress_line(const ProgressSnapshot& p, bool bar, int width) {
  const int frame = std::min(p.frames_done + 1, std::max(p.frames_total, 1));
  const double current = std::clamp(p.current, 0.0, 1.0);
  const std::string rate =
      p.samples_elapsed_s > 0 && p.samples > 0
          ? fmt::format("{:.2f} Msamples/s", p.samples / p.samples_elapsed_s / 1e6)
          : std::string("rate --");
  const std::string eta = format_clock(eta_seconds(p));
  const std::string elapsed = format_clock(p.elapsed_s);
  if (!bar)
    return fmt::format("multiray: frame {}/{} ({:.0f}% of it), {} elapsed, ETA {}, {}", frame,
                       p.frames_total, 100 * current, elapsed, eta, rate);
  // The bar shows the whole run: finished frames plus the share of the current one.
  const double whole = (p.frames_done + current) / std::max(p.frames_total, 1);
  const int filled = std::clamp(int(std::floor(whole * width)), 0, width);
  return fmt::format("frame {}/{} [{}{}] {:3.0f}% of it | {} elapsed | ETA {} | {}", frame,
                     p.frames_total, std::string(size_t(filled), '#'),
                     std::string(size_t(width - filled), '.'), 100 * current, elapsed, eta, rate);
}

}  // namespace multiray::app
