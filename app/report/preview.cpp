// HTML previews: see preview.hpp. The page's script is at the bottom of this file (kPageScript).
#include "millnet/report/preview.hpp"

#include "millnet/report/page_data.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/gcode/reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>

namespace millnet::report {
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string read_asset(const fs::path& p, const char* package) {
  std::ifstream in(p, std::ios::binary);
  if (!in) {
    throw Error(p.string() + ": cannot read the script the preview pages inline (install Debian package " + package +
                ", or point MILLNET_JS_DIR at a folder holding it)");
  }
  std::ostringstream s;
  s << in.rdbuf();
  std::string t = s.str();
  // A script inlined in <script> must not contain "</script"; "<\/" means the same in JavaScript strings
  // and regular expressions, where it can only occur.
  std::string out;
  out.reserve(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] == '<' && i + 1 < t.size() && t[i + 1] == '/') {
      out += "<\\/";
      ++i;
    } else {
      out += t[i];
    }
  }
  return out;
}

/// A JSON string literal (also safe inside <script>: '<' is escaped).
std::string jstr(std::string_view s) {
  std::string o = "\"";
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"')
      o += "\\\"";
    else if (c == '\\')
      o += "\\\\";
    else if (c == '<')
      o += "\\u003c";
    else if (c == '>')
      o += "\\u003e";
    else if (c == '&')
      o += "\\u0026";
    else if (c < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", c);
      o += b;
    } else
      o += ch;
  }
  return o + "\"";
}

/// A number rounded to 1e-3 (µm for mm), without a trailing ".000"; non-finite → null.
std::string jnum(double v) {
  if (!std::isfinite(v)) return "null";
  const double r = std::round(v * 1000.0) / 1000.0;
  if (r == 0) return "0";
  char b[40];
  std::snprintf(b, sizeof b, "%.3f", r);
  std::string s = b;
  while (!s.empty() && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

template <class T, class F>
std::string jarr(const std::vector<T>& v, F f) {
  std::string o = "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i) o += ',';
    o += f(v[i]);
  }
  return o + "]";
}

std::string hex(std::uint32_t c) {
  char b[8];
  std::snprintf(b, sizeof b, "#%06X", c & 0xFFFFFFu);
  return b;
}

std::string html_escape(std::string_view s) {
  std::string o;
  for (const char c : s) {
    if (c == '<')
      o += "&lt;";
    else if (c == '>')
      o += "&gt;";
    else if (c == '&')
      o += "&amp;";
    else if (c == '"')
      o += "&quot;";
    else
      o += c;
  }
  return o;
}

struct RawPoint {
  std::array<double, 3> p;
  StepKind kind;
  double feed;
  std::size_t line;
};

}  // namespace

std::string escape_html(std::string_view s) { return html_escape(s); }

std::vector<std::size_t> decimate_indices(std::size_t n, std::size_t budget) {
  std::vector<std::size_t> out;
  if (n == 0) return out;
  budget = std::max<std::size_t>(budget, 2);
  if (n <= budget) {
    out.resize(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = i;
    return out;
  }
  out.reserve(budget);
  // i·(n-1)/(budget-1) for i = 0 … budget-1: strictly increasing since n-1 ≥ budget-1, first 0, last n-1.
  for (std::size_t i = 0; i < budget; ++i) {
    const auto num = static_cast<unsigned long long>(i) * static_cast<unsigned long long>(n - 1);
    out.push_back(static_cast<std::size_t>(num / (budget - 1)));
  }
  return out;
}

StepKind step_kind(int motion, const std::array<double, 3>& from, const std::array<double, 3>& to) {
  constexpr double eps = 1e-6;
  const auto m = static_cast<gcode::Motion>(motion);
  if (m == gcode::Motion::Rapid) return StepKind::Rapid;
  const double dz = to[2] - from[2];
  const double dxy = std::hypot(to[0] - from[0], to[1] - from[1]);
  if (m == gcode::Motion::Line) {
    if (dz < -eps && dxy <= eps) return StepKind::Plunge;
    if (dz < -eps) return StepKind::Ramp;
    return StepKind::Cut;
  }
  return std::abs(dz) > eps ? StepKind::Helix : StepKind::Cut;
}

PreviewSurface zmap_surface(const simulate::ZMap& z, const std::vector<double>& design, std::size_t max_cells,
                            const std::string& name, const std::string& units) {
  const simulate::GridSpec& g = z.spec();
  PreviewSurface s;
  std::size_t stride = 1;
  while ((g.ny + stride - 1) / stride * ((g.nx + stride - 1) / stride) > std::max<std::size_t>(max_cells, 1)) ++stride;
  const std::size_t rows = (g.ny + stride - 1) / stride, cols = (g.nx + stride - 1) / stride;
  s.z.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  s.value.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t r = 0; r < rows; ++r)  // O(rows × cols) ≤ O(max_cells)
    for (std::size_t c = 0; c < cols; ++c) {
      const std::size_t i = r * stride * g.nx + c * stride;
      const auto er = static_cast<Eigen::Index>(r), ec = static_cast<Eigen::Index>(c);
      s.z(er, ec) = z.heights()[i];
      s.value(er, ec) = i < design.size() ? z.heights()[i] - design[i] : nan;
    }
  // The decimated cells are `stride` times larger, centred where the source cells they stand for were.
  const double cell = g.cell * static_cast<double>(stride);
  s.x0 = g.x0 + g.cell * 0.5 - cell * 0.5;
  s.y0 = g.y0 + g.cell * 0.5 - cell * 0.5;
  s.cell_mm = cell;
  s.source_rows = g.ny;
  s.source_cols = g.nx;
  s.source_stride = stride;
  s.value_name = name;
  s.units = units;
  return s;
}

PreviewProgram read_preview_program(std::string name, std::string text, std::string_view source) {
  PreviewProgram p;
  p.name = std::move(name);
  p.written.program = gcode::read(text, source);
  p.written.text = std::move(text);
  return p;
}

PreviewPath preview_path(const PreviewProgram& program, std::size_t max_points, double arc_step_deg) {
  const gcode::Program& prog = program.written.program;
  std::vector<RawPoint> raw;
  PreviewPath path;
  bool have = false;
  std::array<double, 3> cur{0, 0, 0};
  const double step = std::max(arc_step_deg, 0.5) * kPi / 180.0;
  for (std::size_t i = 0; i < prog.items.size(); ++i) {
    const auto* mv = std::get_if<gcode::Move>(&prog.items[i]);
    if (mv == nullptr) continue;
    ++path.moves;
    const std::size_t line = i < prog.source_line.size() ? prog.source_line[i] : 0;
    if (!have) {  // the first move: its position is where the path starts
      have = true;
      cur = mv->to;
      raw.push_back({cur, StepKind::Rapid, 0.0, line});
      continue;
    }
    StepKind kind = step_kind(static_cast<int>(mv->motion), cur, mv->to);
    // A line down while XY moves is a ramp only as an entry (after a rapid or another entry move); in
    // the material it is a cut (finishing programs descend along the surface all the time).
    if (kind == StepKind::Ramp && !raw.empty() && raw.back().kind == StepKind::Cut) kind = StepKind::Cut;
    if (mv->motion == gcode::Motion::ArcCW || mv->motion == gcode::Motion::ArcCCW) {
      const double cx = mv->center[0], cy = mv->center[1];
      const double r = std::hypot(cur[0] - cx, cur[1] - cy);
      const double a0 = std::atan2(cur[1] - cy, cur[0] - cx), a1 = std::atan2(mv->to[1] - cy, mv->to[0] - cx);
      double sweep = a1 - a0;
      const bool ccw = mv->motion == gcode::Motion::ArcCCW;
      if (ccw) {
        while (sweep <= 1e-12) sweep += 2 * kPi;
      } else {
        while (sweep >= -1e-12) sweep -= 2 * kPi;
      }
      const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil(std::abs(sweep) / step)));
      for (std::size_t k = 1; k < n; ++k) {
        const double t = static_cast<double>(k) / static_cast<double>(n);
        const double a = a0 + sweep * t;
        raw.push_back(
            {{cx + r * std::cos(a), cy + r * std::sin(a), cur[2] + (mv->to[2] - cur[2]) * t}, kind, mv->feed, line});
      }
    }
    cur = mv->to;
    raw.push_back({cur, kind, mv->motion == gcode::Motion::Rapid ? 0.0 : mv->feed, line});
  }
  path.points_before = raw.size();
  for (const std::size_t i : decimate_indices(raw.size(), max_points)) {
    const RawPoint& q = raw[i];
    for (int a = 0; a < 3; ++a) path.xyz.push_back(static_cast<float>(q.p[static_cast<std::size_t>(a)]));
    path.kind.push_back(static_cast<std::uint8_t>(q.kind));
    path.feed.push_back(static_cast<float>(q.feed));
    path.line.push_back(static_cast<std::uint32_t>(q.line));
  }
  return path;
}

namespace {

/// The programs' paths within the point budget, shared in proportion to their tessellated size; a
/// note when that decimated them.
std::vector<PreviewPath> budgeted_paths(const PreviewInput& in, const PreviewLimits& limits,
                                        std::vector<std::string>& notes) {
  std::vector<PreviewPath> paths;
  std::size_t total = 0;
  for (const PreviewProgram& p : in.programs) {
    paths.push_back(preview_path(p, std::numeric_limits<std::size_t>::max(), limits.arc_step_deg));
    total += paths.back().points_before;
  }
  if (total > limits.max_path_points) {
    for (std::size_t k = 0; k < paths.size(); ++k) {
      const double share = static_cast<double>(paths[k].points_before) / static_cast<double>(total);
      const auto budget = static_cast<std::size_t>(std::floor(share * static_cast<double>(limits.max_path_points)));
      paths[k] = preview_path(in.programs[k], std::max<std::size_t>(budget, 2), limits.arc_step_deg);
    }
    notes.push_back("decimated for display: path points " + std::to_string(total) + " → " +
                    std::to_string(limits.max_path_points) + " (evenly spaced; first and last kept)");
  }
  return paths;
}

/// Surface decimation: a stride s over rows and columns within the cell budget (a note when > 1).
std::size_t surface_stride(const PreviewInput& in, const PreviewLimits& limits, std::vector<std::string>& notes) {
  std::size_t stride = 1;
  if (!in.surface) return stride;
  const auto rows = static_cast<std::size_t>(in.surface->z.rows()),
             cols = static_cast<std::size_t>(in.surface->z.cols());
  while ((rows + stride - 1) / stride * ((cols + stride - 1) / stride) > limits.max_surface_cells) ++stride;
  if (stride > 1) {
    notes.push_back("decimated for display: surface " + std::to_string(rows) + "×" + std::to_string(cols) +
                    " cells shown every " + std::to_string(stride) + " cells");
  } else if (in.surface->source_stride > 1) {  // decimated when it was copied (zmap_surface)
    notes.push_back("decimated for display: surface " + std::to_string(in.surface->source_rows) + "×" +
                    std::to_string(in.surface->source_cols) + " cells shown every " +
                    std::to_string(in.surface->source_stride) + " cells");
  }
  return stride;
}

/// Part decimation: every face_stride-th triangle within the face budget (a note when > 1).
std::size_t part_face_stride(const PreviewInput& in, std::vector<std::string>& notes) {
  std::size_t face_stride = 1;
  const auto nf = static_cast<std::size_t>(in.part_F.rows());
  while (nf / face_stride > in.limits.max_mesh_faces) ++face_stride;
  if (face_stride > 1) {
    notes.push_back("decimated for display: part " + std::to_string(nf) + " triangles, every " +
                    std::to_string(face_stride) + "th shown");
  }
  return face_stride;
}

/// Program k's object: its path's points, and the text of the lines the kept points come from
/// (each once), for the "current line" display.
void write_program(std::ostringstream& o, const PreviewProgram& prog, const PreviewPath& p, std::size_t k) {
  o << "{\"name\":" << jstr(prog.name) << ",\"colour\":" << jstr(hex(kProgramColours[k % kProgramColours.size()]))
    << ",\"moves\":" << p.moves << ",\"points_before\":" << p.points_before
    << ",\"xyz\":" << jarr(p.xyz, [](float v) { return jnum(v); })
    << ",\"kind\":" << jarr(p.kind, [](std::uint8_t v) { return std::to_string(v); })
    << ",\"feed\":" << jarr(p.feed, [](float v) { return jnum(v); })
    << ",\"line\":" << jarr(p.line, [](std::uint32_t v) { return std::to_string(v); });
  std::vector<std::string_view> text;
  const std::string& g = prog.written.text;
  for (std::size_t a = 0; a <= g.size();) {
    std::size_t b = g.find('\n', a);
    if (b == std::string::npos) b = g.size();
    std::string_view l(g.data() + a, b - a);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    text.push_back(l);
    a = b + 1;
  }
  std::vector<std::uint32_t> used = p.line;
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  o << ",\"text\":{";
  bool first = true;
  for (const std::uint32_t ln : used) {
    if (ln == 0 || ln > text.size()) continue;
    if (!first) o << ',';
    first = false;
    o << '"' << ln << "\":" << jstr(text[ln - 1]);
  }
  o << "}}";
}

/// The part's vertices and every face_stride-th triangle.
void write_part(std::ostringstream& o, const PreviewInput& in, std::size_t face_stride) {
  const auto nf = static_cast<std::size_t>(in.part_F.rows());
  std::vector<double> v(static_cast<std::size_t>(in.part_V.rows()) * 3);
  for (Eigen::Index i = 0; i < in.part_V.rows(); ++i)
    for (Eigen::Index a = 0; a < 3; ++a) v[static_cast<std::size_t>(i * 3 + a)] = in.part_V(i, a);
  std::vector<int> f;
  for (std::size_t i = 0; i < nf; i += face_stride)
    for (Eigen::Index a = 0; a < 3; ++a) f.push_back(in.part_F(static_cast<Eigen::Index>(i), a));
  o << ",\"part\":{\"V\":" << jarr(v, jnum) << ",\"F\":" << jarr(f, [](int x) { return std::to_string(x); }) << '}';
}

/// The surface every stride-th row and column, its cells grown to match.
void write_surface(std::ostringstream& o, const PreviewSurface& s, std::size_t stride) {
  std::vector<double> z, val;
  std::size_t rows = 0, cols = 0;
  for (Eigen::Index r = 0; r < s.z.rows(); r += static_cast<Eigen::Index>(stride)) {
    ++rows;
    cols = 0;
    for (Eigen::Index c = 0; c < s.z.cols(); c += static_cast<Eigen::Index>(stride)) {
      ++cols;
      z.push_back(s.z(r, c));
      val.push_back(r < s.value.rows() && c < s.value.cols() ? s.value(r, c) : std::nan(""));
    }
  }
  const double cell = s.cell_mm * static_cast<double>(stride);
  const double cy_mm = s.cell_y_mm > 0 ? s.cell_y_mm : s.cell_mm;
  const double celly = cy_mm * static_cast<double>(stride);
  o << ",\"surface\":{\"rows\":" << rows << ",\"cols\":" << cols
    << ",\"x0\":" << jnum(s.x0 + s.cell_mm * 0.5 - cell * 0.5) << ",\"y0\":" << jnum(s.y0 + cy_mm * 0.5 - celly * 0.5)
    << ",\"cell\":" << jnum(cell) << ",\"celly\":" << jnum(celly) << ",\"layer\":" << jstr(s.layer)
    << ",\"name\":" << jstr(s.value_name) << ",\"units\":" << jstr(s.units) << ",\"z\":" << jarr(z, jnum) << ",\"v\":"
    << jarr(val,
            [](double x) { return std::isfinite(x) ? std::to_string(std::round(x * 1e6) / 1e6) : std::string("null"); })
    << '}';
}

}  // namespace

namespace {
std::string data_json(const PreviewInput& in, const PreviewLimits& limits) {
  std::ostringstream o;
  o << "{\"title\":" << jstr(in.title) << ",\"notes\":";
  std::vector<std::string> notes = in.notes;
  const std::vector<PreviewPath> paths = budgeted_paths(in, limits, notes);
  const std::size_t stride = surface_stride(in, limits, notes);
  const std::size_t face_stride = part_face_stride(in, notes);
  o << jarr(notes, [](const std::string& s) { return jstr(s); }) << ",\"programs\":[";
  for (std::size_t k = 0; k < paths.size(); ++k) {
    if (k) o << ',';
    write_program(o, in.programs[k], paths[k], k);
  }
  o << "],\"tool\":{\"d\":" << jnum(in.tool.diameter_mm) << ",\"r\":" << jnum(in.tool.corner_radius_mm)
    << ",\"name\":" << jstr(in.tool.name) << '}';
  if (in.stock) o << ",\"stock\":" << jarr(std::vector<double>(in.stock->begin(), in.stock->end()), jnum);
  if (in.part_V.rows() > 0 && in.part_F.rows() > 0) write_part(o, in, face_stride);
  if (in.surface) write_surface(o, *in.surface, stride);
  o << ",\"colours\":{\"feed\":"
    << jarr(std::vector<std::uint32_t>(kFeedRamp.begin(), kFeedRamp.end()),
            [](std::uint32_t c) { return jstr(hex(c)); })
    << ",\"rapid\":" << jstr(hex(kRapidColour)) << ",\"entry\":" << jstr(hex(kEntryColour)) << "}}";
  return o.str();
}
}  // namespace

std::string preview_data_json(const PreviewInput& in) { return data_json(in, in.limits); }

PreviewAssets preview_assets() {
  const char* env = std::getenv("MILLNET_JS_DIR");
  const fs::path dir = env != nullptr && *env != 0 ? fs::path(env) : fs::path("/usr/share/javascript");
  return {dir / "three" / "build" / "three.min.js", dir / "three" / "examples" / "js" / "controls" / "OrbitControls.js",
          dir / "chart.js" / "chart.min.js"};
}

namespace {
#include "preview_page.inc"
}  // namespace

const char* error_trap_script() { return kErrorTrap; }

namespace {
/// The page's data element within limits.max_page_bytes (with `fixed_bytes` of scripts beside it):
/// while it is larger, the path and surface budgets shrink in proportion to the excess (at most 8
/// times, then what fits is what remains). The decimation notes say what the page shows.
std::string fitted_page_data(const PreviewInput& in, std::size_t fixed_bytes) {
  PreviewLimits limits = in.limits;
  const std::size_t room =
      in.limits.max_page_bytes > fixed_bytes + 200000 ? in.limits.max_page_bytes - fixed_bytes - 200000 : 1;
  std::string data = embed_page_data(data_json(in, limits));
  for (int k = 0; k < 8 && data.size() > room; ++k) {  // O(page) each
    const double f = 0.95 * static_cast<double>(room) / static_cast<double>(data.size());
    limits.max_path_points =
        std::max<std::size_t>(2, static_cast<std::size_t>(f * static_cast<double>(limits.max_path_points)));
    limits.max_surface_cells =
        std::max<std::size_t>(1, static_cast<std::size_t>(f * static_cast<double>(limits.max_surface_cells)));
    data = embed_page_data(data_json(in, limits));
  }
  return data;
}
}  // namespace

std::string preview_html(const PreviewInput& in) {
  const PreviewAssets a = preview_assets();
  const std::string three = read_asset(a.three, "libjs-three");
  const std::string orbit = read_asset(a.orbit_controls, "libjs-three");
  const std::string data = fitted_page_data(in, three.size() + orbit.size());
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" << html_escape(in.title)
    << " — millnet preview</title>\n<style>" << kPageStyle << "</style>\n"
    << "<script>" << kErrorTrap << "</script>\n</head><body>\n"
    << "<div id=\"panel\" style=\"width:" << kPanelWidthPx - 16
    << "px\"></div><div id=\"view\" style=\"left:" << kPanelWidthPx << "px\"></div>\n<script>" << three
    << "\n</script>\n<script>" << orbit << "\n</script>\n"
    << data << "\n<script>" << kPageScript << "</script>\n</body></html>\n";
  return o.str();
}

void write_preview(const fs::path& path, const PreviewInput& input) { write_file_atomic(path, preview_html(input)); }

std::string summary_html(const SummaryPage& page) {
  const std::string chart = read_asset(preview_assets().chart, "libjs-chart.js");
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" << html_escape(page.title)
    << "</title>\n<style>" << kSummaryStyle << "</style>\n<script>" << kErrorTrap << "</script>\n</head><body>\n<h1>"
    << html_escape(page.title) << "</h1>\n<table><tr>";
  for (const auto& h : page.header) o << "<th>" << html_escape(h) << "</th>";
  o << "</tr>\n";
  for (const auto& row : page.rows) {
    o << "<tr>";
    for (const auto& c : row) {
      if (c.rfind("link:", 0) == 0 && c.find('|') != std::string::npos) {
        const auto bar = c.find('|');
        o << "<td><a href=\"" << html_escape(c.substr(bar + 1)) << "\">" << html_escape(c.substr(5, bar - 5))
          << "</a></td>";
      } else {
        o << "<td>" << html_escape(c) << "</td>";
      }
    }
    o << "</tr>\n";
  }
  o << "</table>\n";
  if (!page.previews.empty()) {
    o << "<h2>3D previews</h2><ul>";
    for (const auto& [part, href] : page.previews)
      o << "<li><a href=\"" << html_escape(href) << "\">" << html_escape(part) << "</a></li>";
    o << "</ul>\n";
  }
  o << "<div id=\"charts\"></div>\n<script>" << chart
    << "\n</script>\n<script type=\"application/json\" id=\"millnet-charts\">[";
  for (std::size_t i = 0; i < page.charts.size(); ++i) {
    const SummaryChart& c = page.charts[i];
    if (i) o << ',';
    o << "{\"title\":" << jstr(c.title) << ",\"y\":" << jstr(c.y_label)
      << ",\"labels\":" << jarr(c.labels, [](const std::string& s) { return jstr(s); }) << ",\"series\":[";
    for (std::size_t k = 0; k < c.series.size(); ++k) {
      if (k) o << ',';
      o << "{\"name\":" << jstr(c.series[k].first)
        << ",\"colour\":" << jstr(hex(kProgramColours[k % kProgramColours.size()]))
        << ",\"values\":" << jarr(c.series[k].second, jnum) << '}';
    }
    o << "]}";
  }
  o << "]</script>\n<script>" << kSummaryScript << "</script>\n</body></html>\n";
  return o.str();
}

void write_summary_html(const fs::path& path, const SummaryPage& page) { write_file_atomic(path, summary_html(page)); }

}  // namespace millnet::report
