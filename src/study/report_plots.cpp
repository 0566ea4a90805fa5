#include "study/report_plots.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/core.h>

#include "core/error.h"
#include "core/file_io.h"
#include "core/image.h"
#include "study/svg_chart.h"

namespace multiray::study {

const char* device_colour(size_t i) {
  static const char* kColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                   "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  return kColours[i % 10];
}

TimelineScale timeline_scale(const BenchResult& result, int warmup, size_t frames) {
  TimelineScale scale;
  scale.warmup = warmup;
  // After the warm-up only: a first frame's set-up would flatten every line.
  for (const BenchLane& lane : result.lanes)
    for (const FrameRecord& r : lane.records)
      for (const DeviceReport& d : r.devices)
        if (r.frame >= warmup) scale.time_max_ms = std::max(scale.time_max_ms, d.time_ms);
  if (result.ideal.empty()) return scale;
  // Speeds (1 / time alone) at the timed frames, then linearly between them.
  auto speeds_at = [&](size_t k) {
    std::vector<double> v;
    for (double t : result.ideal[k].device_alone_ms) v.push_back(t > 0 ? 1.0 / t : 0.0);
    return v;
  };
  for (size_t f = 0; f < frames; ++f) {
    size_t k = 0;
    while (k + 1 < result.ideal.size() && result.ideal[k + 1].frame <= int(f)) ++k;
    std::vector<double> v = speeds_at(k);
    if (k + 1 < result.ideal.size() && result.ideal[k].frame < int(f)) {
      const double a = double(int(f) - result.ideal[k].frame) /
                       double(result.ideal[k + 1].frame - result.ideal[k].frame);
      const std::vector<double> next = speeds_at(k + 1);
      for (size_t d = 0; d < v.size() && d < next.size(); ++d) v[d] += (next[d] - v[d]) * a;
    }
    double sum = 0;
    for (double x : v) sum += x;
    for (double& x : v) x = sum > 0 ? x / sum : 0.0;
    scale.ideal_share.push_back(v);
  }
  return scale;
}

void write_timeline_svg(const std::string& path, const std::string& title,
                        const std::vector<FrameRecord>& frames,
                        const std::vector<std::string>& labels, const TimelineScale& scale) {
  const size_t n = frames.size(), devices = labels.size();
  if (n == 0) return;
  double t_max = scale.time_max_ms;  // warm-up frames above it are clipped at the top
  for (const auto& f : frames)
    for (const auto& d : f.devices)
      if (f.frame >= scale.warmup) t_max = std::max(t_max, d.time_ms);
  SvgChart chart(title, n);
  const int times = chart.add_panel("device time (ms)", t_max, 260);
  std::vector<std::pair<std::string, const char*>> legend;
  std::vector<std::vector<double>> shares(devices, std::vector<double>(n, 0.0));
  std::vector<const char*> colours;
  for (size_t d = 0; d < devices; ++d) {
    std::vector<double> t(n, NAN);
    for (size_t i = 0; i < n; ++i)
      if (d < frames[i].devices.size()) {
        t[i] = frames[i].devices[d].time_ms;
        shares[d][i] = frames[i].devices[d].work_share;
      }
    chart.line(times, t, device_colour(d));
    legend.emplace_back(labels[d], device_colour(d));
    colours.push_back(device_colour(d));
  }
  chart.legend(times, legend);
  const int share = chart.add_panel("work share", 1.0, 160);
  chart.stacked(share, shares, colours);
  // The ideal split (each device's share in proportion to its speed alone): dashed lines
  // at the boundaries between the stacked devices.
  for (size_t d = 0; d + 1 < devices && !scale.ideal_share.empty(); ++d) {
    std::vector<double> boundary(n, NAN);
    for (size_t i = 0; i < n && i < scale.ideal_share.size(); ++i) {
      double below = 0;
      for (size_t e = 0; e <= d && e < scale.ideal_share[i].size(); ++e)
        below += scale.ideal_share[i][e];
      if (!scale.ideal_share[i].empty()) boundary[i] = below;
    }
    chart.line(share, boundary, "#000", 0, true);
  }
  if (!scale.ideal_share.empty()) chart.legend(share, {{"ideal split (dashed)", "#000"}});
  if (scale.warmup > 0) chart.shade(0, std::min(double(scale.warmup), double(n - 1)), "warm-up");
  chart.write(path);
}

void write_comparison_svg(const std::string& path, const std::string& title,
                          const std::vector<ComparisonBar>& bars) {
  const double W = 980, left = 250, right = 170, bar_h = 16, gap = 6, head = 34;
  const double plot_w = W - left - right;
  struct Metric {
    const char* name;
    balance::Interval ComparisonBar::*value;
    double print_scale;  // the printed value is value * print_scale
    const char* format;
  };
  const Metric metrics[] = {
      {"efficiency (higher is better)", &ComparisonBar::efficiency, 1.0, "{:.3f}"},
      {"imbalance, % (lower is better)", &ComparisonBar::imbalance, 100.0, "{:.1f}"},
      {"frame time, ms (lower is better)", &ComparisonBar::frame_ms, 1.0, "{:.2f}"}};
  const double block = head + double(bars.size()) * (bar_h + gap) + 16;
  std::string svg = fmt::format(
      "<svg xmlns='http://www.w3.org/2000/svg' width='{}' height='{}' font-family='sans-serif' "
      "font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n"
      "<text x='20' y='22' font-size='15'>{}</text>\n",
      W, 40 + 3 * block, xml_escape(title));
  for (size_t m = 0; m < 3; ++m) {
    const double top = 40 + double(m) * block;
    double max_value = 0;
    for (const ComparisonBar& b : bars) {
      const balance::Interval& i = b.*metrics[m].value;
      if (i.valid) max_value = std::max({max_value, i.median, i.hi});
    }
    const double scale = nice_ceiling(max_value);
    svg += fmt::format("<text x='20' y='{}' font-weight='bold'>{}</text>\n", top + 18,
                       metrics[m].name);
    for (size_t k = 0; k < bars.size(); ++k) {
      const double y = top + head + double(k) * (bar_h + gap);
      const balance::Interval& i = bars[k].*metrics[m].value;
      const bool shown = i.valid && std::isfinite(i.median) && i.median >= 0;
      const double w = shown && scale > 0 ? plot_w * i.median / scale : 0;
      const bool whiskers =
          shown && scale > 0 && i.hi > i.lo && std::isfinite(i.lo) && std::isfinite(i.hi);
      const auto value = [&](double v) {
        return fmt::format(fmt::runtime(metrics[m].format), v * metrics[m].print_scale);
      };
      std::string label = shown ? value(i.median) : "-";
      if (whiskers) label += " [" + value(i.lo) + ", " + value(i.hi) + "]";
      double text_x = left + w + 5;
      svg += fmt::format(
          "<text x='{}' y='{}' text-anchor='end'>{}</text><rect x='{}' y='{}' width='{:.1f}' "
          "height='{}' fill='{}'/>",
          left - 8, y + 12, xml_escape(bars[k].name), left, y, w, bar_h, series_colour(k));
      if (whiskers) {
        const double x0 = left + plot_w * i.lo / scale, x1 = left + plot_w * i.hi / scale;
        svg += fmt::format(
            "<path d='M{0:.1f} {2:.1f}H{1:.1f}M{0:.1f} {3:.1f}V{4:.1f}M{1:.1f} {3:.1f}V{4:.1f}' "
            "stroke='black' stroke-width='1.5'/>",
            x0, x1, y + bar_h / 2, y + 3, y + bar_h - 3);
        text_x = std::max(text_x, x1 + 5);
      }
      svg += fmt::format("<text x='{:.1f}' y='{}'>{}</text>\n", text_x, y + 12, label);
    }
  }
  svg += "</svg>\n";
  write_file_atomically(path, svg);
}

void write_partition_png(const std::string& path, int width, int height,
                         const std::vector<std::vector<balance::WorkItem>>& rendered,
                         const Framebuffer* frame) {
  const bool over = frame && frame->width == width && frame->height == height;
  std::vector<uint8_t> rgb =
      over ? to_srgb8(*frame) : std::vector<uint8_t>(size_t(width) * size_t(height) * 3, 255);
  const float keep = over ? 0.55f : 0.0f;  // share of the picture under the colours
  for (size_t d = 0; d < rendered.size(); ++d) {
    unsigned r, g, b;
    std::sscanf(device_colour(d), "#%02x%02x%02x", &r, &g, &b);
    const float c[3] = {float(r), float(g), float(b)};
    for (const auto& item : rendered[d]) {
      if (item.view != 0) continue;
      const auto& q = item.rect;
      for (int y = std::max(0, q.y0); y < std::min(height, q.y1); ++y)
        for (int x = std::max(0, q.x0); x < std::min(width, q.x1); ++x) {
          const bool border = x == q.x0 || y == q.y0;
          const float k = border && q.width() > 2 && q.height() > 2 ? 0.6f : 1.0f;
          uint8_t* p = &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3];
          for (int ch = 0; ch < 3; ++ch)
            p[ch] =
                uint8_t(std::clamp(keep * float(p[ch]) + (1 - keep) * c[ch] * k, 0.0f, 255.0f));
        }
    }
  }
  write_png_rgb8(path, width, height, rgb);
}

void write_partition_svg(const std::string& path, const std::string& png_name,
                         const std::string& title, int width, int height,
                         const std::vector<std::string>& labels) {
  const double shown_w = std::max(640.0, double(width)), scale = shown_w / std::max(width, 1);
  const double shown_h = double(height) * scale, top = 34, legend_top = top + shown_h + 14;
  std::string svg = fmt::format(
      "<svg xmlns='http://www.w3.org/2000/svg' xmlns:xlink='http://www.w3.org/1999/xlink' "
      "width='{}' height='{}' font-family='sans-serif' font-size='12'>\n"
      "<rect width='100%' height='100%' fill='white'/>\n"
      "<text x='10' y='22' font-size='15'>{}</text>\n"
      "<image x='10' y='{}' width='{:.0f}' height='{:.0f}' href='{}' xlink:href='{}' "
      "style='image-rendering:pixelated'/>\n",
      shown_w + 20, legend_top + 18 * double(labels.size()) + 10, xml_escape(title), top, shown_w,
      shown_h, xml_escape(png_name), xml_escape(png_name));
  for (size_t d = 0; d < labels.size(); ++d)
    svg += fmt::format(
        "<rect x='10' y='{:.0f}' width='12' height='12' fill='{}'/><text x='28' y='{:.0f}'>{}"
        "</text>\n",
        legend_top + 18 * double(d), device_colour(d), legend_top + 10 + 18 * double(d),
        xml_escape(labels[d]));
  svg += "</svg>\n";
  write_file_atomically(path, svg);
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

}  // namespace multiray::study
