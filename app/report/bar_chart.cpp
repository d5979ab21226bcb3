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

namespace {

constexpr int kLine = 19;  ///< line height of category names and key entries, px

/// Checks every series (one finite value per category) and returns the values' range, 0 included
/// (bars start at 0).
std::pair<double, double> value_range(const std::filesystem::path& path, const std::vector<NamedValues>& series,
                                      std::size_t K) {
  double vmin = 0, vmax = 0;
  for (std::size_t s = 0; s < series.size(); ++s) {  // O(S·K)
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
  return {vmin, vmax};
}

/// The y axis's data range: opt.y_range, or the values' range with headroom for the value labels,
/// widened to nice ticks.
void y_range_of(const std::filesystem::path& path, double vmin, double vmax, const BarOptions& opt, Axis& y) {
  y.lo = vmin;
  y.hi = vmax;
  if (opt.y_range) {
    std::tie(y.lo, y.hi) = *opt.y_range;
    if (!std::isfinite(y.lo) || !std::isfinite(y.hi) || !(y.hi > y.lo))
      fail(path, "bar chart: y_range must be finite with min < max");
    return;
  }
  const double span = vmax - vmin;
  if (opt.show_values && span > 0) {
    if (vmax > 0) y.hi += 0.08 * span;
    if (vmin < 0) y.lo -= 0.08 * span;
  }
  nice_range(y.lo, y.hi, 6);
}

/// Category names: wrapped under their group (gw px wide), or numbered with a key when wrapping
/// needs more than 4 lines or a word does not fit. The key is laid out in two columns when its
/// longest entry fits in half the plot's width.
struct CategoryLabels {
  std::vector<std::vector<std::string>> wrapped;
  bool numbered = false;
  std::vector<std::string> key;
  int key_cols = 1, key_rows = 0;
  int cat_h = 0, key_h = 0;  ///< heights of the labels under the axis and of the key, px
};

CategoryLabels category_labels(const std::vector<std::string>& categories, double gw, int plot_w) {
  const std::size_t K = categories.size();
  CategoryLabels c;
  c.wrapped.resize(K);
  std::size_t max_lines = 0;
  for (std::size_t k = 0; k < K; ++k) {
    c.wrapped[k] = wrap(categories[k], kTickFont, static_cast<int>(gw) - 8);
    max_lines = std::max(max_lines, c.wrapped[k].size());
  }
  bool widest_fits = true;
  for (const auto& w : c.wrapped)
    for (const auto& l : w) widest_fits = widest_fits && text_size(l, kTickFont).width <= static_cast<int>(gw) - 2;
  c.numbered = max_lines > 4 || !widest_fits;
  if (c.numbered) {
    for (std::size_t k = 0; k < K; ++k) c.key.push_back(std::to_string(k + 1) + ": " + ascii(categories[k]));
    max_lines = 1;
  }
  c.cat_h = static_cast<int>(max_lines) * kLine + 12;
  if (c.numbered) {
    int kw = 0;
    for (const auto& s : c.key) kw = std::max(kw, text_size(s, kTickFont).width);
    c.key_cols = kw + 20 <= plot_w / 2 ? 2 : 1;
  }
  c.key_rows =
      c.numbered
          ? static_cast<int>((K + static_cast<std::size_t>(c.key_cols) - 1) / static_cast<std::size_t>(c.key_cols))
          : 0;
  c.key_h = c.numbered ? c.key_rows * kLine + 10 : 0;
  return c;
}

/// Decimals of the value labels: opt.value_decimals, else none when every value is whole.
int value_decimals(const std::vector<NamedValues>& series, const BarOptions& opt) {
  if (opt.value_decimals >= 0) return opt.value_decimals;
  bool whole = true;
  for (const auto& se : series)
    for (double v : se.values) whole = whole && v == std::round(v);
  return whole ? 0 : 2;
}

/// The bars (clipped to the plot box [left, right] × [top, bottom]), their value labels where they
/// fit, the group separators and the zero line. O(K·S).
void draw_bars(cv::Mat& img, const std::vector<NamedValues>& series, std::size_t K, const Axis& y, int left, int right,
               int top, int bottom, const BarOptions& opt) {
  const std::size_t S = series.size();
  const double gw = static_cast<double>(right - left) / static_cast<double>(K);
  const int decimals = value_decimals(series, opt);
  cv::Mat roi = img(cv::Rect(left + 1, top + 1, right - left - 1, bottom - top - 1));
  const double bw = gw * 0.78 / static_cast<double>(S);
  const double zero = y.to_px(std::clamp(0.0, y.lo, y.hi));
  for (std::size_t k = 0; k < K; ++k) {
    for (std::size_t s = 0; s < S; ++s) {
      const double v = series[s].values[k];
      const double x0 = left + gw * static_cast<double>(k) + gw * 0.11 + bw * static_cast<double>(s);
      const double py = y.to_px(std::clamp(v, y.lo, y.hi));
      const cv::Point a(cvRound(x0 + 1) - left - 1, cvRound(std::min(py, zero)) - top - 1);
      const cv::Point b(cvRound(x0 + bw - 1) - left - 1, cvRound(std::max(py, zero)) - top - 1);
      cv::rectangle(roi, a, b, series_colour(s), cv::FILLED);
      if (!opt.show_values) continue;
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.*f", std::min(decimals, 6), v);
      const int tw = text_size(buf, kSmallFont).width;
      if (tw > bw + 4) continue;
      const int cx = cvRound(x0 + bw / 2);
      if (v >= 0)
        put_text(img, buf, {cx, std::max(top + 14, cvRound(py) - 5)}, kSmallFont, kTextGrey, HAlign::Center,
                 VAlign::Bottom);
      else
        put_text(img, buf, {cx, std::min(bottom - 4, cvRound(py) + 5)}, kSmallFont, kTextGrey, HAlign::Center,
                 VAlign::Top);
    }
    // Group separators help the eye when there are several series.
    if (k > 0 && S > 1) {
      const double sx = left + gw * static_cast<double>(k);
      line(img, {sx, static_cast<double>(bottom)}, {sx, static_cast<double>(bottom + 6)}, kAxisGrey, 1);
    }
  }
  line(img, {static_cast<double>(left), zero}, {static_cast<double>(right), zero}, kBlack, 1);
}

/// The category labels under the groups, then the key (numbered labels); returns the y below them.
int draw_category_labels(cv::Mat& img, const CategoryLabels& c, std::size_t K, int left, int right, int bottom) {
  const double gw = static_cast<double>(right - left) / static_cast<double>(K);
  for (std::size_t k = 0; k < K; ++k) {
    const int cx = cvRound(left + gw * (static_cast<double>(k) + 0.5));
    if (c.numbered) {
      put_text(img, std::to_string(k + 1), {cx, bottom + 9}, kLabelFont, kBlack, HAlign::Center, VAlign::Top);
    } else {
      for (std::size_t l = 0; l < c.wrapped[k].size(); ++l)
        put_text(img, c.wrapped[k][l], {cx, bottom + 9 + static_cast<int>(l) * kLine}, kTickFont, kBlack,
                 HAlign::Center, VAlign::Top);
    }
  }
  int yy = bottom + c.cat_h;
  if (c.numbered) {
    const int colw = (right - left) / c.key_cols;
    for (std::size_t k = 0; k < K; ++k) {
      const int col = static_cast<int>(k) / c.key_rows, row = static_cast<int>(k) % c.key_rows;
      put_text(img, c.key[k], {left + col * colw, yy + row * kLine}, kTickFont, kTextGrey, HAlign::Left, VAlign::Top);
    }
    yy += c.key_h;
  }
  return yy;
}

}  // namespace

Layout grouped_bar_png(const std::filesystem::path& path, const std::vector<std::string>& categories,
                       const std::vector<NamedValues>& series, const std::string& title_text,
                       const std::string& y_label, const BarOptions& opt) {
  const std::size_t K = categories.size(), S = series.size();
  if (K == 0) fail(path, "bar chart: no categories given, expected at least one");
  if (S == 0) fail(path, "bar chart: no series given, expected at least one");
  const auto [vmin, vmax] = value_range(path, series, K);
  Axis x, y;
  x.lo = 0;
  x.hi = static_cast<double>(K);
  y_range_of(path, vmin, vmax, opt, y);

  const int left = 60 + widest_tick_label(y.lo, y.hi, 6), right = kWidth - 40;
  const double gw = static_cast<double>(right - left) / static_cast<double>(K);
  const CategoryLabels cats = category_labels(categories, gw, right - left);
  std::vector<LegendItem> items;
  if (S > 1 || !series[0].name.empty())
    for (std::size_t s = 0; s < S; ++s) items.push_back({series[s].name, series_colour(s), LegendKind::Box});
  const int legend_h = legend(nullptr, items, left, 0, right - left);

  const int top = title_height(title_text) + 6;
  const int bottom = top + 440;
  cv::Mat img(bottom + cats.cat_h + cats.key_h + (legend_h > 0 ? legend_h + 10 : 0) + 12, kWidth, CV_8UC3, kWhite);
  title(img, title_text);
  x.p0 = left;
  x.p1 = right;
  y.p0 = bottom;
  y.p1 = top;
  AxesStyle style;
  style.x_ticks = false;
  draw_axes(img, x, y, "", y_label, style);
  draw_bars(img, series, K, y, left, right, top, bottom, opt);
  const int yy = draw_category_labels(img, cats, K, left, right, bottom);
  if (legend_h > 0) legend(&img, items, left, yy, right - left);
  write_png(path, img);
  return make_layout(img, x, y);
}

}  // namespace millnet::report
