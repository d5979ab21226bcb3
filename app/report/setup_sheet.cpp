// The setup sheet (setup_sheet.hpp): tables and two inline SVG views, printable.
#include "millnet/report/setup_sheet.hpp"

#include "millnet/report/page_data.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/report/preview.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace millnet::report {
namespace {

std::string num(double v, int decimals) {
  if (!std::isfinite(v)) return "–";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, v == 0 ? 0.0 : v);  // no "-0.0"
  std::string s = b;
  if (s == "-0" || s.rfind("-0.", 0) == 0) {
    if (s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  }
  return s;
}
std::string esc(const std::string& s) { return escape_html(s); }

/// The colour map's colour at t in [0, 1] as "#rrggbb" (OpenCV's viridis, the picture's own).
std::string viridis_hex(double t) {
  cv::Mat one(1, 1, CV_8UC1, cv::Scalar(static_cast<int>(std::lround(std::clamp(t, 0.0, 1.0) * 255))));
  cv::Mat bgr;
  cv::applyColorMap(one, bgr, cv::COLORMAP_VIRIDIS);
  const cv::Vec3b c = bgr.at<cv::Vec3b>(0, 0);
  char b[8];
  std::snprintf(b, sizeof b, "#%02x%02x%02x", c[2], c[1], c[0]);
  return b;
}

/// The part's heights sampled to at most `max_px` a side, coloured by height (transparent off the
/// part), as a PNG data URI; lo/hi receive the height range.
std::string part_png(const SetupSheet& s, int max_px, double& lo, double& hi, std::size_t& step) {
  const simulate::GridSpec& g = s.grid;
  const std::vector<double>& h = *s.heights;
  step = std::max<std::size_t>(
      1, (std::max(g.nx, g.ny) + static_cast<std::size_t>(max_px) - 1) / static_cast<std::size_t>(max_px));
  const std::size_t w = (g.nx + step - 1) / step, r = (g.ny + step - 1) / step;
  lo = std::numeric_limits<double>::infinity();
  hi = -lo;
  for (const double z : h)  // O(cells)
    if (!std::isnan(z)) lo = std::min(lo, z), hi = std::max(hi, z);
  if (!(lo <= hi)) lo = hi = 0;
  cv::Mat grey(static_cast<int>(r), static_cast<int>(w), CV_8UC1, cv::Scalar(0));
  cv::Mat alpha(static_cast<int>(r), static_cast<int>(w), CV_8UC1, cv::Scalar(0));
  for (std::size_t py = 0; py < r; ++py)  // O(picture pixels): the cell at each pixel's corner
    for (std::size_t px = 0; px < w; ++px) {
      const double z = h[py * step * g.nx + px * step];
      if (std::isnan(z)) continue;
      const int row = static_cast<int>(r - 1 - py);  // image rows run down, Y up
      grey.at<uchar>(row, static_cast<int>(px)) =
          static_cast<uchar>(std::lround(hi > lo ? (z - lo) / (hi - lo) * 255 : 128));
      alpha.at<uchar>(row, static_cast<int>(px)) = 255;
    }
  cv::Mat bgr, bgra;
  cv::applyColorMap(grey, bgr, cv::COLORMAP_VIRIDIS);
  std::vector<cv::Mat> ch;
  cv::split(bgr, ch);
  ch.push_back(alpha);
  cv::merge(ch, bgra);
  std::vector<uchar> png;
  cv::imencode(".png", bgra, png, {cv::IMWRITE_PNG_COMPRESSION, 6});
  return "data:image/png;base64," + base64(std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

/// The view's frame: mm → px, y up.
struct View {
  double x0, y1, scale;
  [[nodiscard]] double px(double x) const { return (x - x0) * scale; }
  [[nodiscard]] double py(double y) const { return (y1 - y) * scale; }
};

void origin_marker(std::ostringstream& o, const View& v, double at_x, double at_y, double len_mm,
                   const char* second_axis) {
  const double x = v.px(at_x), y = v.py(at_y), l = len_mm * v.scale;
  o << "<g class=\"origin\"><line x1=\"" << num(x, 1) << "\" y1=\"" << num(y, 1) << "\" x2=\"" << num(x + l, 1)
    << "\" y2=\"" << num(y, 1) << "\" stroke=\"#c00\" stroke-width=\"2\" marker-end=\"url(#arrow-x)\"/>"
    << "<line x1=\"" << num(x, 1) << "\" y1=\"" << num(y, 1) << "\" x2=\"" << num(x, 1) << "\" y2=\"" << num(y - l, 1)
    << "\" stroke=\"#080\" stroke-width=\"2\" marker-end=\"url(#arrow-y)\"/>"
    << "<text x=\"" << num(x + l + 3, 1) << "\" y=\"" << num(y + 4, 1) << "\" fill=\"#c00\">X</text>"
    << "<text x=\"" << num(x - 4, 1) << "\" y=\"" << num(y - l - 4, 1) << "\" fill=\"#080\">" << second_axis
    << "</text><circle cx=\"" << num(x, 1) << "\" cy=\"" << num(y, 1)
    << "\" r=\"5\" fill=\"#fff\" stroke=\"#000\" stroke-width=\"1.5\"/><path d=\"M" << num(x, 1) << ' ' << num(y - 5, 1)
    << " A5 5 0 0 1 " << num(x + 5, 1) << ' ' << num(y, 1) << " L" << num(x, 1) << ' ' << num(y, 1) << " Z M"
    << num(x, 1) << ' ' << num(y + 5, 1) << " A5 5 0 0 1 " << num(x - 5, 1) << ' ' << num(y, 1) << " L" << num(x, 1)
    << ' ' << num(y, 1) << " Z\" fill=\"#000\"/></g>";
}

const char* kDefs =
    "<defs><marker id=\"arrow-x\" markerWidth=\"8\" markerHeight=\"8\" refX=\"6\" refY=\"4\" orient=\"auto\">"
    "<path d=\"M0,0 L8,4 L0,8 Z\" fill=\"#c00\"/></marker><marker id=\"arrow-y\" markerWidth=\"8\" "
    "markerHeight=\"8\" refX=\"6\" refY=\"4\" orient=\"auto\"><path d=\"M0,0 L8,4 L0,8 Z\" fill=\"#080\"/></marker>"
    "</defs>";

/// From above: the stock, the part coloured by height, the origin, the sizes, the height legend.
void top_view(std::ostringstream& o, const SetupSheet& s) {
  const double wmm = s.stock_x1 - s.stock_x0, dmm = s.stock_y1 - s.stock_y0;
  const double scale = std::min(440 / std::max(wmm, 1e-9), 360 / std::max(dmm, 1e-9));
  const double pad = 40;
  const View v{s.stock_x0 - pad / scale, s.stock_y1 + pad / scale, scale};
  const double W = wmm * scale + 2 * pad + 90, H = dmm * scale + 2 * pad + 10;
  o << "<svg id=\"top-view\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(W, 0) << "\" height=\"" << num(H, 0)
    << "\" viewBox=\"0 0 " << num(W, 0) << ' ' << num(H, 0) << "\">" << kDefs;
  o << "<rect x=\"" << num(v.px(s.stock_x0), 1) << "\" y=\"" << num(v.py(s.stock_y1), 1) << "\" width=\""
    << num(wmm * scale, 1) << "\" height=\"" << num(dmm * scale, 1)
    << "\" fill=\"#e8e8e8\" stroke=\"#333\" stroke-width=\"1.5\"/>";
  double lo = 0, hi = 0;
  if (s.heights != nullptr && !s.heights->empty()) {
    std::size_t step = 1;
    const std::string uri = part_png(s, 480, lo, hi, step);
    const simulate::GridSpec& g = s.grid;
    const double gw = g.cell * static_cast<double>(g.nx), gd = g.cell * static_cast<double>(g.ny);
    o << "<image id=\"part-picture\" x=\"" << num(v.px(g.x0), 1) << "\" y=\"" << num(v.py(g.y0 + gd), 1)
      << "\" width=\"" << num(gw * scale, 1) << "\" height=\"" << num(gd * scale, 1)
      << "\" preserveAspectRatio=\"none\" style=\"image-rendering:pixelated\" href=\"" << uri << "\"/>";
    // The legend: the colour ramp with the lowest and highest part Z.
    const double lx = v.px(s.stock_x1) + 24, ly = v.py(s.stock_y1), lh = std::min(160.0, dmm * scale);
    o << "<linearGradient id=\"ramp\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\">";
    for (int k = 0; k <= 8; ++k)
      o << "<stop offset=\"" << num(k / 8.0, 3) << "\" stop-color=\"" << viridis_hex(k / 8.0) << "\"/>";
    o << "</linearGradient><rect x=\"" << num(lx, 1) << "\" y=\"" << num(ly, 1) << "\" width=\"14\" height=\""
      << num(lh, 1) << "\" fill=\"url(#ramp)\" stroke=\"#333\"/><text x=\"" << num(lx + 18, 1) << "\" y=\""
      << num(ly + 10, 1) << "\">Z " << num(hi, 2) << "</text><text x=\"" << num(lx + 18, 1) << "\" y=\""
      << num(ly + lh, 1) << "\">Z " << num(lo, 2) << "</text><text x=\"" << num(lx, 1) << "\" y=\""
      << num(ly + lh + 16, 1) << "\">part height</text>";
  }
  origin_marker(o, v, s.origin_x, s.origin_y, std::clamp(0.15 * std::min(wmm, dmm), 5.0, 30.0), "Y");
  o << "<text x=\"" << num(v.px((s.stock_x0 + s.stock_x1) / 2), 1) << "\" y=\"" << num(v.py(s.stock_y0) + 20, 1)
    << "\" text-anchor=\"middle\">stock X " << num(wmm, 1) << " mm (X " << num(s.stock_x0 - s.origin_x, 1) << " … "
    << num(s.stock_x1 - s.origin_x, 1) << ")</text><text transform=\"translate(" << num(v.px(s.stock_x0) - 12, 1) << ','
    << num(v.py((s.stock_y0 + s.stock_y1) / 2), 1) << ") rotate(-90)\" text-anchor=\"middle\">stock Y " << num(dmm, 1)
    << " mm (Y " << num(s.stock_y0 - s.origin_y, 1) << " … " << num(s.stock_y1 - s.origin_y, 1) << ")</text></svg>";
}

/// From the front (looking along +Y): the stock, the part's silhouette, Z0 and the deepest tool Z.
void front_view(std::ostringstream& o, const SetupSheet& s) {
  const double wmm = s.stock_x1 - s.stock_x0, hmm = std::max(s.blank_top_z - s.stock_bottom_z, 1e-9);
  const double scale = std::min(440 / std::max(wmm, 1e-9), 220 / hmm);
  const double pad = 40;
  const View v{s.stock_x0 - pad / scale, s.blank_top_z + pad / scale, scale};
  const double W = wmm * scale + 2 * pad + 150, H = hmm * scale + 2 * pad;
  o << "<svg id=\"front-view\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(W, 0) << "\" height=\""
    << num(H, 0) << "\" viewBox=\"0 0 " << num(W, 0) << ' ' << num(H, 0) << "\">" << kDefs;
  o << "<rect x=\"" << num(v.px(s.stock_x0), 1) << "\" y=\"" << num(v.py(s.blank_top_z), 1) << "\" width=\""
    << num(wmm * scale, 1) << "\" height=\"" << num(hmm * scale, 1)
    << "\" fill=\"#e8e8e8\" stroke=\"#333\" stroke-width=\"1.5\"/>";
  if (s.blank_top_z > 0)  // the sawn top the facing takes off
    o << "<rect id=\"facing-layer\" x=\"" << num(v.px(s.stock_x0), 1) << "\" y=\"" << num(v.py(s.blank_top_z), 1)
      << "\" width=\"" << num(wmm * scale, 1) << "\" height=\"" << num(s.blank_top_z * scale, 1)
      << "\" fill=\"#f2c48d\" stroke=\"#333\"/><text x=\"" << num(v.px(s.stock_x1) + 12, 1) << "\" y=\""
      << num(v.py(s.blank_top_z) - 4, 1) << "\">sawn top Z " << num(s.blank_top_z, 2) << ", faced to Z0</text>";
  if (s.heights != nullptr && !s.heights->empty()) {  // the silhouette: per column, the highest point
    const simulate::GridSpec& g = s.grid;
    const std::size_t step = std::max<std::size_t>(1, g.nx / 600);
    std::ostringstream d;
    bool open = false;
    for (std::size_t ix = 0; ix < g.nx; ix += step) {  // O(cells / step)
      double top = -std::numeric_limits<double>::infinity();
      for (std::size_t iy = 0; iy < g.ny; ++iy) {
        const double z = (*s.heights)[iy * g.nx + ix];
        if (!std::isnan(z)) top = std::max(top, z);
      }
      if (!std::isfinite(top)) continue;
      d << (open ? " L" : "M") << num(v.px(g.x(ix)), 1) << ' ' << num(v.py(top), 1);
      open = true;
    }
    if (open)
      o << "<path id=\"part-silhouette\" d=\"" << d.str() << " L" << num(v.px(s.part_width), 1) << ' '
        << num(v.py(s.part_bottom_z), 1) << " L" << num(v.px(0), 1) << ' ' << num(v.py(s.part_bottom_z), 1)
        << " Z\" fill=\"#3b528b\" stroke=\"#1f2f55\"/>";
  }
  const double xr = v.px(s.stock_x1) + 8;
  o << "<line x1=\"" << num(v.px(s.stock_x0) - 10, 1) << "\" y1=\"" << num(v.py(s.deepest_z), 1) << "\" x2=\""
    << num(xr, 1) << "\" y2=\"" << num(v.py(s.deepest_z), 1)
    << "\" stroke=\"#c00\" stroke-dasharray=\"6 4\"/><text x=\"" << num(xr + 4, 1) << "\" y=\""
    << num(v.py(s.deepest_z) + 4, 1) << "\" fill=\"#c00\">deepest tool Z " << num(s.deepest_z, 2)
    << (std::abs(v.py(s.deepest_z) - v.py(s.stock_bottom_z)) < 14 ? " = part base" : "") << "</text><text x=\""
    << num(xr + 4, 1) << "\" y=\"" << num(v.py(0) + 4, 1) << "\">Z0 = stock top</text>";
  if (std::abs(v.py(s.deepest_z) - v.py(s.stock_bottom_z)) >= 14)  // its own label where there is room
    o << "<text x=\"" << num(xr + 4, 1) << "\" y=\"" << num(v.py(s.stock_bottom_z) + 4, 1) << "\">Z "
      << num(s.stock_bottom_z, 2) << " part base</text>";
  origin_marker(o, v, s.origin_x, 0, std::clamp(0.15 * std::min(wmm, hmm), 4.0, 20.0), "Z");
  o << "</svg>";
}

constexpr const char* kStyle =
    "body{font:13px/1.35 system-ui,sans-serif;margin:18px;color:#111}h1{font-size:20px;margin:0 0 4px}"
    "h2{font-size:15px;margin:18px 0 6px;border-bottom:1px solid #999}table{border-collapse:collapse;margin:4px 0}"
    "td,th{border:1px solid #bbb;padding:3px 7px;text-align:left;vertical-align:top}th{background:#eee}"
    "td.n{text-align:right;font-variant-numeric:tabular-nums}.bad{color:#b00;font-weight:bold}.ok{color:#060}"
    ".views{display:flex;flex-wrap:wrap;gap:16px;align-items:flex-start}svg{font:12px system-ui,sans-serif;"
    "background:#fff}code{font:12px monospace;word-break:break-all}"
    "@media print{body{margin:8mm}h2{break-after:avoid}table,svg{break-inside:avoid}}";

}  // namespace

std::string setup_sheet_html(const SetupSheet& s) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" << esc(s.title) << "</title>\n<style>"
    << kStyle << "</style>\n<script>" << error_trap_script() << "</script>\n</head><body>\n";
  o << "<h1>" << esc(s.title) << "</h1>\n<p>Part <code>" << esc(s.part_file) << "</code> · post " << esc(s.post)
    << " · material " << esc(s.material) << " · total cycle time <b>" << num(s.cycle_time_min(), 1) << " min</b> ("
    << num(s.total_time_min, 1) << " min kinematic + " << s.tool_changes << " tool changes × "
    << num(s.tool_change_s, 0) << " s)</p>\n";
  // 1. Stock and origin.
  const double sw = s.stock_x1 - s.stock_x0, sd = s.stock_y1 - s.stock_y0, sh = s.blank_top_z - s.stock_bottom_z;
  o << "<h2>Stock and work origin</h2>\n<table>"
    << "<tr><th>stock</th><td>" << (s.blank_top_z > 0 ? "sawn blank " : "pre-squared block ") << num(sw, 1) << " × "
    << num(sd, 1) << " × " << num(sh, 1) << " mm (X × Y × Z)";
  if (s.blank_top_z > 0)
    o << ", its top faced " << num(s.blank_top_z, 2) << " mm down to Z0 by operation 1 (its sides stay as sawn)";
  o << ", part footprint " << num(s.part_width, 1) << " × " << num(s.part_depth, 1) << " mm inside it with "
    << num(-s.stock_x0, 1) << " / " << num(s.stock_x1 - s.part_width, 1) << " mm on X− / X+, " << num(-s.stock_y0, 1)
    << " / " << num(s.stock_y1 - s.part_depth, 1) << " mm on Y− / Y+</td></tr>"
    << "<tr><th>work origin (G54)</th><td>X0 Y0 at the " << esc(s.origin_name)
    << " (the stock's lower-left corner at X " << num(s.stock_x0 - s.origin_x, 1) << " Y "
    << num(s.stock_y0 - s.origin_y, 1) << ", the part footprint's at X " << num(-s.origin_x, 1) << " Y "
    << num(-s.origin_y, 1) << "); Z0 on the stock top, " << num(-s.part_top_z, 2)
    << " mm above the part's highest point";
  if (s.blank_top_z > 0)
    o << " — " << num(s.blank_top_z, 2) << " mm below the sawn blank's top: touch off on the blank's top and set Z +"
      << num(s.blank_top_z, 3);
  o << "</td></tr>"
    << "<tr><th>clamping</th><td>";
  const double free_mm = s.deepest_z - s.stock_bottom_z;
  if (free_mm > 0.5)
    o << num(free_mm, 1) << " mm of the block's height under Z " << num(s.deepest_z, 2)
      << " is never cut: clamp within it";
  else
    o << "<span class=\"bad\">the tools go down to Z " << num(s.deepest_z, 2)
      << ", the part's base: nothing of this block is left free to clamp.</span> Use a block taller by the vise "
         "jaws' grip under the part (Z0 stays on its top), or a sub-plate";
  o << "</td></tr></table>\n<div class=\"views\">";
  top_view(o, s);
  front_view(o, s);
  o << "</div>\n";
  // 2. Tools.
  o << "<h2>Tools</h2>\n<table><tr><th>T</th><th>H</th><th>tool</th><th>type</th><th>Ø mm</th><th>stick-out mm</th>"
       "<th>holder Ø × length mm</th><th>reach needed mm</th><th>holder clears the part</th></tr>\n";
  for (const SetupTool& t : s.tools) {
    o << "<tr><td class=\"n\">" << t.number << "</td><td class=\"n\">" << t.length_offset << "</td><td>"
      << esc(t.id.empty() ? t.description : t.id + ": " + t.description);
    if (!t.note.empty()) o << "<br><i>" << esc(t.note) << "</i>";
    o << "</td><td>" << esc(t.type) << "</td><td class=\"n\">" << num(t.diameter_mm, 2) << "</td><td class=\"n\">"
      << (t.stickout_mm > 0 ? num(t.stickout_mm, 1) : "not stated") << "</td><td class=\"n\">"
      << (t.holder_diameter_mm > 0 ? num(t.holder_diameter_mm, 1) + " × " + num(t.holder_length_mm, 1)
                                   : std::string("not stated"))
      << "</td><td class=\"n\">" << num(t.reach_needed_mm, 2) << "</td><td>";
    if (!t.holder_checked)
      o << "not checked (stick-out or holder not stated)";
    else if (t.holder_clearance_mm >= 0)
      o << "<span class=\"ok\">yes</span>, by " << num(t.holder_clearance_mm, 2) << " mm";
    else
      o << "<span class=\"bad\">NO: short by " << num(-t.holder_clearance_mm, 2) << " mm</span>";
    o << "</td></tr>\n";
  }
  o << "</table>\n";
  // 3. Operations.
  o << "<h2>Operations</h2>\n<table><tr><th>#</th><th>operation</th><th>T</th><th>strategy</th><th>spindle rpm</th>"
       "<th>feed mm/min</th><th>stepover mm</th><th>step-down mm</th><th>deepest Z</th><th>largest depth of cut mm</th>"
       "<th>rapids into material</th><th>left above the design after it, mm</th><th>time min</th>"
       "<th>program run alone</th></tr>\n";
  for (const SetupOperation& op : s.operations)
    o << "<tr><td class=\"n\">" << op.index << "</td><td>" << esc(op.name) << "</td><td class=\"n\">T" << op.tool_number
      << "</td><td>" << esc(op.strategy) << "</td><td class=\"n\">" << num(op.rpm, 0) << "</td><td class=\"n\">"
      << num(op.feed_mm_min, 0) << "</td><td class=\"n\">" << (op.stepover_mm > 0 ? num(op.stepover_mm, 3) : "–")
      << "</td><td class=\"n\">" << (op.step_down_mm > 0 ? num(op.step_down_mm, 3) : "–") << "</td><td class=\"n\">"
      << num(op.deepest_z_mm, 2) << "</td><td class=\"n" << (op.beyond_flutes ? " bad" : "") << "\">"
      << num(op.max_depth_of_cut_mm, 2) << "</td><td class=\"n" << (op.cutting_rapids > 0 ? " bad" : "") << "\">"
      << op.cutting_rapids << "</td><td class=\"n\">" << num(op.left_after_mm, 2) << "</td><td class=\"n\">"
      << num(op.time_min, 1) << "</td><td><code>" << esc(op.program) << "</code></td></tr>\n";
  o << "<tr><th colspan=\"12\">total</th><td class=\"n\"><b>" << num(s.total_time_min, 1)
    << "</b></td><td></td></tr></table>\n";
  // 4. The simulated result.
  o << "<h2>Simulated result (the job program machined from the block on one z-map)</h2>\n<table>";
  for (const auto& [k, val] : s.result) o << "<tr><th>" << esc(k) << "</th><td>" << esc(val) << "</td></tr>";
  o << "</table>\n";
  // 5. Files.
  o << "<h2>Program files</h2>\n<table><tr><th>file</th><th>bytes</th><th>SHA-256 (check with sha256sum)</th></tr>\n";
  for (const SetupFile& f : s.files)
    o << "<tr><td><code>" << esc(f.name) << "</code></td><td class=\"n\">" << f.bytes << "</td><td><code>"
      << esc(f.sha256) << "</code></td></tr>\n";
  o << "</table>\n";
  if (!s.notes.empty()) {
    o << "<h2>Notes</h2>\n<ul>";
    for (const std::string& n : s.notes) o << "<li>" << esc(n) << "</li>";
    o << "</ul>\n";
  }
  o << "<script>document.body.setAttribute('data-rendered', '1');</script>\n</body></html>\n";
  return o.str();
}

void write_setup_sheet(const std::filesystem::path& path, const SetupSheet& sheet) {
  write_file_atomic(path, setup_sheet_html(sheet));
}

}  // namespace millnet::report
