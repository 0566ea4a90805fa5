// Line charts over frames for the reports (SVG, viewable in any browser): panels stacked
// under a title that share the x axis (frame numbers), each with its own y axis rounded up
// to a "nice" maximum, lines, dashed reference lines, marked frames and a legend. One
// implementation for the frame-by-frame charts so that they all read alike.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace multiray::study {

// The smallest 1, 2 or 5 times a power of ten at or above x (x <= 0: 1).
double nice_ceiling(double x);

// `text` with &, <, >, ' and " escaped, for SVG text and attributes.
std::string xml_escape(const std::string& text);

// The colour of series i in every chart (10 distinct colours, then repeating).
const char* series_colour(size_t i);

class SvgChart {
 public:
  // A chart over frames 0..frames-1, `width` px wide.
  SvgChart(std::string title, size_t frames, double width = 900);

  // A panel below the previous ones, `height` px tall, y from 0 to nice_ceiling(y_max),
  // ticks printed with `tick_format` (an fmt format of one double). Returns its index.
  int add_panel(const std::string& y_label, double y_max, double height,
                const std::string& tick_format = "{:g}");
  // A polyline of ys[i] at frame first + i; non-finite values break the line.
  void line(int panel, const std::vector<double>& ys, const char* colour, size_t first = 0,
            bool dashed = false);
  // A dashed horizontal line at y with a label at its right end.
  void reference(int panel, double y, const std::string& label);
  // A dotted vertical line through every panel at `frame`, labelled above the first.
  void mark(double frame, const std::string& label);
  // Coloured boxes with names, in the top-left corner of `panel`.
  void legend(int panel, const std::vector<std::pair<std::string, const char*>>& entries);
  // Layers stacked from 0 upwards in `panel`: layers[k][i] is layer k's height at frame i
  // (heights, not tops), filled with colours[k].
  void stacked(int panel, const std::vector<std::vector<double>>& layers,
               const std::vector<const char*>& colours);
  // A grey band through every panel over frames [first, last], labelled at its top (e.g.
  // the warm-up that summaries leave out).
  void shade(double first, double last, const std::string& label);

  std::string svg() const;
  // Writes svg() atomically; throws IoError.
  void write(const std::string& path) const;

 private:
  struct Panel {
    double top, height, y_max;
  };
  double x_of(double frame) const;
  double y_of(const Panel& p, double y) const;

  // Frame numbers under the last panel: ticks every 1, 2 or 5 times a power of ten.
  std::string frame_axis() const;

  std::string title_;
  size_t frames_;
  double width_, left_ = 60, right_ = 20, bottom_ = 40;
  std::vector<Panel> panels_;
  std::string body_;
};

}  // namespace multiray::study
