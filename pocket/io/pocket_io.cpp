// Pocket JSON and ASCII DXF readers.
#include "millnet/pocket/io/pocket_io.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/edit_distance.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/json_input.hpp"
#include "millnet/pocket/tolerances.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <sstream>
#include <cstdint>
#include <unordered_map>

namespace millnet::pocket {

namespace {
using nlohmann::json;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

double json_number(const json& j, const std::string& source, const std::string& key) {
  if (!j.is_number()) throw Error(source + ": " + key + ": expected a number, got " + std::string(j.type_name()));
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw Error(source + ": " + key + ": expected a finite number");
  return v;
}

// Coordinates are range-checked here, before Clipper sees them: its integer grid (tol::
// clipper_resolution_mm) ends near ±4.6e14 mm, and its "Coordinate outside allowed range" names
// neither the file nor the vertex (issue 15; tests/corpus/cli/pocket_coordinate_1e300.args).
constexpr double kMaxCoordinateMm = 1e6;

double coordinate(double v, const std::string& where) {
  if (!(std::abs(v) <= kMaxCoordinateMm))
    throw Error(where + ": coordinate " + format_double(v) +
                " mm is outside the allowed range, expected -1000000…1000000 mm");
  return v;
}

Loop json_loop(const json& j, const std::string& source, const std::string& key) {
  if (!j.is_array()) throw Error(source + ": " + key + ": expected an array of [x, y, bulge]");
  Loop loop;
  for (std::size_t k = 0; k < j.size(); ++k) {
    const std::string vk = key + "[" + std::to_string(k) + "]";
    const json& v = j[k];
    if (!v.is_array() || v.size() < 2 || v.size() > 3)
      throw Error(source + ": " + vk + ": expected [x, y] or [x, y, bulge]");
    Vertex x;
    x.x = coordinate(json_number(v[0], source, vk + "[0]"), source + ": " + vk + "[0]");
    x.y = coordinate(json_number(v[1], source, vk + "[1]"), source + ": " + vk + "[1]");
    x.bulge = v.size() == 3 ? json_number(v[2], source, vk + "[2]") : 0.0;
    loop.push_back(x);
  }
  return loop;
}

// The keys a pocket JSON file may hold: a misspelt key ("tool_diamter") is an error, never ignored
// (issue 15: the program was written for the default tool; tests/corpus/pocket/misspelt_key.json).
const std::vector<std::string>& pocket_keys() {
  static const std::vector<std::string> k = {"units",     "boundary",    "islands",     "tool_diameter",  "stepover",
                                             "depth",     "safe_z",      "step_down",   "stock_to_leave", "feed_slot",
                                             "feed_half", "feed_plunge", "spindle_rpm", "note",           "name",
                                             "comment",   "format"};
  return k;
}

void check_pocket_keys(const json& j, const std::string& source) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string& key = it.key();
    const auto& known = pocket_keys();
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    std::string shown = key.substr(0, 40), hint;
    for (const std::string& k : known)
      if (key.size() < 64 && edit_distance(key, k) <= 2) hint = " (did you mean \"" + k + "\"?)";
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    throw file_error(source, "\"" + shown + "\": unknown key" + hint + "; allowed: " + list);
  }
}

void finish(PocketFile& f, const std::string& source) {
  const NormalizeReport rep = validate_and_normalize(f.region, source);
  f.notes.insert(f.notes.end(), rep.notes.begin(), rep.notes.end());
}

// ---------------------------------------------------------------- DXF
struct Pair {
  int code = 0;
  std::string value;
  long line = 0;  ///< 1-based line of the group code
};

std::vector<Pair> dxf_pairs(const std::string& text, const std::string& source) {
  std::vector<Pair> out;
  std::istringstream in(text);
  std::string a, b;
  long line = 0;
  auto trim = [](std::string s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
    std::size_t i = 0;
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    return s.substr(i);
  };
  while (std::getline(in, a)) {
    ++line;
    const long code_line = line;
    if (!std::getline(in, b)) {
      if (trim(a).empty()) break;
      throw line_error(source, code_line, "DXF group code without a value");
    }
    ++line;
    Pair p;
    const std::string c = trim(a);
    try {
      std::size_t used = 0;
      p.code = std::stoi(c, &used);
      if (used != c.size()) throw std::invalid_argument(c);
    } catch (const std::exception&) {
      throw line_error(source, code_line, "expected a DXF group code (an integer), got '" + c + "'");
    }
    p.value = trim(b);
    p.line = code_line;
    out.push_back(std::move(p));
  }
  return out;
}

double dxf_number(const Pair& p, const std::string& source) {
  double v = 0;
  try {
    std::size_t used = 0;
    v = std::stod(p.value, &used);
    if (used != p.value.size() || !std::isfinite(v)) throw std::invalid_argument(p.value);
  } catch (const std::exception&) {
    throw line_error(source, p.line + 1,
                     "group " + std::to_string(p.code) + ": expected a number, got '" + p.value + "'");
  }
  if ((p.code >= 10 && p.code <= 39) || p.code == 40)  // coordinates and radii: before Clipper sees them
    (void)coordinate(v, source + ":" + std::to_string(p.line + 1) + ": group " + std::to_string(p.code));
  return v;
}

/// An open piece or a closed loop read from the DXF, with where it came from.
struct Piece {
  std::vector<Vertex> pts;  ///< open: last vertex's bulge unused
  bool closed = false;
  std::string what;  ///< "LINE handle 2A (line 120)"
};

std::vector<Vertex> reversed_open(const std::vector<Vertex>& v) {
  const std::size_t m = v.size();
  std::vector<Vertex> w(m);
  for (std::size_t i = 0; i < m; ++i) {
    w[i] = v[m - 1 - i];
    w[i].bulge = i + 1 < m ? -v[m - 2 - i].bulge : 0.0;
  }
  return w;
}

/// Where the ENTITIES section's first entity starts. Throws when there is none, or when the file
/// does not end with "0 EOF".
std::size_t entities_start(const std::vector<Pair>& pr, const std::string& source) {
  std::size_t i = 0;
  bool found = false;
  for (; i + 1 < pr.size(); ++i)
    if (pr[i].code == 0 && pr[i].value == "SECTION" && pr[i + 1].code == 2 && pr[i + 1].value == "ENTITIES") {
      i += 2;
      found = true;
      break;
    }
  if (!found) throw file_error(source, "no ENTITIES section");
  // A file cut between entities must not read as a smaller pocket (issue 15: the islands after the
  // cut were lost; tests/corpus/pocket/dxf_truncated_between_entities.dxf): ENTITIES ends with
  // ENDSEC and the file with EOF.
  const long last_line = pr.empty() ? 0 : pr.back().line + 1;
  if (pr.empty() || pr.back().code != 0 || pr.back().value != "EOF")
    throw line_error(source, last_line, "the file ends here without \"0 EOF\" (truncated?)");
  return i;
}

/// One entity: its group pairs up to the next group 0, and what error messages call it.
struct Entity {
  const std::string& source;
  std::string type;
  long at = 0;                 ///< line of its group 0
  std::vector<const Pair*> g;  ///< its groups
  std::string what;            ///< "LINE handle 2A (line 120)"
  double mx = 1;               ///< −1: OCS with extrusion (0,0,−1), which mirrors X

  /// The number of group `code`; def when it is missing and not required.
  double num(int code, bool required, double def = 0) const {
    for (const Pair* p : g)
      if (p->code == code) return dxf_number(*p, source);
    if (required) throw line_error(source, at, what + ": missing group " + std::to_string(code));
    return def;
  }
};

/// An ARC (one open piece with its bulge) or a CIRCLE (a closed loop of two half circles).
Piece arc_piece(const Entity& e) {
  constexpr double deg = std::numbers::pi / 180;
  const double cx = e.mx * e.num(10, true), cy = e.num(20, true), r = e.num(40, true);
  if (!(r > 0)) throw line_error(e.source, e.at, e.what + ": radius must be > 0");
  Piece pc;
  pc.what = e.what;
  if (e.type == "CIRCLE") {
    pc.closed = true;
    pc.pts = {{cx + r, cy, 1}, {cx - r, cy, 1}};
    return pc;
  }
  double a0 = e.num(50, true), a1 = e.num(51, true);
  double sweep = std::fmod(a1 - a0, 360.0);
  if (sweep <= 0) sweep += 360;
  // In a mirrored OCS the angles run the other way.
  if (e.mx < 0) {
    a0 = 180 - a0;
    a1 = 180 - a1;
  }
  const double b = std::tan(sweep * deg / 4) * e.mx;
  pc.pts = {{cx + r * std::cos(a0 * deg), cy + r * std::sin(a0 * deg), b},
            {cx + r * std::cos(a1 * deg), cy + r * std::sin(a1 * deg), 0}};
  return pc;
}

Piece lwpolyline_piece(const Entity& e) {
  Piece pc;
  pc.what = e.what;
  pc.closed = (static_cast<long>(e.num(70, false, 0)) & 1) != 0;
  for (const Pair* p : e.g) {
    if (p->code == 10)
      pc.pts.push_back({e.mx * dxf_number(*p, e.source), 0, 0});
    else if (p->code == 20 && !pc.pts.empty())
      pc.pts.back().y = dxf_number(*p, e.source);
    else if (p->code == 42 && !pc.pts.empty())
      pc.pts.back().bulge = e.mx * dxf_number(*p, e.source);
  }
  if (pc.pts.size() < 2) throw line_error(e.source, e.at, e.what + ": fewer than 2 vertices");
  return pc;
}

/// A POLYLINE and the VERTEX entities that follow it until SEQEND, from pr[j] on; j is left after
/// the SEQEND.
Piece polyline_piece(const Entity& e, const std::vector<Pair>& pr, std::size_t& j) {
  const std::string& source = e.source;
  Piece pc;
  pc.what = e.what;
  pc.closed = (static_cast<long>(e.num(70, false, 0)) & 1) != 0;
  if ((static_cast<long>(e.num(70, false, 0)) & (16 | 64)) != 0)
    throw line_error(source, e.at, e.what + ": polygon meshes / polyface meshes are not pocket outlines");
  while (j < pr.size() && pr[j].code == 0 && pr[j].value == "VERTEX") {
    std::size_t k = j + 1;
    Vertex v;
    for (; k < pr.size() && pr[k].code != 0; ++k) {
      if (pr[k].code == 10) v.x = e.mx * dxf_number(pr[k], source);
      if (pr[k].code == 20) v.y = dxf_number(pr[k], source);
      if (pr[k].code == 42) v.bulge = e.mx * dxf_number(pr[k], source);
    }
    pc.pts.push_back(v);
    j = k;
  }
  if (j < pr.size() && pr[j].code == 0 && pr[j].value == "SEQEND") {
    ++j;
    while (j < pr.size() && pr[j].code != 0) ++j;
  } else {
    throw line_error(source, e.at, e.what + ": VERTEX list not ended by SEQEND");
  }
  if (pc.pts.size() < 2) throw line_error(source, e.at, e.what + ": fewer than 2 vertices");
  return pc;
}

std::vector<Piece> dxf_pieces(const std::vector<Pair>& pr, const std::string& source) {
  std::vector<Piece> pieces;
  std::size_t i = entities_start(pr, source);
  while (i < pr.size()) {
    if (pr[i].code != 0) {
      ++i;
      continue;
    }
    Entity e{source, pr[i].value, pr[i].line, {}, {}, 1};
    if (e.type == "EOF")
      throw line_error(source, pr[i].line, "EOF inside the ENTITIES section (no ENDSEC: truncated?)");
    if (e.type == "ENDSEC") break;
    std::size_t j = i + 1;
    while (j < pr.size() && pr[j].code != 0) e.g.push_back(&pr[j++]);
    std::string handle = "?";
    double ext_z = 1;
    for (const Pair* p : e.g) {
      if (p->code == 5) handle = p->value;
      if (p->code == 230) ext_z = dxf_number(*p, source);
    }
    e.what = e.type + " handle " + handle + " (line " + std::to_string(e.at) + ")";
    e.mx = ext_z < 0 ? -1.0 : 1.0;
    if (e.type == "LINE") {
      Piece pc;
      pc.what = e.what;
      pc.pts = {{e.num(10, true), e.num(20, true), 0}, {e.num(11, true), e.num(21, true), 0}};
      pieces.push_back(std::move(pc));
    } else if (e.type == "ARC" || e.type == "CIRCLE") {
      pieces.push_back(arc_piece(e));
    } else if (e.type == "LWPOLYLINE") {
      pieces.push_back(lwpolyline_piece(e));
    } else if (e.type == "POLYLINE") {
      pieces.push_back(polyline_piece(e, pr, j));
    }
    // Other entities (TEXT, DIMENSION, POINT, …) carry no pocket geometry.
    i = j;
  }
  // A closed polyline that repeats its first vertex at the end: drop the duplicate.
  for (Piece& p : pieces)
    if (p.closed && p.pts.size() > 2 && (p.pts.back().p() - p.pts.front().p()).norm() <= tol::chain_join_mm)
      p.pts.pop_back();
  return pieces;
}

/// The open pieces' end points in a hash grid of cell tol::chain_join_mm: the pieces with an end
/// within chain_join_mm of a point are in its 3×3 cells. It replaced a scan of all pieces per join
/// (issue 15: 44 s for a 100,000-entity DXF).
class EndGrid {
public:
  explicit EndGrid(const std::vector<Piece>& open) {
    for (std::size_t k = 0; k < open.size(); ++k) {
      cells_[key(open[k].pts.front().p(), 0, 0)].push_back(k);
      cells_[key(open[k].pts.back().p(), 0, 0)].push_back(k);
    }
  }
  /// Pieces with an end in the 3×3 cells around p (unsorted, may repeat).
  void near(const Vec2& p, std::vector<std::size_t>& out) const {
    out.clear();
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        if (const auto it = cells_.find(key(p, dx, dy)); it != cells_.end())
          out.insert(out.end(), it->second.begin(), it->second.end());
  }

private:
  static std::pair<std::int64_t, std::int64_t> key(const Vec2& p, int dx, int dy) {
    auto cell = [](double v) {  // clamped: far-out coordinates share cells, which only costs time
      return static_cast<std::int64_t>(std::clamp(std::floor(v / tol::chain_join_mm), -1e15, 1e15));
    };
    return {cell(p.x()) + dx, cell(p.y()) + dy};
  }
  struct Hash {
    std::size_t operator()(const std::pair<std::int64_t, std::int64_t>& k) const noexcept {
      return static_cast<std::size_t>(static_cast<std::uint64_t>(k.first) * 0x9E3779B97F4A7C15ULL ^
                                      static_cast<std::uint64_t>(k.second));
    }
  };
  std::unordered_map<std::pair<std::int64_t, std::int64_t>, std::vector<std::size_t>, Hash> cells_;
};

/// Chains open pieces end to end (either direction) into closed loops; at each join the unused piece
/// of smallest index with an end within tol::chain_join_mm is taken (its start before its end).
/// O(pieces) expected (EndGrid).
std::vector<Loop> chain_loops(std::vector<Piece> pieces, const std::string& source, std::vector<std::string>& notes) {
  std::vector<Loop> loops;
  std::vector<Piece> open;
  for (Piece& p : pieces) {
    if (p.closed)
      loops.push_back(std::move(p.pts));
    else
      open.push_back(std::move(p));
  }
  const EndGrid ends(open);
  std::vector<std::size_t> cand;
  std::vector<bool> used(open.size(), false);
  std::size_t chained = 0;
  for (std::size_t s = 0; s < open.size(); ++s) {
    if (used[s]) continue;
    used[s] = true;
    std::vector<Vertex> chain = open[s].pts;
    std::size_t count = 1;
    while ((chain.back().p() - chain.front().p()).norm() > tol::chain_join_mm) {
      bool extended = false;
      ends.near(chain.back().p(), cand);
      std::sort(cand.begin(), cand.end());
      for (const std::size_t k : cand) {
        if (extended) break;
        if (used[k]) continue;
        std::vector<Vertex> next;
        if ((open[k].pts.front().p() - chain.back().p()).norm() <= tol::chain_join_mm)
          next = open[k].pts;
        else if ((open[k].pts.back().p() - chain.back().p()).norm() <= tol::chain_join_mm)
          next = reversed_open(open[k].pts);
        else
          continue;
        used[k] = true;
        chain.back().bulge = next.front().bulge;  // the joint vertex starts the next piece's segment
        chain.insert(chain.end(), next.begin() + 1, next.end());
        ++count;
        extended = true;
      }
      if (!extended) {
        std::ostringstream os;
        os << "open loop: the chain starting at " << open[s].what << " ends at (" << chain.back().x << ", "
           << chain.back().y << ") with no entity within " << tol::chain_join_mm << " mm of it (start at ("
           << chain.front().x << ", " << chain.front().y << "))";
        throw file_error(source, os.str());
      }
    }
    // Closed: the last vertex repeats the first; its bulge is already on the previous vertex.
    chain.pop_back();
    loops.push_back(std::move(chain));
    chained += count;
  }
  if (chained > 0)
    notes.push_back("chained " + std::to_string(chained) + " open DXF entit" + (chained == 1 ? "y" : "ies") +
                    " into closed loops");
  return loops;
}
}  // namespace

PocketFile parse_pocket_json(const std::string& text, const std::string& source) {
  check_json_nesting(text, source);
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    throw file_error(source, "invalid JSON: " + json_error_text(e.what()));
  }
  if (!j.is_object()) throw file_error(source, "expected a JSON object with \"boundary\"");
  check_pocket_keys(j, source);
  PocketFile f;
  if (j.contains("units")) {
    if (!j["units"].is_string()) throw file_error(source, "units: expected a string");
    if (j["units"].get<std::string>() != "mm")
      throw file_error(source, "units: only \"mm\" is supported, got \"" + j["units"].get<std::string>() + "\"");
  }
  if (!j.contains("boundary")) throw file_error(source, "missing key \"boundary\"");
  f.region.boundary = json_loop(j["boundary"], source, "boundary");
  if (j.contains("islands")) {
    if (!j["islands"].is_array()) throw file_error(source, "islands: expected an array of loops");
    for (std::size_t k = 0; k < j["islands"].size(); ++k)
      f.region.islands.push_back(json_loop(j["islands"][k], source, "islands[" + std::to_string(k) + "]"));
  }
  const std::pair<const char*, std::optional<double>*> keys[] = {{"tool_diameter", &f.tool_diameter},
                                                                 {"stepover", &f.stepover},
                                                                 {"depth", &f.depth},
                                                                 {"safe_z", &f.safe_z},
                                                                 {"step_down", &f.step_down},
                                                                 {"stock_to_leave", &f.stock_to_leave},
                                                                 {"feed_slot", &f.feed_slot},
                                                                 {"feed_half", &f.feed_half},
                                                                 {"feed_plunge", &f.feed_plunge},
                                                                 {"spindle_rpm", &f.spindle_rpm}};
  for (const auto& [k, dst] : keys)
    if (j.contains(k)) *dst = json_number(j[k], source, k);
  finish(f, source);
  return f;
}

PocketFile parse_pocket_dxf(const std::string& text, const std::string& source) {
  PocketFile f;
  const auto pairs = dxf_pairs(text, source);
  std::vector<Loop> loops = chain_loops(dxf_pieces(pairs, source), source, f.notes);
  if (loops.empty())
    throw file_error(source, "no closed outline (LWPOLYLINE, POLYLINE, LINE, ARC, CIRCLE) in ENTITIES");
  // Nesting by containment: the loop with the largest area encloses the rest. O(loops²).
  std::sort(loops.begin(), loops.end(),
            [](const Loop& a, const Loop& b) { return std::abs(signed_area(a)) > std::abs(signed_area(b)); });
  f.region.boundary = loops.front();
  for (std::size_t k = 1; k < loops.size(); ++k) {
    // Outside only when no vertex is inside: a loop partly inside crosses the boundary, which the
    // validation below reports as such.
    if (std::none_of(loops[k].begin(), loops[k].end(), [&](const Vertex& v) { return inside(loops.front(), v.p()); }))
      throw file_error(source, "loop " + std::to_string(k) + " (vertex at (" + std::to_string(loops[k].front().x) +
                                   ", " + std::to_string(loops[k].front().y) +
                                   ")) lies outside the outermost loop: one pocket per file");
    for (std::size_t m = 1; m < k; ++m)
      if (inside(loops[m], loops[k].front().p()))
        throw file_error(source, "loop " + std::to_string(k) + " lies inside island loop " + std::to_string(m) +
                                     ": islands inside islands are not supported (yet)");
    f.region.islands.push_back(loops[k]);
  }
  finish(f, source);
  return f;
}

PocketFile read_pocket(const std::filesystem::path& path) {
  const std::string ext = lower(path.extension().string());
  const std::string text = read_file(path);
  if (ext == ".json") return parse_pocket_json(text, path.string());
  if (ext == ".dxf") return parse_pocket_dxf(text, path.string());
  throw file_error(path.string(), "unknown pocket format '" + ext + "' (expected .json or .dxf)");
}

void write_pocket_json(const std::filesystem::path& path, const Region& region) {
  auto loop_json = [](const Loop& l) {
    json a = json::array();
    for (const Vertex& v : l) a.push_back({v.x, v.y, v.bulge});
    return a;
  };
  json j;
  j["units"] = "mm";
  j["boundary"] = loop_json(region.boundary);
  j["islands"] = json::array();
  for (const Loop& l : region.islands) j["islands"].push_back(loop_json(l));
  write_file_atomic(path, j.dump(1) + "\n");
}

}  // namespace millnet::pocket
