#pragma once
// The setup sheet of a job (issue 40 §3): one self-contained, printable HTML page for the operator —
// the part and stock from above and from the front with the work origin marked and dimensioned, the
// tool list (T, H, type, diameter, stick-out, holder, the reach each operation needs and whether the
// holder clears the part), per operation the strategy, cutting data, time and simulated result, and
// the program files with their SHA-256. Pictures are inline SVG (the top view's part shading an
// embedded PNG with its height legend); nothing is fetched. Same input ⇒ same bytes.
#include "millnet/simulate/zmap.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace millnet::report {

struct SetupTool {
  int number = 0, length_offset = 0;  ///< T and H
  std::string id, description, type;
  double diameter_mm = 0, corner_radius_mm = 0;
  double stickout_mm = 0;                               ///< 0: not stated
  double holder_diameter_mm = 0, holder_length_mm = 0;  ///< 0: not stated
  double reach_needed_mm = 0;                           ///< the most its operations need below the holder's face
  bool holder_checked = false;                          ///< stick-out and holder stated
  double holder_clearance_mm = 0;                       ///< stick-out − reach needed (< 0: collision)
  std::string note;  ///< e.g. "chosen for its reach: the configured … reaches 30 mm"
};

struct SetupOperation {
  int index = 0;  ///< 1-based
  std::string name, strategy;
  int tool_number = 0;
  double rpm = 0, feed_mm_min = 0;
  double stepover_mm = 0, step_down_mm = 0;  ///< 0: not applicable
  double time_min = 0;                       ///< kinematic, simulated from the job program
  double deepest_z_mm = 0;
  double max_depth_of_cut_mm = 0;
  bool beyond_flutes = false;  ///< the largest depth of cut exceeds the tool's flute length (drawn red)
  std::size_t cutting_rapids = 0;
  double left_after_mm = 0;  ///< the most stock above the design after it (what the next tool meets)
  std::string program;       ///< its own program file (for shops that run operations one by one)
};

struct SetupFile {
  std::string name, sha256;
  std::size_t bytes = 0;
};

struct SetupSheet {
  std::string title, part_file, post, material;
  // Frame (program coordinates, mm): origin X0 Y0 at the footprint's lower-left corner, Z0 the stock top.
  double stock_x0 = 0, stock_y0 = 0, stock_x1 = 0, stock_y1 = 0, stock_bottom_z = 0;
  double part_width = 0, part_depth = 0, part_top_z = 0, part_bottom_z = 0;
  /// A sawn blank (/rough/stock_squared false): its top, above Z0, that the first operation faces
  /// down to Z0; 0: a pre-squared block, its top Z0.
  double blank_top_z = 0;
  double deepest_z = 0;  ///< the lowest any tool goes
  /// The work origin (G54's X0 Y0) in this frame and its name (/machine/work_origin): the programs'
  /// X Y are these coordinates less it.
  double origin_x = 0, origin_y = 0;
  std::string origin_name = "part footprint's lower-left corner";
  /// The part's design heights on `grid` (NaN off the part), program frame; not owned (the page
  /// samples at most 480 × 480 of them for its picture).
  simulate::GridSpec grid;
  const std::vector<double>* heights = nullptr;
  std::vector<SetupTool> tools;
  std::vector<SetupOperation> operations;
  double total_time_min = 0;  ///< Σ of the operations' kinematic times
  int tool_changes = 0;       ///< T M6 in the job program
  double tool_change_s = 0;   ///< /machine/tool_change_s
  /// The job's cycle time: the operations' kinematic times and every tool change, min.
  [[nodiscard]] double cycle_time_min() const { return total_time_min + tool_changes * tool_change_s / 60; }
  /// The simulated job from the block: lines "gouge: none", "in spec: 99.2 % of 1,234 mm²", …
  std::vector<std::pair<std::string, std::string>> result;
  std::vector<SetupFile> files;
  std::vector<std::string> notes;
};

[[nodiscard]] std::string setup_sheet_html(const SetupSheet& sheet);
/// setup_sheet_html to `path`, atomically.
void write_setup_sheet(const std::filesystem::path& path, const SetupSheet& sheet);

}  // namespace millnet::report
