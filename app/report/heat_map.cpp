// Heat map of a height grid (issue 2 §1: "PNG of a grid (heat map) on request").
#include "canvas.hpp"

#include "millnet/report/plots.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace millnet::report {

using namespace detail;

namespace {

/// Checks the grid (≥ 1×1, finite) and the options; returns the colour scale's value range.
std::pair<double, double> checked_range(const std::filesystem::path& path, const Eigen::MatrixXd& grid,
                                        const HeatMapOptions& opt) {
  const Eigen::Index ny = grid.rows(), nx = grid.cols();
  if (ny < 1 || nx < 1)
    fail(path, "heat map: grid is " + std::to_string(ny) + "x" + std::to_string(nx) +
                   ", expected at least 1x1 (rows = y, cols = x)");
  if (!grid.allFinite()) fail(path, "heat map: grid has NaN or infinite values, expected finite heights");
  double lo = grid.minCoeff(), hi = grid.maxCoeff();
  if (opt.value_range) {
    lo = opt.value_range->first;
    hi = opt.value_range->second;
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo))
      fail(path, "heat map: value_range must be finite with min < max");
  }
  if (opt.extent_mm) {
    const auto& e = *opt.extent_mm;
    if (!std::isfinite(e[0]) || !std::isfinite(e[1]) || !std::isfinite(e[2]) || !std::isfinite(e[3]) ||
        !(e[1] > e[0]) || !(e[3] > e[2]))
      fail(path, "heat map: extent_mm must be finite {x_min, x_max, y_min, y_max} with min < max");
  }
  return {lo, hi};
}

/// Integer cell size {width, height} so that every cell is a crisp block of one colour. Cells stay
/// square unless the physical extent says otherwise (then the cell aspect follows the extent).
std::pair<int, int> cell_size(Eigen::Index nx, Eigen::Index ny, const HeatMapOptions& opt) {
  constexpr int kMaxPlot = 660;
  double aspect = static_cast<double>(ny) / static_cast<double>(nx);  // plot height / width
  if (opt.extent_mm) {
    const auto& e = *opt.extent_mm;
    aspect = (e[3] - e[2]) / (e[1] - e[0]);
  }
  const int cw = std::max(
      1, static_cast<int>(std::min<double>(static_cast<double>(kMaxPlot) / static_cast<double>(nx),
                                           static_cast<double>(kMaxPlot) / (aspect * static_cast<double>(nx)))));
  const int ch =
      std::max(1, static_cast<int>(std::lround(cw * aspect * static_cast<double>(nx) / static_cast<double>(ny))));
  return {cw, ch};
}

/// Each cell's value printed on it (white on dark colours), in a font shrunk to fit the cells; none
/// when it would be too small to read.
void annotate_cells(cv::Mat& img, const Eigen::MatrixXd& grid, double lo, double hi, int left, int top, int cw, int ch,
                    int decimals) {
  const Eigen::Index ny = grid.rows(), nx = grid.cols();
  const int dec = std::clamp(decimals, 0, 6);
  Font f = kSmallFont;
  auto label = [&](double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", dec, v);
    return std::string(buf);
  };
  int widest = 0;
  for (Eigen::Index r = 0; r < ny; ++r)
    for (Eigen::Index c = 0; c < nx; ++c) widest = std::max(widest, text_size(label(grid(r, c)), f).width);
  if (widest > cw - 4) f.scale *= static_cast<double>(cw - 4) / widest;
  if (!(f.scale >= 0.28 && text_size("0", f).height <= ch - 4)) return;
  for (Eigen::Index r = 0; r < ny; ++r) {
    for (Eigen::Index c = 0; c < nx; ++c) {
      const double v = grid(r, c);
      const auto rgb = viridis_rgb(hi > lo ? (v - lo) / (hi - lo) : 0.5);
      const double lum = 0.299 * rgb[0] + 0.587 * rgb[1] + 0.114 * rgb[2];
      const cv::Point centre(left + static_cast<int>(c) * cw + cw / 2,
                             top + static_cast<int>(ny - 1 - r) * ch + ch / 2);
      put_text(img, label(v), centre, f, lum < 128 ? kWhite : kBlack, HAlign::Center, VAlign::Middle);
    }
  }
}

/// The axes in mm over extent_mm, else in cells (one number per cell while they fit, nice steps
/// beyond); their labels into xl, yl.
void heat_axes(Eigen::Index nx, Eigen::Index ny, const HeatMapOptions& opt, Axis& x, Axis& y, AxesStyle& style,
               std::string& xl, std::string& yl) {
  style.grid = false;
  xl = "x (column)";
  yl = "y (row)";
  if (opt.extent_mm) {
    const auto& e = *opt.extent_mm;
    x.lo = e[0];
    x.hi = e[1];
    y.lo = e[2];
    y.hi = e[3];
    xl = "x (mm)";
    yl = "y (mm)";
  } else {
    x.lo = 0.5;
    x.hi = static_cast<double>(nx) + 0.5;
    y.lo = 0.5;
    y.hi = static_cast<double>(ny) + 0.5;
    style.x_target = nx <= 20 ? static_cast<int>(nx) : 8;
    style.y_target = ny <= 20 ? static_cast<int>(ny) : 8;
  }
}

/// Tool paths over a map in mm: rapids dashed, cuts in white over a thin black line so they read on
/// every colour. O(overlay points).
void draw_overlays(cv::Mat& img, const HeatMapOptions& opt, const Axis& x, const Axis& y) {
  auto to_px = [&](const std::vector<std::array<double, 2>>& pl) {
    std::vector<cv::Point2d> px;
    px.reserve(pl.size());
    for (const auto& p : pl) px.emplace_back(x.to_px(p[0]), y.to_px(p[1]));
    return px;
  };
  for (const auto& pl : opt.overlay_rapids) dashed_polyline(img, to_px(pl), cv::Scalar(60, 60, 230), 1, 6, 4);
  for (const auto& pl : opt.overlay_cuts) polyline(img, to_px(pl), kWhite, 1);
}

/// Under the colour bar, what its ends leave out: "≥ hi: p %" and "≤ lo: p %" (ASCII: ">=", "<=").
void clipped_note(cv::Mat& img, int bottom, double lo, double hi, const HeatMapOptions& opt) {
  auto pct = [](double share) {
    char b[32];
    std::snprintf(b, sizeof b, "%.1f %%", 100 * share);
    return std::string(b);
  };
  int y = bottom + 22;
  if (opt.above_share > 0 || opt.below_share > 0) {
    put_text(img, "scale clipped:", {kWidth - 12, y}, kTickFont, kTextGrey, HAlign::Right, VAlign::Middle);
    y += 16;
  }
  if (opt.above_share > 0) {
    put_text(img, ">= " + compact_number(hi, 4) + ": " + pct(opt.above_share) + " of cells", {kWidth - 12, y},
             kTickFont, kTextGrey, HAlign::Right, VAlign::Middle);
    y += 16;
  }
  if (opt.below_share > 0)
    put_text(img, "<= " + compact_number(lo, 4) + ": " + pct(opt.below_share) + " of cells", {kWidth - 12, y},
             kTickFont, kTextGrey, HAlign::Right, VAlign::Middle);
}

}  // namespace

ColourRange robust_range(const Eigen::MatrixXd& grid, double q) {
  std::vector<double> v;
  v.reserve(static_cast<std::size_t>(grid.size()));
  for (Eigen::Index i = 0; i < grid.size(); ++i)  // O(cells)
    if (std::isfinite(grid.data()[i])) v.push_back(grid.data()[i]);
  ColourRange r;
  if (v.empty()) return r;
  const auto n = v.size();
  auto rank = [&](double p) {  // nearest rank: the ceil(p·n)-th smallest
    const auto k =
        static_cast<std::size_t>(std::clamp(std::ceil(p * static_cast<double>(n)), 1.0, static_cast<double>(n))) - 1;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
  };
  const double qlo = rank(q), qhi = rank(1 - q);
  const double mn = *std::min_element(v.begin(), v.end()), mx = *std::max_element(v.begin(), v.end());
  r.lo = mn;
  r.hi = mx;
  const double core = qhi - qlo;
  if (!(core > 0)) return r;
  if (mx - qhi > 0.5 * core) r.hi = qhi;
  if (qlo - mn > 0.5 * core) r.lo = qlo;
  std::size_t below = 0, above = 0;
  for (const double x : v) below += x < r.lo ? 1U : 0U, above += x > r.hi ? 1U : 0U;
  r.below_share = static_cast<double>(below) / static_cast<double>(n);
  r.above_share = static_cast<double>(above) / static_cast<double>(n);
  return r;
}

Layout heat_map_png(const std::filesystem::path& path, const Eigen::MatrixXd& grid, const std::string& title_text,
                    const std::string& units, const HeatMapOptions& opt) {
  const auto [lo, hi] = checked_range(path, grid, opt);
  const Eigen::Index ny = grid.rows(), nx = grid.cols();
  const auto [cw, ch] = cell_size(nx, ny, opt);
  const int plot_w = cw * static_cast<int>(nx), plot_h = ch * static_cast<int>(ny);

  const int head = title_height(title_text);
  const int left = std::max(110, (kWidth - plot_w - 190) / 2 + 40);
  const int top = head + 10;
  cv::Mat img(top + plot_h + 90, kWidth, CV_8UC3, kWhite);
  title(img, title_text);

  // O(rows·cols) cells.
  for (Eigen::Index r = 0; r < ny; ++r) {
    for (Eigen::Index c = 0; c < nx; ++c) {
      const double v = grid(r, c);
      const double t = hi > lo ? (v - lo) / (hi - lo) : 0.5;
      const int x0 = left + static_cast<int>(c) * cw;
      const int y0 = top + static_cast<int>(ny - 1 - r) * ch;  // row 0 at the bottom
      cv::rectangle(img, cv::Point(x0, y0), cv::Point(x0 + cw - 1, y0 + ch - 1), viridis(t), cv::FILLED);
    }
  }
  if (opt.annotate) annotate_cells(img, grid, lo, hi, left, top, cw, ch, opt.annotate_decimals);

  Axis x, y;
  x.p0 = left;
  x.p1 = left + plot_w;
  y.p0 = top + plot_h;
  y.p1 = top;
  AxesStyle style;
  std::string xl, yl;
  heat_axes(nx, ny, opt, x, y, style, xl, yl);
  draw_axes(img, x, y, xl, yl, style);
  if (opt.extent_mm && (!opt.overlay_cuts.empty() || !opt.overlay_rapids.empty())) draw_overlays(img, opt, x, y);
  colour_bar(img, left + plot_w + 36, top, 26, top + plot_h, lo, hi, units, &viridis);
  clipped_note(img, top + plot_h, lo, hi, opt);
  write_png(path, img);
  return make_layout(img, x, y);
}

}  // namespace millnet::report
