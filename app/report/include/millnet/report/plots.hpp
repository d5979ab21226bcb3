#pragma once
// millnet's pictures: PNG heat maps, curves, bar charts, tool-path plots and feed profiles.
//
// Every function takes plain data (no JSON), draws on a white ~1000 px wide canvas with titled,
// ticked and numbered axes, legends and a colour-blind-friendly palette (Okabe–Ito for series,
// viridis for maps), encodes PNG in memory and writes it atomically (millnet::write_file_atomic).
// Same data ⇒ same bytes. Text is drawn with OpenCV's Hershey font, which has no Unicode glyphs:
// common symbols are transliterated (α → "alpha", ² → "^2", ₃ → "3", ° → "deg", — → "-", …).
//
// Errors: bad input (empty data, sizes that do not match, non-finite values, x ≤ 0 on a log axis)
// and unwritable paths throw millnet::Error whose message starts with the output path.
//
// Each function returns the Layout of its (main) data area so that callers and tests can map data
// coordinates to pixels.
#include "millnet/pocket/geometry.hpp"
#include "millnet/pocket/toolpath.hpp"

#include "millnet/pocket/feedmap.hpp"

#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace millnet::report {

/// Where the data area of a picture sits, in pixels (x to the right, y down; the box is
/// [plot_left, plot_right) × [plot_top, plot_bottom)) and which data range it shows.
struct Layout {
  int width = 0, height = 0;  ///< whole image, px
  int plot_left = 0, plot_top = 0, plot_right = 0, plot_bottom = 0;
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;  ///< data range of the box edges
  bool log_x = false, log_y = false;
  /// Pixel position (x, y) of a data point (sub-pixel, not rounded).
  [[nodiscard]] std::array<double, 2> to_pixel(double x, double y) const;
};

/// A curve: y against x, drawn in the order given.
struct Series {
  std::string name;
  std::vector<double> xs, ys;
};

/// Values without their own x (one per category of a bar chart, or per sample of a profile).
struct NamedValues {
  std::string name;
  std::vector<double> values;
};

// ---------------------------------------------------------------------------------------------
// 1. Heat map of a grid (the 15×15 height grid of a part).

struct HeatMapOptions {
  /// Print each cell's value in the cell (black or white, whichever reads better on its colour).
  bool annotate = false;
  int annotate_decimals = 1;
  /// Physical extent {x_min, x_max, y_min, y_max} in mm of the grid's outer cell edges; without
  /// it the axes number the cells 1…cols (x) and 1…rows (y).
  std::optional<std::array<double, 4>> extent_mm;
  /// Colour range; default = [min, max] of the grid.
  std::optional<std::pair<double, double>> value_range;
  /// Tool paths drawn over the map (needs extent_mm; points in mm): cutting moves as solid lines,
  /// rapids dashed. Empty by default (the plain heat map is unchanged).
  std::vector<std::vector<std::array<double, 2>>> overlay_cuts;
  std::vector<std::vector<std::array<double, 2>>> overlay_rapids;
  /// Shares of the cells beyond value_range (robust_range): drawn in the end colours, and the colour
  /// bar says "≤ lo: p %" / "≥ hi: p %" under it. 0: nothing clipped at that end.
  double below_share = 0, above_share = 0;
};

/// A colour scale the few extreme cells of a map do not flatten (issue 37 §1: an Ra map whose
/// scale ran to 580 µm read as one colour): [min, max] of the grid, each end pulled in to the q
/// (1 − q) quantile by nearest rank when the cells beyond it would stretch the scale by more than
/// half the range between the two quantiles; with the shares of cells beyond each end. O(cells).
struct ColourRange {
  double lo = 0, hi = 0;
  double below_share = 0, above_share = 0;
};
[[nodiscard]] ColourRange robust_range(const Eigen::MatrixXd& grid, double q = 0.01);

/// Heat map of `grid` (rows = y, cols = x; row 0 = smallest y, drawn at the BOTTOM; col 0 = smallest
/// x, at the left), viridis colours with a colour bar labelled `units` (e.g. "height (mm)").
/// Layout: x in columns 0.5…cols+0.5 (cell c centred at c+1) or mm with extent_mm; y likewise.
Layout heat_map_png(const std::filesystem::path& path, const Eigen::MatrixXd& grid, const std::string& title,
                    const std::string& units, const HeatMapOptions& options = {});

/// One part of a relief sheet: its top surface as heights (rows = y from the smallest y, cols = x),
/// the footprint it spans, and a caption.
struct ReliefTile {
  Eigen::MatrixXd heights;
  double width_mm = 0, depth_mm = 0;  ///< footprint along x and y
  std::string caption;
};

/// A sheet of shaded reliefs (datasets/README.md's library pictures): each tile drawn to fit its
/// box, lit from the upper left, coloured by its height from its lowest (0) to its highest point (1)
/// (one colour bar; the caption gives the relief in mm), with a scale bar in mm per tile and a
/// caption of up to two lines; `columns` tiles per row. O(total cells + pixels).
void relief_sheet_png(const std::filesystem::path& path, const std::vector<ReliefTile>& tiles, const std::string& title,
                      int columns);

// ---------------------------------------------------------------------------------------------
// 2. Line plots (leave-one-out RMS against α; per-vector class probabilities).

struct Marker {
  double x = 0;
  std::string label;  ///< e.g. "chosen alpha = 0.25"
};

struct LinePlotOptions {
  bool log_x = false;
  bool log_y = false;
  bool show_points = false;                          ///< a dot at every data point
  std::optional<Marker> marker;                      ///< a dashed vertical line at marker.x with its label
  std::optional<std::pair<double, double>> y_range;  ///< fixed y range (e.g. {0, 1})
  std::optional<std::pair<double, double>> x_range;  ///< fixed x range
};

/// One or more curves on common axes, a legend below the plot when there is more than one series
/// (or any series has a name). Series with xs.size() != ys.size() or no points are errors.
Layout line_plot_png(const std::filesystem::path& path, const std::vector<Series>& series, const std::string& title,
                     const std::string& x_label, const std::string& y_label, const LinePlotOptions& options = {});

/// Several per-index curves (the paper's Fig. 6: x = stored vector 1…N, y = output of the true
/// class in filtration and verification), y in [0, 1] unless y_range says otherwise, points shown.
/// Each NamedValues is one curve; x = 1…values.size().
Layout multi_line_png(const std::filesystem::path& path, const std::vector<NamedValues>& curves,
                      const std::string& title, const std::string& x_label, const std::string& y_label,
                      std::optional<std::pair<double, double>> y_range = std::pair{0.0, 1.0});

// ---------------------------------------------------------------------------------------------
// 3. Grouped bar chart (per-strategy probabilities or totals, the paper's Fig. 8).

struct BarOptions {
  bool show_values = true;  ///< value above each bar when the bars are wide enough
  int value_decimals = -1;  ///< < 0: none when every value is whole (counts), else 2
  std::optional<std::pair<double, double>> y_range;
};

/// One group of bars per category (categories.size() groups), one bar per series in each group;
/// every series needs categories.size() values. Long category names are wrapped under their
/// group; when they would take more than four lines, groups are numbered and a key lists names.
Layout grouped_bar_png(const std::filesystem::path& path, const std::vector<std::string>& categories,
                       const std::vector<NamedValues>& series, const std::string& title, const std::string& y_label,
                       const BarOptions& options = {});

// ---------------------------------------------------------------------------------------------
// 4. Pocket and tool path (the seed's Figs. 17–20), 6. roughing levels.

struct PocketPlotOptions {
  /// Feed colour range (mm/min); default = [min, max] of the assigned (> 0) feeds.
  std::optional<std::pair<double, double>> feed_range;
  bool show_tool_points = true;
};

/// The pocket (boundary black, islands filled grey), tool points (small dots), the path's chains
/// (cuts coloured by their per-segment feed with a colour bar in mm/min; chains without feeds in
/// one colour), rapids between consecutive chains dashed, pre-drilled entries (Chain::predrill) as
/// circled crosses, equal aspect, mm axes, and `metrics` as a "name: value" text block.
/// Arcs (bulges) are drawn as arcs. Any of region/tool points/path may be empty.
Layout pocket_path_png(const std::filesystem::path& path, const pocket::Region& region,
                       const std::vector<pocket::Vec2>& tool_points, const pocket::Path2D& toolpath,
                       const std::string& title, const std::vector<std::pair<std::string, std::string>>& metrics = {},
                       const PocketPlotOptions& options = {});

/// Several disjoint regions on one picture (a roughing level whose material splits in pockets).
Layout pocket_path_png(const std::filesystem::path& path, const std::vector<pocket::Region>& regions,
                       const std::vector<pocket::Vec2>& tool_points, const pocket::Path2D& toolpath,
                       const std::string& title, const std::vector<std::pair<std::string, std::string>>& metrics = {},
                       const PocketPlotOptions& options = {});

/// A roughing level: the level's region(s) and path (tool points not drawn), titled
/// "<title> - level Z = <z> mm".
Layout level_png(const std::filesystem::path& path, const pocket::Region& region, const pocket::Path2D& toolpath,
                 double z_mm, const std::string& title,
                 const std::vector<std::pair<std::string, std::string>>& metrics = {},
                 const PocketPlotOptions& options = {});
Layout level_png(const std::filesystem::path& path, const std::vector<pocket::Region>& regions,
                 const pocket::Path2D& toolpath, double z_mm, const std::string& title,
                 const std::vector<std::pair<std::string, std::string>>& metrics = {},
                 const PocketPlotOptions& options = {});

// ---------------------------------------------------------------------------------------------
// 5. Profiles along the path (the seed's Fig. 14: engagement n3, feed, MRR).

/// One stacked panel: its y label and one or more series sampled at the common s.
struct Panel {
  std::string y_label;
  std::vector<NamedValues> series;
};

struct ProfileOptions {
  bool steps = false;  ///< draw each value as constant until the next s
  std::string x_label = "s along the path (mm)";
};

/// Stacked panels sharing the x axis `s` (mm along the path, non-decreasing); every series of
/// every panel needs s.size() values. Returns the Layout of the bottom panel.
Layout profile_png(const std::filesystem::path& path, const std::vector<double>& s, const std::vector<Panel>& panels,
                   const std::string& title, const ProfileOptions& options = {});

/// A pocket's feed profile along its path (the seed's Fig. 14): engagement, feed and material
/// removal rate over the path length, one panel each. Nothing is drawn for fewer than two pieces
/// (returns false).
bool feed_profile_png(const std::filesystem::path& path, const pocket::FeedProfile& profile, const std::string& title);

// ---------------------------------------------------------------------------------------------
/// The colours the pictures use, exposed for callers and tests: viridis at t ∈ [0, 1] (clamped)
/// as {r, g, b}.
[[nodiscard]] std::array<unsigned char, 3> viridis_rgb(double t);

}  // namespace millnet::report
