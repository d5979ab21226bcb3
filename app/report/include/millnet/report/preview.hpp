#pragma once
// HTML previews (issue 16 §2): one self-contained page per program that opens offline from file://
// in any browser — the part shaded, the stock outline, the tool paths (rapids dashed, cutting moves
// coloured by feed, or by program where a page shows several; plunges, ramps and helices marked),
// a slider + play button stepping through the program with the tool drawn at its position and the
// current G-code line shown, and, where a simulation ran, the machined surface coloured by deviation
// or Ra with a legend. Orbit / pan / zoom, top / front / iso views and a toggle per layer.
//
// three.js and its OrbitControls (Debian libjs-three, r111) and Chart.js (libjs-chart.js) are read
// from the Debian paths at run time (preview_assets()) and inlined; nothing is fetched by the page.
// Programs are taken as written (gcode::Written: the text and the program read back from it), so a
// page shows exactly what the file says and works for any file the reader accepts. Large jobs are decimated for display (path
// points and surface cells, see PreviewLimits) and the page says what was dropped.
//
// Frame: mm, Z up, the program's frame (Z = 0 at the stock top). Same input ⇒ same bytes.
// Errors: an unreadable program, a missing script file or an unwritable path throw millnet::Error
// naming the file.
#include "millnet/gcode/writer.hpp"
#include "millnet/simulate/zmap.hpp"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace millnet::report {

/// Colours the page draws with (also what tests look for in screenshots), 0xRRGGBB.
inline constexpr std::array<std::uint32_t, 5> kFeedRamp = {0x0072B2, 0x56B4E9, 0x009E73, 0xE69F00, 0xD55E00};
inline constexpr std::uint32_t kRapidColour = 0x777777;
inline constexpr std::uint32_t kEntryColour = 0xCC00CC;  ///< plunges, ramps, helices (magenta)
/// One colour per program where a page shows several (Okabe–Ito without black and yellow).
inline constexpr std::array<std::uint32_t, 6> kProgramColours = {0xD55E00, 0x0072B2, 0x009E73,
                                                                 0xCC79A7, 0xE69F00, 0x56B4E9};
/// Width of the page's side panel in CSS px; the 3D view fills the rest of the window to its right.
inline constexpr int kPanelWidthPx = 280;

/// What a step of the path is: the page colours and names them.
enum class StepKind : std::uint8_t { Rapid = 0, Cut = 1, Plunge = 2, Ramp = 3, Helix = 4 };

struct PreviewProgram {
  std::string name;  ///< shown in the legend (e.g. "zigzag", "s3 finish")
  /// The program as written: its text (the page shows its lines) and that text read back (the
  /// page draws its moves; Program::source_line ties each to its line). gcode::written() gives both.
  gcode::Written written;
};

/// A program from its text (a file's content): read with gcode::read, which throws millnet::Error
/// "<source>:<line>: …" on text it cannot read.
[[nodiscard]] PreviewProgram read_preview_program(std::string name, std::string text, std::string_view source);

struct PreviewTool {
  double diameter_mm = 6;
  double corner_radius_mm = 0;  ///< 0 flat, diameter/2 ball, between: bull nose
  std::string name;
};

/// A machined surface: z-map heights (rows = y, cols = x; cell (r, c) centred at
/// (x0 + (c + 0.5)·cell, y0 + (r + 0.5)·cell)) and a value per cell (deviation, Ra; NaN = none).
struct PreviewSurface {
  Eigen::MatrixXd z, value;
  double x0 = 0, y0 = 0, cell_mm = 1;
  double cell_y_mm = 0;                    ///< cell size along y; 0 ⇒ cell_mm (square cells)
  std::string layer = "machined surface";  ///< the layer's name (a height grid is not machined)
  std::string value_name = "deviation";    ///< legend title
  std::string units = "mm";
  /// Taken every `source_stride`-th row and column of a source_rows × source_cols grid (zmap_surface
  /// decimates as it copies: a page never shows more than its cell budget); the page notes it.
  std::size_t source_rows = 0, source_cols = 0, source_stride = 1;
};

struct PreviewLimits {
  std::size_t max_path_points = 200000;    ///< tessellated path points over all programs
  std::size_t max_surface_cells = 250000;  ///< surface cells shown
  std::size_t max_mesh_faces = 400000;     ///< part triangles shown
  double arc_step_deg = 6;                 ///< arc tessellation angle
  /// The whole page (three.js and OrbitControls, ~0.9 MB, included): its data is packed (gzip +
  /// base64, report/page_data.hpp) and the path and surface budgets shrink until it fits.
  std::size_t max_page_bytes = 5000000;
};

struct PreviewInput {
  std::string title;
  std::vector<PreviewProgram> programs;
  /// The part: V n×3 (mm, program frame), F m×3 vertex indices; empty = no part.
  Eigen::MatrixXd part_V;
  Eigen::MatrixXi part_F;
  /// Stock box {x_min, y_min, z_min, x_max, y_max, z_max}; none = the paths' bounding box.
  std::optional<std::array<double, 6>> stock;
  PreviewTool tool;
  std::optional<PreviewSurface> surface;
  std::vector<std::string> notes;  ///< lines shown under the title
  PreviewLimits limits;
};

/// The path of one program as the page draws it (after tessellation of arcs and decimation).
struct PreviewPath {
  std::vector<float> xyz;           ///< 3 per point
  std::vector<std::uint8_t> kind;   ///< StepKind of the move ending at each point
  std::vector<float> feed;          ///< mm/min (0 for rapids)
  std::vector<std::uint32_t> line;  ///< 1-based source line of the move ending at each point
  std::size_t moves = 0;            ///< moves in the program
  std::size_t points_before = 0;    ///< points before decimation
};

/// The indices 0 … n-1 kept when at most `budget` (≥ 2) are kept: all of them when n ≤ budget, else
/// evenly spaced ones that always include the first and the last. Sorted, no repeats.
[[nodiscard]] std::vector<std::size_t> decimate_indices(std::size_t n, std::size_t budget);

/// The kind of a move from `from` (plunge: Z goes down with XY fixed; ramp: a line down while XY
/// moves; helix: an arc that changes Z).
[[nodiscard]] StepKind step_kind(int motion, const std::array<double, 3>& from, const std::array<double, 3>& to);

/// The page's surface of a z-map coloured by its deviation from `design` (machined − design per
/// cell, NaN where the design is), every s-th row and column with s the smallest stride that keeps
/// at most `max_cells` cells (what the page shows: the copy never holds the whole grid).
/// O(max_cells).
[[nodiscard]] PreviewSurface zmap_surface(const simulate::ZMap& z, const std::vector<double>& design,
                                          std::size_t max_cells, const std::string& name, const std::string& units);

/// Tessellates a program into display points, keeping at most `max_points`.
[[nodiscard]] PreviewPath preview_path(const PreviewProgram& program, std::size_t max_points, double arc_step_deg);

/// The JSON the page embeds (numbers rounded to µm) within input.limits' point and cell budgets
/// (preview_html may shrink them to fit max_page_bytes): exposed for tests.
[[nodiscard]] std::string preview_data_json(const PreviewInput& input);

/// The whole page.
[[nodiscard]] std::string preview_html(const PreviewInput& input);

/// Writes the page atomically.
void write_preview(const std::filesystem::path& path, const PreviewInput& input);

/// A run's summary page: a table (header + rows, cells as text; a cell "link:TEXT|HREF" becomes a
/// link), per part a link to its preview, and bar charts (Chart.js) of named series over the parts.
struct SummaryChart {
  std::string title, y_label;
  std::vector<std::string> labels;
  std::vector<std::pair<std::string, std::vector<double>>> series;
};
struct SummaryPage {
  std::string title;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<SummaryChart> charts;
  std::vector<std::pair<std::string, std::string>> previews;  ///< (part, relative href of its page)
};
[[nodiscard]] std::string summary_html(const SummaryPage& page);
void write_summary_html(const std::filesystem::path& path, const SummaryPage& page);

/// The Debian script files inlined into the pages (env MILLNET_JS_DIR overrides /usr/share/javascript).
struct PreviewAssets {
  std::filesystem::path three, orbit_controls, chart;
};
[[nodiscard]] PreviewAssets preview_assets();

/// Text as HTML ("<" → "&lt;", quotes too): what every page of millnet writes text with.
[[nodiscard]] std::string escape_html(std::string_view s);
/// The script every page starts with: an error or unhandled rejection is written into the page
/// ("MILLNET_PAGE_ERROR: …"), so that a headless browser's DOM dump shows it.
[[nodiscard]] const char* error_trap_script();

}  // namespace millnet::report
