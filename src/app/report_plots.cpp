#include "app/report_plots.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/core.h>

#include "core/error.h"
#include "core/file_io.h"
#include "core/image.h"

namespace multiray::app {

const char* device_colour(size_t i) {
  static const char* kColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                   "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  return kColours[i % 10];
}

void write_timeline_svg(const std::string& path, const std::string& title,
                        const std::vector<FrameRecord>& frames,
                        const std::vector<std::string>& labels) {
  const double W = 900, left = 60, right = 20, plot_w = W - left - right;
  const double top_y = 40, top_h = 260, gap = 50, bottom_h = 160,
               H = top_y + top_h + gap + bottom_h + 60;
  const size_t n = frames.size(), devices = labels.size();
  if (n == 0) return;
  double t_max = 1e-9;
  for (const auto& f : frames)
    for (const auto& d : f.devices) t_max = std::max(t_max, d.time_ms);
  t_max *= 1.05;
  auto x_of = [&](double i) { return left + (n > 1 ? i / double(n - 1) : 0.5) * plot_w; };
  std::string svg = fmt::format(
      "<svg xmlns='http://www.w3.org/2000/svg' width='{}' height='{}' font-family='sans-serif' "
      "font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n"
      "<text x='{}' y='20' font-size='15'>{}</text>\n",
      W, H, left, title);
  // Axes and grid of the time plot.
  for (int k = 0; k <= 4; ++k) {
    const double y = top_y + top_h * (1 - k / 4.0);
    svg += fmt::format(
        "<line x1='{}' y1='{}' x2='{}' y2='{}' stroke='#ddd'/>"
        "<text x='{}' y='{}' text-anchor='end'>{:.0f}</text>\n",
        left, y, left + plot_w, y, left - 5, y + 4, t_max * k / 4.0);
  }
  svg += fmt::format("<text x='15' y='{}' transform='rotate(-90 15 {})'>device time (ms)</text>\n",
                     top_y + top_h / 2, top_y + top_h / 2);
  for (size_t d = 0; d < devices; ++d) {
    std::string pts;
    for (size_t i = 0; i < n; ++i)
      if (d < frames[i].devices.size())
        pts += fmt::format("{:.1f},{:.1f} ", x_of(double(i)),
                           top_y + top_h * (1 - frames[i].devices[d].time_ms / t_max));
    svg += fmt::format("<polyline fill='none' stroke='{}' stroke-width='1.5' points='{}'/>\n",
                       device_colour(d), pts);
    svg += fmt::format(
        "<rect x='{}' y='{}' width='10' height='10' fill='{}'/><text x='{}' y='{}'>{}</text>\n",
        left + 10, top_y + 8 + 16 * double(d), device_colour(d), left + 25,
        top_y + 17 + 16 * double(d), labels[d]);
  }
  // Stacked work shares.
  const double by = top_y + top_h + gap;
  svg += fmt::format("<text x='15' y='{}' transform='rotate(-90 15 {})'>work share</text>\n",
                     by + bottom_h / 2, by + bottom_h / 2);
  for (size_t d = 0; d < devices; ++d) {
    std::string upper, lower;
    for (size_t i = 0; i < n; ++i) {
      double below = 0;
      for (size_t e = 0; e < d && e < frames[i].devices.size(); ++e)
        below += frames[i].devices[e].work_share;
      const double here = d < frames[i].devices.size() ? frames[i].devices[d].work_share : 0;
      upper += fmt::format("{:.1f},{:.1f} ", x_of(double(i)), by + bottom_h * (1 - below - here));
      lower = fmt::format("{:.1f},{:.1f} ", x_of(double(i)), by + bottom_h * (1 - below)) + lower;
    }
    svg += fmt::format("<polygon fill='{}' fill-opacity='0.8' points='{}{}'/>\n", device_colour(d),
                       upper, lower);
  }
  svg += fmt::format("<rect x='{}' y='{}' width='{}' height='{}' fill='none' stroke='black'/>\n",
                     left, by, plot_w, bottom_h);
  svg += fmt::format("<text x='{}' y='{}' text-anchor='middle'>frame (0..{})</text>\n",
                     left + plot_w / 2, by + bottom_h + 30, n - 1);
  svg += "</svg>\n";
  write_file_atomically(path, svg);
}

void write_partition_png(const std::string& path, int width, int height,
                         const std::vector<std::vector<balance::WorkItem>>& rendered) {
  std::vector<uint8_t> rgb(size_t(width) * size_t(height) * 3, 255);
  for (size_t d = 0; d < rendered.size(); ++d) {
    unsigned r, g, b;
    std::sscanf(device_colour(d), "#%02x%02x%02x", &r, &g, &b);
    for (const auto& item : rendered[d]) {
      if (item.view != 0) continue;
      const auto& q = item.rect;
      for (int y = std::max(0, q.y0); y < std::min(height, q.y1); ++y)
        for (int x = std::max(0, q.x0); x < std::min(width, q.x1); ++x) {
          const bool border = x == q.x0 || y == q.y0;
          const float k = border && q.width() > 2 && q.height() > 2 ? 0.6f : 1.0f;
          uint8_t* p = &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3];
          p[0] = uint8_t(float(r) * k), p[1] = uint8_t(float(g) * k), p[2] = uint8_t(float(b) * k);
        }
    }
  }
  write_png_rgb8(path, width, height, rgb);
}

void write_scaling_svg(const std::string& path, const std::string& title,
                       const std::vector<ScalingSeries>& series) {
  const double W = 1040, H = 540, left = 70, right = 270, top = 64, plot_h = 400;
  const double plot_w = W - left - right;
  double lo = 1e300, hi = 0;
  for (const auto& s : series)
    for (const auto& [n, e] : s.points) lo = std::min(lo, n), hi = std::max(hi, n);
  if (!(hi > 0)) return;
  const double l0 = std::log2(lo), l1 = std::max(std::log2(hi), l0 + 1);
  auto x_of = [&](double n) { return left + (std::log2(n) - l0) / (l1 - l0) * plot_w; };
  auto y_of = [&](double e) { return top + plot_h * (1 - std::clamp(e, 0.0, 1.0)); };
  std::string svg = fmt::format(
      "<svg xmlns='http://www.w3.org/2000/svg' width='{}' height='{}' font-family='sans-serif' "
      "font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n"
      "<text x='{}' y='22' font-size='14'>{}</text>\n",
      W, H, left, title.substr(0, title.find(" — ")));
  // Details after " — " go on a second, smaller line.
  if (title.find(" — ") != std::string::npos)
    svg += fmt::format("<text x='{}' y='42' font-size='11' fill='#444'>{}</text>\n", left,
                       title.substr(title.find(" — ") + 5));
  for (int k = 0; k <= 10; k += 2) {
    const double y = y_of(k / 10.0);
    svg += fmt::format(
        "<line x1='{}' y1='{:.1f}' x2='{}' y2='{:.1f}' stroke='#ddd'/><text x='{}' y='{:.1f}' "
        "text-anchor='end'>{:.1f}</text>\n",
        left, y, left + plot_w, y, left - 6, y + 4, k / 10.0);
  }
  for (double n = std::exp2(std::ceil(l0)); n <= std::exp2(l1) + 0.5; n *= 2)
    svg += fmt::format(
        "<line x1='{0:.1f}' y1='{1}' x2='{0:.1f}' y2='{2}' stroke='#eee'/><text x='{0:.1f}' "
        "y='{3}' text-anchor='middle'>{4}</text>\n",
        x_of(n), top, top + plot_h, top + plot_h + 16, int(n));
  svg += fmt::format(
      "<text x='{}' y='{}' text-anchor='middle'>devices</text><text x='16' y='{}' "
      "transform='rotate(-90 16 {})' text-anchor='middle'>efficiency</text>\n",
      left + plot_w / 2, top + plot_h + 36, top + plot_h / 2, top + plot_h / 2);
  for (size_t i = 0; i < series.size(); ++i) {
    std::string pts;
    for (const auto& [n, e] : series[i].points)
      pts += fmt::format("{:.1f},{:.1f} ", x_of(n), y_of(e));
    svg += fmt::format("<polyline points='{}' fill='none' stroke='{}' stroke-width='2'/>\n", pts,
                       device_colour(i));
    for (const auto& [n, e] : series[i].points)
      svg += fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='3' fill='{}'/>\n", x_of(n), y_of(e),
                         device_colour(i));
    const double ly = top + 14 + 18 * double(i);
    const double last = series[i].points.empty() ? 0 : series[i].points.back().second;
    svg += fmt::format(
        "<rect x='{}' y='{:.1f}' width='12' height='12' fill='{}'/><text x='{}' y='{:.1f}'>{} "
        "({:.2f} at {})</text>\n",
        left + plot_w + 12, ly - 10, device_colour(i), left + plot_w + 28, ly, series[i].name,
        last, series[i].points.empty() ? 0 : int(series[i].points.back().first));
  }
  svg += "</svg>\n";
  write_file_atomically(path, svg);
}

}  // namespace multiray::app
