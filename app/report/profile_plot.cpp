// Profiles along the tool path on stacked panels (the seed's Fig. 14: engagement n3, feed, MRR).
#include "canvas.hpp"

#include "millnet/report/plots.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace millnet::report {

using namespace detail;

namespace {

/// Checks s (finite, non-decreasing) and every panel's series (one finite value per s); returns
/// each panel's y range, widened to nice ticks.
std::vector<std::pair<double, double>> panel_ranges(const std::filesystem::path& path, const std::vector<double>& s,
                                                    const std::vector<Panel>& panels) {
  if (s.empty()) fail(path, "profile plot: no samples (s is empty)");
  if (panels.empty()) fail(path, "profile plot: no panels given, expected at least one");
  for (std::size_t i = 0; i < s.size(); ++i) {  // O(samples)
    if (!std::isfinite(s[i])) fail(path, "profile plot: s[" + std::to_string(i) + "] is not finite");
    if (i > 0 && s[i] < s[i - 1])
      fail(path, "profile plot: s[" + std::to_string(i) + "] < s[" + std::to_string(i - 1) +
                     "], expected s non-decreasing (mm along the path)");
  }
  std::vector<std::pair<double, double>> yr(panels.size());
  for (std::size_t p = 0; p < panels.size(); ++p) {  // O(panels · series · samples)
    if (panels[p].series.empty()) fail(path, "profile plot: panel " + std::to_string(p) + " has no series");
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t k = 0; k < panels[p].series.size(); ++k) {
      const auto& v = panels[p].series[k].values;
      const std::string which = "profile plot: panel " + std::to_string(p) + " series " + std::to_string(k) + " (\"" +
                                panels[p].series[k].name + "\")";
      if (v.size() != s.size())
        fail(path, which + " has " + std::to_string(v.size()) + " values, expected one per s (" +
                       std::to_string(s.size()) + ")");
      for (double val : v) {
        if (!std::isfinite(val)) fail(path, which + " has a value that is not finite");
        lo = std::min(lo, val);
        hi = std::max(hi, val);
      }
    }
    padded_nice_range(lo, hi, 4);
    yr[p] = {lo, hi};
  }
  return yr;
}

bool has_legend(const Panel& p) { return p.series.size() > 1 || !p.series[0].name.empty(); }

/// One panel's curves (dots while there are few samples; steps when asked) inside its frame
/// [left, right] × [top, top + panel_h]. O(samples) per series.
void draw_panel_curves(cv::Mat& img, const std::vector<double>& s, const Panel& panel, const Axis& x, const Axis& y,
                       int left, int right, int top, int panel_h, bool steps) {
  cv::Mat roi = img(cv::Rect(left + 1, top + 1, right - left - 1, panel_h - 1));
  const bool dots = s.size() <= 150;
  for (std::size_t k = 0; k < panel.series.size(); ++k) {
    const auto& v = panel.series[k].values;
    std::vector<cv::Point2d> pts;
    auto at = [&](double sv, double val) { return cv::Point2d(x.to_px(sv) - left - 1, y.to_px(val) - top - 1); };
    for (std::size_t i = 0; i < s.size(); ++i) {
      pts.push_back(at(s[i], v[i]));
      if (steps && i + 1 < s.size()) pts.push_back(at(s[i + 1], v[i]));
    }
    polyline(roi, pts, series_colour(k), 2);
    if (dots || s.size() == 1)
      for (std::size_t i = 0; i < s.size(); ++i) circle_at(roi, at(s[i], v[i]), 2.6, series_colour(k), -1);
  }
}

}  // namespace

Layout profile_png(const std::filesystem::path& path, const std::vector<double>& s, const std::vector<Panel>& panels,
                   const std::string& title_text, const ProfileOptions& opt) {
  const std::vector<std::pair<double, double>> yr = panel_ranges(path, s, panels);
  Axis x;
  x.lo = s.front();
  x.hi = s.back();
  nice_range(x.lo, x.hi, 10);

  int yw = 0;
  for (const auto& [lo, hi] : yr) yw = std::max(yw, widest_tick_label(lo, hi, 4));
  const int left = 60 + yw, right = kWidth - 40;
  const int panel_h = panels.size() <= 3 ? 190 : 150;
  // Per panel: room above the frame for its legend when it has one.
  constexpr int kHeader = 30, kGap = 14;
  const int top0 = title_height(title_text);
  const int n = static_cast<int>(panels.size());
  int height = top0 + n * panel_h + (n - 1) * kGap + 70;
  for (const auto& p : panels) height += has_legend(p) ? kHeader : 0;
  cv::Mat img(height, kWidth, CV_8UC3, kWhite);
  title(img, title_text);
  x.p0 = left;
  x.p1 = right;

  Axis y;
  int top = top0 - kGap;
  for (int p = 0; p < n; ++p) {
    const Panel& panel = panels[static_cast<std::size_t>(p)];
    top += (p > 0 ? panel_h : 0) + kGap + (has_legend(panel) ? kHeader : 0);
    y = Axis{};
    y.lo = yr[static_cast<std::size_t>(p)].first;
    y.hi = yr[static_cast<std::size_t>(p)].second;
    y.p0 = top + panel_h;
    y.p1 = top;
    AxesStyle style;
    style.x_numbers = p == n - 1;
    style.x_target = 10;
    style.y_target = 4;
    draw_axes(img, x, y, opt.x_label, panel.y_label, style);
    draw_panel_curves(img, s, panel, x, y, left, right, top, panel_h, opt.steps);
    std::vector<LegendItem> items;
    if (has_legend(panel))
      for (std::size_t k = 0; k < panel.series.size(); ++k)
        items.push_back({panel.series[k].name, series_colour(k), LegendKind::Line});
    legend(&img, items, left, top - kHeader + 2, right - left);
  }
  write_png(path, img);
  return make_layout(img, x, y);
}

bool feed_profile_png(const std::filesystem::path& path, const pocket::FeedProfile& profile, const std::string& title) {
  std::vector<double> s, n3, f, mrr;
  for (const auto& p : profile.pieces) {  // O(pieces)
    s.push_back(p.s_mm);
    n3.push_back(p.engagement);
    f.push_back(p.feed);
    mrr.push_back(p.mrr_mm3_min);
  }
  if (s.size() < 2) return false;
  (void)profile_png(
      path, s,
      {{"engagement n3 (cells)", {{"n3", n3}}}, {"feed (mm/min)", {{"feed", f}}}, {"MRR (mm^3/min)", {{"MRR", mrr}}}},
      title, {.steps = true});
  return true;
}

}  // namespace millnet::report
