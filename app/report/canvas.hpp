#pragma once
// Private drawing helpers shared by the report pictures (OpenCV stays inside app/report).
#include "millnet/report/plots.hpp"

#include <opencv2/core.hpp>

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace millnet::report::detail {

constexpr int kWidth = 1000;  ///< every picture is this wide, px

struct Font {
  double scale;
  int thickness;
};
inline constexpr Font kTitleFont{0.75, 2};
inline constexpr Font kLabelFont{0.55, 1};
inline constexpr Font kTickFont{0.47, 1};
inline constexpr Font kSmallFont{0.42, 1};

enum class HAlign { Left, Center, Right };
enum class VAlign { Top, Middle, Bottom };  ///< Bottom = the text's baseline

inline const cv::Scalar kWhite(255, 255, 255), kBlack(0, 0, 0), kGridGrey(228, 228, 228), kAxisGrey(90, 90, 90),
    kTextGrey(60, 60, 60);

/// Okabe–Ito colour-blind-safe palette (BGR), cycled for series i.
[[nodiscard]] cv::Scalar series_colour(std::size_t i);
/// Viridis at t ∈ [0, 1] (clamped), BGR.
[[nodiscard]] cv::Scalar viridis(double t);

/// UTF-8 → the ASCII the Hershey font can draw (α → "alpha", ² → "^2", unknown → "?").
[[nodiscard]] std::string ascii(std::string_view utf8);

/// Size of `text` (already ASCII or not: it is transliterated) in `font`; height excludes descent.
[[nodiscard]] cv::Size text_size(const std::string& text, Font font);
/// Draws text anchored at `at` with the given alignment.
void put_text(cv::Mat& img, const std::string& text, cv::Point at, Font font, const cv::Scalar& colour,
              HAlign h = HAlign::Left, VAlign v = VAlign::Bottom);
/// Draws text rotated 90° counter-clockwise (reads bottom to top), centred on `centre`.
void put_text_vertical(cv::Mat& img, const std::string& text, cv::Point centre, Font font, const cv::Scalar& colour);
/// Splits `text` at spaces into lines no wider than `max_width` px (a word longer than that gets a
/// line of its own).
[[nodiscard]] std::vector<std::string> wrap(const std::string& text, Font font, int max_width);

/// Anti-aliased primitives at sub-pixel precision (OpenCV's 4-bit fixed point "shift").
void line(cv::Mat& img, cv::Point2d a, cv::Point2d b, const cv::Scalar& colour, int thickness);
void polyline(cv::Mat& img, const std::vector<cv::Point2d>& pts, const cv::Scalar& colour, int thickness);
void dashed_polyline(cv::Mat& img, const std::vector<cv::Point2d>& pts, const cv::Scalar& colour, int thickness,
                     double dash_px, double gap_px);
void circle_at(cv::Mat& img, cv::Point2d c, double r, const cv::Scalar& colour, int thickness);  ///< -1 = filled
void fill_polygons(cv::Mat& img, const std::vector<std::vector<cv::Point2d>>& polys, const cv::Scalar& colour);

/// A data axis mapped onto a pixel interval [p0, p1] (p1 < p0 for y axes drawn upward).
struct Axis {
  double lo = 0, hi = 1;
  bool log = false;
  double p0 = 0, p1 = 1;
  [[nodiscard]] double to_px(double v) const;
};

/// "Nice" tick values (1, 2, 5 × 10^k) covering [lo, hi] with about `target` intervals.
[[nodiscard]] std::vector<double> nice_ticks(double lo, double hi, int target);
/// Step between nice ticks for [lo, hi].
[[nodiscard]] double nice_step(double lo, double hi, int target);
/// Expands [lo, hi] outward to multiples of the nice step (a zero-width range is widened first).
void nice_range(double& lo, double& hi, int target);
/// nice_range after a 3 % margin on each side (not crossing zero), so that no data point sits
/// on the frame.
void padded_nice_range(double& lo, double& hi, int target);
/// Decade range for a log axis: [10^floor(log10 lo), 10^ceil(log10 hi)].
void log_range(double& lo, double& hi);
/// Tick label with as many decimals as the step needs (no "-0").
[[nodiscard]] std::string tick_label(double v, double step);
/// Width of the widest of the tick labels of nice_ticks(lo, hi, target), px: the room a y axis
/// needs left of the frame for its numbers.
[[nodiscard]] int widest_tick_label(double lo, double hi, int target);
/// Compact number: up to `sig` significant digits, scientific outside [1e-3, 1e6).
[[nodiscard]] std::string compact_number(double v, int sig = 3);

/// Frame, light grid lines, ticks with numbers on both axes, axis labels. `x_labels` false leaves
/// out the x tick numbers and label (stacked panels). Returns the tick step used on y.
struct AxesStyle {
  bool x_numbers = true;
  bool x_ticks = true;  ///< false: no x ticks nor vertical grid lines (bar charts draw their own)
  bool grid = true;
  int x_target = 8, y_target = 6;
};
void draw_axes(cv::Mat& img, const Axis& x, const Axis& y, const std::string& x_label, const std::string& y_label,
               const AxesStyle& style = {});

/// A vertical colour bar at pixel box [left, left+w) × [top, bottom) for values [lo, hi] coloured
/// by `colour_of(t)`, ticks and numbers on its right, `label` rotated beside them.
void colour_bar(cv::Mat& img, int left, int top, int w, int bottom, double lo, double hi, const std::string& label,
                cv::Scalar (*colour_of)(double));

/// Legend entry kinds.
enum class LegendKind { Line, Dashed, Box, Dot, CircledCross };
struct LegendItem {
  std::string name;
  cv::Scalar colour;
  LegendKind kind = LegendKind::Line;
};
/// Lays the entries out in rows starting at (left, top) within `width`; returns the height used.
int legend(cv::Mat* img, const std::vector<LegendItem>& items, int left, int top, int width);

/// Title centred at the top (wrapped if long); returns the y below it.
int title(cv::Mat& img, const std::string& text);
/// Height the title needs.
[[nodiscard]] int title_height(const std::string& text);

/// Encodes PNG (fixed compression level: deterministic bytes) and writes atomically.
void write_png(const std::filesystem::path& path, const cv::Mat& img);

/// millnet::Error "<path>: <what>".
[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what);

/// Fills `layout` from two axes.
[[nodiscard]] Layout make_layout(const cv::Mat& img, const Axis& x, const Axis& y);

}  // namespace millnet::report::detail
