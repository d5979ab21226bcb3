// Grouped bar chart: per-strategy predicted probabilities or totals (the paper's Fig. 8).
#include "canvas.hpp"

#include "millnet/report/plots.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace millnet::report {

using namespace detail;

Layout grouped_bar_png(const std::filesystem::path& path, const std::vector<std::string>& categories,
                       const std::vector<NamedValues>& series, const std::string& title_text,
                       const std::string& y_label, const BarOptions& opt) {
  const std::size_t K = categories.size(), S = series.size();
  if (K == 0) fail(path, "bar chart: no categories given, expected at least one");
  if (S == 0) fail(path, "bar chart: no series given, expected at least one");
  double vmin = 0, vmax = 0;             // bars start at 0, so 0 is always in range
  for (std::size_t s = 0; s < S; ++s) {  // O(S·K)
    const auto& v = series[s].values;
    if (v.size() != K)
      fail(path, "bar chart: series " + std::to_string(s) + " (\"" + series[s].name + "\") has " +
                     std::to_string(v.size()) + " values, expected one per category (" + std::to_string(K) + ")");
    for (std::size_t k = 0; k < K; ++k) {
      if (!std::isfinite(v[k]))
        fail(path, "bar chart: series " + std::to_string(s) + " value " + std::to_string(k) + " is not finite");
      vmin = std::min(vmin, v[k]);
      vmax = std::max(vmax, v[k]);
    }
  }
  Axis x, y;
  x.lo = 0;
  x.hi = static_cast<double>(K);
  y.lo = vmin;
  y.hi = vmax;
  if (opt.y_range) {
    std::tie(y.lo, y.hi) = *opt.y_range;
    if (!std::isfinite(y.lo) || !std::isfinite(y.hi) || !(y.hi > y.lo))
      fail(path, "bar chart: y_range must be finite with min < max");
  } else {
    // Headroom for the value labels above the tallest bar.
    const double span = vmax - vmin;
    if (opt.show_values && span > 0) {
      if (vmax > 0) y.hi += 0.08 * span;
      if (vmin < 0) y.lo -= 0.08 * span;
    }
    nice_range(y.lo, y.hi, 6);
  }

  int yw = 0;
  {
    const double step = nice_step(y.lo, y.hi, 6);
    for (double v : nice_ticks(y.lo, y.hi, 6)) yw = std::max(yw, text_size(tick_label(v, step), kTickFont).width);
  }
  const int left = 60 + yw, right = kWidth - 40;
  const double gw = static_cast<double>(right - left) / static_cast<double>(K);

  // Category names: wrapped under their group, or numbered with a key when wrapping needs > 4 lines.
  constexpr int kLine = 19;
  std::vector<std::vector<std::string>> wrapped(K);
  std::size_t max_lines = 0;
  for (std::size_t k = 0; k < K; ++k) {
    wrapped[k] = wrap(categories[k], kTickFont, static_cast<int>(gw) - 8);
    max_lines = std::max(max_lines, wrapped[k].size());
  }
  bool widest_fits = true;
  for (const auto& w : wrapped)
    for (const auto& l : w) widest_fits = widest_fits && text_size(l, kTickFont).width <= static_cast<int>(gw) - 2;
  const bool numbered = max_lines > 4 || !widest_fits;
  std::vector<std::string> key;
  if (numbered) {
    for (std::size_t k = 0; k < K; ++k) key.push_back(std::to_string(k + 1) + ": " + ascii(categories[k]));
    max_lines = 1;
  }
  const int cat_h = static_cast<int>(max_lines) * kLine + 12;
  // The key is laid out in two columns when its longest entry fits in half the width.
  int key_cols = 1;
  if (numbered) {
    int kw = 0;
    for (const auto& s : key) kw = std::max(kw, text_size(s, kTickFont).width);
    key_cols = kw + 20 <= (right - left) / 2 ? 2 : 1;
  }
  const int key_rows =
      numbered ? static_cast<int>((K + static_cast<std::size_t>(key_cols) - 1) / static_cast<std::size_t>(key_cols))
               : 0;
  const int key_h = numbered ? key_rows * kLine + 10 : 0;

  std::vector<LegendItem> items;
  if (S > 1 || !series[0].name.empty())
    for (std::size_t s = 0; s < S; ++s) items.push_back({series[s].name, series_colour(s), LegendKind::Box});
  const int legend_h = legend(nullptr, items, left, 0, right - left);

  const int top = title_height(title_text) + 6;
  const int bottom = top + 440;
  cv::Mat img(bottom + cat_h + key_h + (legend_h > 0 ? legend_h + 10 : 0) + 12, kWidth, CV_8UC3, kWhite);
  title(img, title_text);
  x.p0 = left;
  x.p1 = right;
  y.p0 = bottom;
  y.p1 = top;
  AxesStyle style;
  style.x_ticks = false;
  draw_axes(img, x, y, "", y_label, style);

  int decimals = opt.value_decimals;
  if (decimals < 0) {
    bool whole = true;
    for (const auto& se : series)
      for (double v : se.values) whole = whole && v == std::round(v);
    decimals = whole ? 0 : 2;
  }
  cv::Mat roi = img(cv::Rect(left + 1, top + 1, right - left - 1, bottom - top - 1));
  const double bw = gw * 0.78 / static_cast<double>(S);
  const double zero = y.to_px(std::clamp(0.0, y.lo, y.hi));
  for (std::size_t k = 0; k < K; ++k) {  // O(K·S) bars
    for (std::size_t s = 0; s < S; ++s) {
      const double v = series[s].values[k];
      const double x0 = left + gw * static_cast<double>(k) + gw * 0.11 + bw * static_cast<double>(s);
      const double py = y.to_px(std::clamp(v, y.lo, y.hi));
      const cv::Point a(cvRound(x0 + 1) - left - 1, cvRound(std::min(py, zero)) - top - 1);
      const cv::Point b(cvRound(x0 + bw - 1) - left - 1, cvRound(std::max(py, zero)) - top - 1);
      cv::rectangle(roi, a, b, series_colour(s), cv::FILLED);
      if (opt.show_values) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.*f", std::min(decimals, 6), v);
        const int tw = text_size(buf, kSmallFont).width;
        if (tw <= bw + 4) {
          const int cx = cvRound(x0 + bw / 2);
          if (v >= 0)
            put_text(img, buf, {cx, std::max(top + 14, cvRound(py) - 5)}, kSmallFont, kTextGrey, HAlign::Center,
                     VAlign::Bottom);
          else
            put_text(img, buf, {cx, std::min(bottom - 4, cvRound(py) + 5)}, kSmallFont, kTextGrey, HAlign::Center,
                     VAlign::Top);
        }
      }
    }
    // Group separators help the eye when there are several series.
    if (k > 0 && S > 1) {
      const double sx = left + gw * static_cast<double>(k);
      line(img, {sx, static_cast<double>(bottom)}, {sx, static_cast<double>(bottom + 6)}, kAxisGrey, 1);
    }
  }
  line(img, {static_cast<double>(left), zero}, {static_cast<double>(right), zero}, kBlack, 1);

  // Category labels.
  for (std::size_t k = 0; k < K; ++k) {
    const int cx = cvRound(left + gw * (static_cast<double>(k) + 0.5));
    if (numbered) {
      put_text(img, std::to_string(k + 1), {cx, bottom + 9}, kLabelFont, kBlack, HAlign::Center, VAlign::Top);
    } else {
      for (std::size_t l = 0; l < wrapped[k].size(); ++l)
        put_text(img, wrapped[k][l], {cx, bottom + 9 + static_cast<int>(l) * kLine}, kTickFont, kBlack, HAlign::Center,
                 VAlign::Top);
    }
  }
  int yy = bottom + cat_h;
  if (numbered) {
    const int colw = (right - left) / key_cols;
    for (std::size_t k = 0; k < K; ++k) {
      const int col = static_cast<int>(k) / key_rows, row = static_cast<int>(k) % key_rows;
      put_text(img, key[k], {left + col * colw, yy + row * kLine}, kTickFont, kTextGrey, HAlign::Left, VAlign::Top);
    }
    yy += key_h;
  }
  if (legend_h > 0) legend(&img, items, left, yy, right - left);
  write_png(path, img);
  return make_layout(img, x, y);
}

}  // namespace millnet::report
