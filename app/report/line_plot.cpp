// Line plots: the leave-one-out RMS against alpha (log x) with the chosen alpha marked, and the
// per-vector class-probability curves of filtration and verification (the paper's Fig. 6).
#include "canvas.hpp"

#include "millnet/report/plots.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace millnet::report {

using namespace detail;

namespace {

void check_range(const std::filesystem::path& path, const std::optional<std::pair<double, double>>& r, const char* what,
                 bool log) {
  if (!r) return;
  if (!std::isfinite(r->first) || !std::isfinite(r->second) || !(r->second > r->first))
    fail(path, std::string("line plot: ") + what + " must be finite with min < max");
  if (log && !(r->first > 0)) fail(path, std::string("line plot: ") + what + " must be > 0 on a log axis");
}

/// Checks every series (equal x and y counts, finite points, > 0 on a log axis) and the marker,
/// and returns the data's box {xmin, xmax, ymin, ymax}, the marker's x included.
std::array<double, 4> data_box(const std::filesystem::path& path, const std::vector<Series>& series,
                               const LinePlotOptions& opt) {
  double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin, ymin = xmin, ymax = -xmin;
  for (std::size_t k = 0; k < series.size(); ++k) {  // O(total points)
    const Series& s = series[k];
    const std::string which = "line plot: series " + std::to_string(k) + " (\"" + s.name + "\")";
    if (s.xs.size() != s.ys.size())
      fail(path, which + " has " + std::to_string(s.xs.size()) + " x values but " + std::to_string(s.ys.size()) +
                     " y values, expected equal counts");
    if (s.xs.empty()) fail(path, which + " has no points");
    for (std::size_t i = 0; i < s.xs.size(); ++i) {
      const double xv = s.xs[i], yv = s.ys[i];
      if (!std::isfinite(xv) || !std::isfinite(yv))
        fail(path, which + " point " + std::to_string(i) + " is not finite");
      if (opt.log_x && !(xv > 0))
        fail(path, which + " point " + std::to_string(i) + " has x = " + compact_number(xv) +
                       ", expected x > 0 on a log axis");
      if (opt.log_y && !(yv > 0))
        fail(path, which + " point " + std::to_string(i) + " has y = " + compact_number(yv) +
                       ", expected y > 0 on a log axis");
      xmin = std::min(xmin, xv);
      xmax = std::max(xmax, xv);
      ymin = std::min(ymin, yv);
      ymax = std::max(ymax, yv);
    }
  }
  if (opt.marker) {
    if (!std::isfinite(opt.marker->x) || (opt.log_x && !(opt.marker->x > 0)))
      fail(path, "line plot: marker x must be finite (and > 0 on a log axis)");
    xmin = std::min(xmin, opt.marker->x);
    xmax = std::max(xmax, opt.marker->x);
  }
  return {xmin, xmax, ymin, ymax};
}

/// The axes' data ranges: the options' ranges, else the data's widened to decades (log) or nice
/// ticks.
void axis_ranges(const std::array<double, 4>& box, const LinePlotOptions& opt, Axis& x, Axis& y) {
  x.log = opt.log_x;
  y.log = opt.log_y;
  x.lo = box[0];
  x.hi = box[1];
  y.lo = box[2];
  y.hi = box[3];
  if (opt.x_range)
    std::tie(x.lo, x.hi) = *opt.x_range;
  else if (x.log)
    log_range(x.lo, x.hi);
  else
    nice_range(x.lo, x.hi, 8);
  if (opt.y_range)
    std::tie(y.lo, y.hi) = *opt.y_range;
  else if (y.log)
    log_range(y.lo, y.hi);
  else
    padded_nice_range(y.lo, y.hi, 6);
}

/// The curves, clipped to the plot box (out-of-range parts are cut by the ROI), with dots at their
/// points where asked or where a series has one point. O(total points).
void draw_curves(cv::Mat& img, const std::vector<Series>& series, const Axis& x, const Axis& y, int left, int right,
                 int top, int bottom, bool show_points) {
  cv::Mat roi = img(cv::Rect(left + 1, top + 1, right - left - 1, bottom - top - 1));
  auto px = [&](double xv, double yv) { return cv::Point2d(x.to_px(xv) - left - 1, y.to_px(yv) - top - 1); };
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    std::vector<cv::Point2d> pts;
    pts.reserve(s.xs.size());
    for (std::size_t i = 0; i < s.xs.size(); ++i) pts.push_back(px(s.xs[i], s.ys[i]));
    polyline(roi, pts, series_colour(k), 2);
    if (show_points || pts.size() == 1) {
      // Dots shrink when the points crowd (hundreds of stored vectors) so the curve stays legible.
      const double spacing =
          static_cast<double>(right - left) / static_cast<double>(std::max<std::size_t>(1, pts.size()));
      const double r = std::clamp(spacing / 3.0, 1.6, 3.2);
      for (const auto& p : pts) circle_at(roi, p, r, series_colour(k), -1);
    }
  }
}

/// The marker: a dashed vertical line, a ring where each curve crosses it, its label at the top.
void draw_marker(cv::Mat& img, const Marker& marker, const std::vector<Series>& series, const Axis& x, const Axis& y,
                 int right, int top, int bottom) {
  const double mx = x.to_px(marker.x);
  dashed_polyline(img, {{mx, static_cast<double>(top)}, {mx, static_cast<double>(bottom)}}, kBlack, 1, 7, 5);
  // Where each curve crosses the marker: a ring, by linear interpolation in the drawn coordinates.
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    for (std::size_t i = 0; i + 1 < s.xs.size(); ++i) {
      const double a = x.to_px(s.xs[i]), b = x.to_px(s.xs[i + 1]);
      if ((mx - a) * (mx - b) > 0 || a == b) continue;
      const double t = (mx - a) / (b - a);
      const double py = y.to_px(s.ys[i]) + t * (y.to_px(s.ys[i + 1]) - y.to_px(s.ys[i]));
      circle_at(img, {mx, py}, 6, series_colour(k), 2);
      break;
    }
  }
  if (marker.label.empty()) return;
  const int w = text_size(marker.label, kLabelFont).width;
  const bool right_side = mx + 8 + w < right - 4;
  const cv::Point at(cvRound(right_side ? mx + 8 : mx - 8), top + 8);
  const cv::Rect box(right_side ? at.x - 3 : at.x - w - 3, at.y - 3, w + 6, text_size("Ag", kLabelFont).height + 10);
  cv::rectangle(img, box, kWhite, cv::FILLED);
  put_text(img, marker.label, at, kLabelFont, kBlack, right_side ? HAlign::Left : HAlign::Right, VAlign::Top);
}

}  // namespace

Layout line_plot_png(const std::filesystem::path& path, const std::vector<Series>& series,
                     const std::string& title_text, const std::string& x_label, const std::string& y_label,
                     const LinePlotOptions& opt) {
  if (series.empty()) fail(path, "line plot: no series given, expected at least one");
  check_range(path, opt.x_range, "x_range", opt.log_x);
  check_range(path, opt.y_range, "y_range", opt.log_y);
  Axis x, y;
  axis_ranges(data_box(path, series, opt), opt, x, y);

  // Left margin from the widest y number so that the rotated y label never overlaps it.
  int yw = widest_tick_label(y.lo, y.hi, 6);
  if (y.log) yw = std::max(yw, text_size("1e-10", kTickFont).width);
  const int left = 60 + yw, right = kWidth - 40;
  std::vector<LegendItem> items;
  const bool show_legend = series.size() > 1 || !series[0].name.empty();
  if (show_legend)
    for (std::size_t k = 0; k < series.size(); ++k)
      items.push_back({series[k].name, series_colour(k), LegendKind::Line});
  const int legend_h = legend(nullptr, items, left, 0, right - left);
  const int top = title_height(title_text) + 6;
  const int plot_h = 480;
  const int bottom = top + plot_h;
  cv::Mat img(bottom + 64 + (legend_h > 0 ? legend_h + 8 : 0) + 8, kWidth, CV_8UC3, kWhite);
  title(img, title_text);
  x.p0 = left;
  x.p1 = right;
  y.p0 = bottom;
  y.p1 = top;
  draw_axes(img, x, y, x_label, y_label);
  draw_curves(img, series, x, y, left, right, top, bottom, opt.show_points);
  if (opt.marker) draw_marker(img, *opt.marker, series, x, y, right, top, bottom);
  if (legend_h > 0) legend(&img, items, left, bottom + 66, right - left);
  write_png(path, img);
  return make_layout(img, x, y);
}

Layout multi_line_png(const std::filesystem::path& path, const std::vector<NamedValues>& curves,
                      const std::string& title_text, const std::string& x_label, const std::string& y_label,
                      std::optional<std::pair<double, double>> y_range) {
  std::vector<Series> series;
  series.reserve(curves.size());
  for (const auto& c : curves) {
    Series s{c.name, {}, c.values};
    s.xs.resize(c.values.size());
    for (std::size_t i = 0; i < c.values.size(); ++i) s.xs[i] = static_cast<double>(i + 1);
    series.push_back(std::move(s));
  }
  LinePlotOptions opt;
  opt.show_points = true;
  if (y_range) {  // 2 % headroom so that points at exactly 0 or 1 are not cut by the frame
    const double pad = 0.02 * (y_range->second - y_range->first);
    opt.y_range = std::pair{y_range->first - pad, y_range->second + pad};
  }
  std::size_t n = 0;
  for (const auto& c : curves) n = std::max(n, c.values.size());
  if (n > 0) opt.x_range = std::pair{0.5, static_cast<double>(n) + 0.5};
  return line_plot_png(path, series, title_text, x_label, y_label, opt);
}

}  // namespace millnet::report
