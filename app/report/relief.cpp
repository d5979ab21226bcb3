// Shaded reliefs of generated parts (issue 39 §2: every family documented with a picture).
#include "canvas.hpp"

#include "millnet/report/plots.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace millnet::report {

using namespace detail;

namespace {

constexpr int kCaptionH = 52, kPad = 10;

/// The largest "nice" length (1, 2, 5 × 10^k mm) not above a quarter of `span_mm`.
double scale_bar_mm(double span_mm) {
  double v = std::pow(10.0, std::floor(std::log10(span_mm / 4)));
  for (const double k : {5.0, 2.0})
    if (v * k <= span_mm / 4) return v * k;
  return v;
}

/// One tile into img's box [left, left+w) × [top, top+h): relief fitted, caption and scale bar below.
void draw_tile(cv::Mat& img, const ReliefTile& t, int left, int top, int w, int h) {
  const Eigen::Index ny = t.heights.rows(), nx = t.heights.cols();
  const double fit = std::min((w - 2.0 * kPad) / t.width_mm, (h - kCaptionH - 2.0 * kPad) / t.depth_mm);  // px per mm
  const int pw = std::max(1, static_cast<int>(t.width_mm * fit)), ph = std::max(1, static_cast<int>(t.depth_mm * fit));
  const int x0 = left + (w - pw) / 2, y0 = top + kPad;
  const double zmin = t.heights.minCoeff(), zspan = std::max(t.heights.maxCoeff() - zmin, 1e-9);
  const double dx = t.width_mm / static_cast<double>(std::max<Eigen::Index>(nx - 1, 1));
  const double dy = t.depth_mm / static_cast<double>(std::max<Eigen::Index>(ny - 1, 1));
  const double lx = -0.5, ly = 0.5, lz = std::sqrt(0.5);  // light from the upper left (−x, +y), 45° up
  for (int py = 0; py < ph; ++py)                         // O(pw · ph)
    for (int px = 0; px < pw; ++px) {
      const double fx = (px + 0.5) / pw * static_cast<double>(nx - 1);
      const double fy = (1 - (py + 0.5) / ph) * static_cast<double>(ny - 1);  // row 0 (smallest y) at the bottom
      const auto j = std::clamp<Eigen::Index>(static_cast<Eigen::Index>(fx), 0, nx - 1);
      const auto i = std::clamp<Eigen::Index>(static_cast<Eigen::Index>(fy), 0, ny - 1);
      const auto j1 = std::min(j + 1, nx - 1), i1 = std::min(i + 1, ny - 1);
      const double gx = (t.heights(i, j1) - t.heights(i, j)) / dx, gy = (t.heights(i1, j) - t.heights(i, j)) / dy;
      const double shade = std::max(0.0, (-gx * lx - gy * ly + lz) / std::sqrt(gx * gx + gy * gy + 1));
      const cv::Scalar c = viridis((t.heights(i, j) - zmin) / zspan);
      const double k = 0.35 + 0.65 * shade;
      img.at<cv::Vec3b>(y0 + py, x0 + px) = cv::Vec3b(
          cv::saturate_cast<uchar>(c[0] * k), cv::saturate_cast<uchar>(c[1] * k), cv::saturate_cast<uchar>(c[2] * k));
    }
  const int base = y0 + ph + 16;
  const double bar = scale_bar_mm(t.width_mm);
  line(img, {static_cast<double>(x0), base - 4.0}, {x0 + bar * fit, base - 4.0}, kBlack, 2);
  put_text(img, compact_number(bar) + " mm", {x0 + static_cast<int>(bar * fit) + 6, base}, kSmallFont, kTextGrey);
  const std::vector<std::string> lines = wrap(t.caption, kSmallFont, w - 8);
  for (std::size_t k = 0; k < lines.size() && k < 2; ++k)
    put_text(img, lines[k], {left + w / 2, base + 16 + 15 * static_cast<int>(k)}, kSmallFont, kBlack, HAlign::Center);
}

}  // namespace

void relief_sheet_png(const std::filesystem::path& path, const std::vector<ReliefTile>& tiles, const std::string& title,
                      int columns) {
  if (tiles.empty()) fail(path, "relief sheet: no tiles");
  if (columns < 1) fail(path, "relief sheet: columns must be ≥ 1");
  for (const ReliefTile& t : tiles)
    if (t.heights.rows() < 2 || t.heights.cols() < 2 || !t.heights.allFinite() || !(t.width_mm > 0) ||
        !(t.depth_mm > 0))
      fail(path, "relief sheet: tile '" + t.caption + "' needs ≥ 2×2 finite heights and a positive footprint");
  const int legend_w = 110, cols = std::min<int>(columns, static_cast<int>(tiles.size()));
  const int tile_w = (kWidth - legend_w) / cols, tile_h = tile_w + kCaptionH - 10;
  const int rows = (static_cast<int>(tiles.size()) + cols - 1) / cols;
  const int head = title_height(title);
  cv::Mat img(head + rows * tile_h + kPad, kWidth, CV_8UC3, kWhite);
  (void)detail::title(img, title);
  for (std::size_t k = 0; k < tiles.size(); ++k)
    draw_tile(img, tiles[k], static_cast<int>(k % static_cast<std::size_t>(cols)) * tile_w,
              head + static_cast<int>(k / static_cast<std::size_t>(cols)) * tile_h, tile_w, tile_h);
  colour_bar(img, kWidth - legend_w + 12, head + 20, 18, head + std::min(rows * tile_h, 420) - 20, 0, 1,
             "height / the part's relief (in its caption)", viridis);
  write_png(path, img);
}

}  // namespace millnet::report
