#include "study/svg_chart.h"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

#include "core/file_io.h"

namespace multiray::study {

double nice_ceiling(double x) {
  if (!(x > 0) || !std::isfinite(x)) return 1;
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * p >= x * (1 - 1e-12)) return m * p;
  return 10 * p;
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '\'':
        out += "&apos;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

const char* series_colour(size_t i) {
  static const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                   "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  return kColours[i % 10];
}

SvgChart::SvgChart(std::string title, size_t frames, double width)
    : title_(std::move(title)), frames_(frames), width_(width) {}

double SvgChart::x_of(double frame) const {
  const double plot_w = width_ - left_ - right_;
  return left_ + (frames_ > 1 ? frame / double(frames_ - 1) : 0.5) * plot_w;
}

double SvgChart::y_of(const Panel& p, double y) const {
  return p.top + p.height * (1 - std::clamp(y / p.y_max, 0.0, 1.0));
}

int SvgChart::add_panel(const std::string& y_label, double y_max, double height,
                        const std::string& tick_format) {
  const double gap = 45;
  const double top = panels_.empty() ? 40 : panels_.back().top + panels_.back().height + gap;
  panels_.push_back({top, height, nice_ceiling(y_max)});
  const Panel& p = panels_.back();
  for (int k = 0; k <= 4; ++k) {
    const double y = p.top + p.height * (1 - k / 4.0);
    body_ += fmt::format(
        "<line x1='{}' y1='{:.1f}' x2='{}' y2='{:.1f}' stroke='#ddd'/><text x='{}' y='{:.1f}' "
        "text-anchor='end'>{}</text>\n",
        left_, y, width_ - right_, y, left_ - 5, y + 4,
        fmt::format(fmt::runtime(tick_format), p.y_max * k / 4));
  }
  body_ += fmt::format(
      "<text x='15' y='{0:.1f}' transform='rotate(-90 15 {0:.1f})' "
      "text-anchor='middle'>{1}</text>\n",
      p.top + p.height / 2, xml_escape(y_label));
  return int(panels_.size()) - 1;
}

void SvgChart::line(int panel, const std::vector<double>& ys, const char* colour, size_t first,
                    bool dashed) {
  const Panel& p = panels_.at(size_t(panel));
  std::string pts;
  auto flush = [&] {
    if (!pts.empty())
      body_ +=
          fmt::format("<polyline fill='none' stroke='{}' stroke-width='1.3'{} points='{}'/>\n",
                      colour, dashed ? " stroke-dasharray='4,3'" : "", pts);
    pts.clear();
  };
  for (size_t i = 0; i < ys.size(); ++i) {
    if (!std::isfinite(ys[i])) {
      flush();
      continue;
    }
    pts += fmt::format("{:.1f},{:.1f} ", x_of(double(first + i)), y_of(p, ys[i]));
  }
  flush();
}

void SvgChart::reference(int panel, double y, const std::string& label) {
  const Panel& p = panels_.at(size_t(panel));
  const double yy = y_of(p, y);
  body_ += fmt::format(
      "<line x1='{}' y1='{:.1f}' x2='{}' y2='{:.1f}' stroke='black' stroke-dasharray='6,4'/>"
      "<text x='{}' y='{:.1f}' text-anchor='end'>{}</text>\n",
      left_, yy, width_ - right_, yy, width_ - right_, yy - 4, xml_escape(label));
}

void SvgChart::mark(double frame, const std::string& label) {
  if (panels_.empty()) return;
  const double x = x_of(frame);
  const Panel& last = panels_.back();
  body_ += fmt::format(
      "<line x1='{0:.1f}' y1='{1}' x2='{0:.1f}' y2='{2}' stroke='#999' stroke-dasharray='2,3'/>"
      "<text x='{0:.1f}' y='{3}' text-anchor='middle' fill='#666'>{4}</text>\n",
      x, panels_.front().top, last.top + last.height, panels_.front().top - 4, xml_escape(label));
}

void SvgChart::legend(int panel, const std::vector<std::pair<std::string, const char*>>& entries) {
  const Panel& p = panels_.at(size_t(panel));
  for (size_t i = 0; i < entries.size(); ++i)
    body_ += fmt::format(
        "<rect x='{}' y='{}' width='10' height='10' fill='{}'/><text x='{}' y='{}'>{}</text>\n",
        left_ + 10, p.top + 8 + 16 * double(i), entries[i].second, left_ + 25,
        p.top + 17 + 16 * double(i), xml_escape(entries[i].first));
}

void SvgChart::stacked(int panel, const std::vector<std::vector<double>>& layers,
                       const std::vector<const char*>& colours) {
  const Panel& p = panels_.at(size_t(panel));
  std::vector<double> base(frames_, 0.0);
  for (size_t k = 0; k < layers.size(); ++k) {
    std::string upper, lower;
    for (size_t i = 0; i < frames_ && i < layers[k].size(); ++i) {
      const double h = std::isfinite(layers[k][i]) ? layers[k][i] : 0.0;
      upper += fmt::format("{:.1f},{:.1f} ", x_of(double(i)), y_of(p, base[i] + h));
      lower = fmt::format("{:.1f},{:.1f} ", x_of(double(i)), y_of(p, base[i])) + lower;
      base[i] += h;
    }
    body_ += fmt::format("<polygon fill='{}' fill-opacity='0.8' points='{}{}'/>\n",
                         colours.at(k % colours.size()), upper, lower);
  }
}

void SvgChart::shade(double first, double last, const std::string& label) {
  if (panels_.empty() || last < first) return;
  const double x0 = x_of(first), x1 = x_of(last);
  for (const Panel& p : panels_)
    body_ += fmt::format(
        "<rect x='{:.1f}' y='{}' width='{:.1f}' height='{}' fill='#000' fill-opacity='0.07'/>\n",
        x0, p.top, std::max(x1 - x0, 1.0), p.height);
  body_ += fmt::format("<text x='{:.1f}' y='{}' fill='#666'>{}</text>\n", x0 + 3,
                       panels_.front().top - 4, xml_escape(label));
}

std::string SvgChart::frame_axis() const {
  if (panels_.empty() || frames_ == 0) return {};
  const Panel& last = panels_.back();
  const double step = nice_ceiling(std::max(1.0, double(frames_ - 1) / 8));
  std::string out;
  for (double f = 0; f <= double(frames_ - 1) + 1e-9; f += step)
    out += fmt::format(
        "<line x1='{0:.1f}' y1='{1}' x2='{0:.1f}' y2='{2}' stroke='#333'/>"
        "<text x='{0:.1f}' y='{3}' text-anchor='middle'>{4:g}</text>\n",
        x_of(f), last.top + last.height, last.top + last.height + 4, last.top + last.height + 16,
        f);
  return out;
}

std::string SvgChart::svg() const {
  const double height =
      panels_.empty() ? 80 : panels_.back().top + panels_.back().height + bottom_ + 12;
  return fmt::format(
      "<svg xmlns='http://www.w3.org/2000/svg' width='{0}' height='{1}' font-family='sans-serif' "
      "font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n"
      "<text x='{2}' y='20' font-size='15'>{3}</text>\n{4}{5}"
      "<text x='{6}' y='{7}' text-anchor='middle'>frame</text>\n</svg>\n",
      width_, height, left_, xml_escape(title_), body_, frame_axis(),
      left_ + (width_ - left_ - right_) / 2, height - 8);
}

void SvgChart::write(const std::string& path) const { write_file_atomically(path, svg()); }

}  // namespace multiray::study
