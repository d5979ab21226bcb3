// Independent G-code replay and gouge check (see gcode_replay.hpp). Own geometry on purpose.
#include "gcode_replay.hpp"

#include <cctype>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace millnet::testing {

namespace {
constexpr double kPi = 3.14159265358979323846;

struct P2 {
  double x, y;
};
P2 sub(P2 a, P2 b) { return {a.x - b.x, a.y - b.y}; }
double dot(P2 a, P2 b) { return a.x * b.x + a.y * b.y; }
double crs(P2 a, P2 b) { return a.x * b.y - a.y * b.x; }
double len(P2 a) { return std::hypot(a.x, a.y); }

/// A wall: a line (r == 0) or an arc given by centre, radius, start angle and signed sweep.
struct Wall {
  P2 a{}, b{};
  bool arc = false;
  P2 c{};
  double r = 0, a0 = 0, sw = 0;
};

Wall make_wall(P2 a, P2 b, double bulge) {
  Wall w;
  w.a = a;
  w.b = b;
  if (bulge == 0.0) return w;
  w.arc = true;
  const P2 ch = sub(b, a);
  const double L = len(ch);
  w.sw = 4 * std::atan(bulge);
  // Radius from the half-chord and the half-sweep; centre from the chord's midpoint.
  w.r = (L / 2) / std::abs(std::sin(w.sw / 2));
  const double h = (L / 2) / std::tan(w.sw / 2);  // signed distance to the left of the chord
  w.c = {(a.x + b.x) / 2 - ch.y / L * h, (a.y + b.y) / 2 + ch.x / L * h};
  w.a0 = std::atan2(a.y - w.c.y, a.x - w.c.x);
  return w;
}

double wall_distance(const Wall& w, P2 p) {
  if (!w.arc) {
    const P2 d = sub(w.b, w.a);
    const double l2 = dot(d, d);
    double t = l2 > 0 ? dot(sub(p, w.a), d) / l2 : 0;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    return len(sub(p, {w.a.x + t * d.x, w.a.y + t * d.y}));
  }
  double rel = std::atan2(p.y - w.c.y, p.x - w.c.x) - w.a0;
  if (w.sw < 0) rel = -rel;
  rel = std::fmod(rel, 2 * kPi);
  if (rel < 0) rel += 2 * kPi;
  if (rel <= std::abs(w.sw)) return std::abs(len(sub(p, w.c)) - w.r);
  return std::min(len(sub(p, w.a)), len(sub(p, w.b)));
}

std::vector<P2> densify(const ReplayLoop& loop) {
  std::vector<P2> out;
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const P2 a{loop[k][0], loop[k][1]};
    const P2 b{loop[(k + 1) % loop.size()][0], loop[(k + 1) % loop.size()][1]};
    out.push_back(a);
    if (loop[k][2] == 0.0) continue;
    const Wall w = make_wall(a, b, loop[k][2]);
    const int n = 720;
    for (int i = 1; i < n; ++i) {
      const double ang = w.a0 + w.sw * i / n;
      out.push_back({w.c.x + w.r * std::cos(ang), w.c.y + w.r * std::sin(ang)});
    }
  }
  return out;
}

/// Even–odd ray casting on a finely flattened loop (used only far from walls).
bool in_poly(const std::vector<P2>& poly, P2 p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const P2 a = poly[i], b = poly[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) in = !in;
  }
  return in;
}

double num(const std::string& s, int line) {
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used != s.size()) throw std::invalid_argument(s);
    return v;
  } catch (const std::exception&) {
    throw std::runtime_error("gcode line " + std::to_string(line) + ": bad number '" + s + "'");
  }
}
}  // namespace

ReplayResult replay_gcode(const std::string& text, double safe_z) {
  ReplayResult r;
  std::istringstream in(text);
  std::string raw;
  int line = 0, motion = -1;
  double pos[3] = {0, 0, safe_z};
  bool pos_known = false;
  double feed = 0;
  bool cut_since_retract = false, retracted = false, last_was_rapid = true;
  while (std::getline(in, raw)) {
    ++line;
    std::string s;
    int paren = 0;
    for (char ch : raw) {
      if (ch == '(') {
        ++paren;
        continue;
      }
      if (ch == ')') {
        --paren;
        continue;
      }
      if (ch == ';') break;
      if (paren == 0 && !std::isspace(static_cast<unsigned char>(ch)))
        s.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(ch))));
    }
    if (s.empty() || s == "%") continue;
    std::map<char, std::string> words;
    std::vector<double> gcodes;
    for (std::size_t i = 0; i < s.size();) {
      const char letter = s[i++];
      std::size_t j = i;
      while (j < s.size() &&
             (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.' || s[j] == '-' || s[j] == '+'))
        ++j;
      if (!std::isalpha(static_cast<unsigned char>(letter)) || j == i)
        throw std::runtime_error("gcode line " + std::to_string(line) + ": cannot parse '" + raw + "'");
      const std::string val = s.substr(i, j - i);
      if (letter == 'G')
        gcodes.push_back(num(val, line));
      else
        words[letter] = val;
      i = j;
    }
    for (double g : gcodes) {
      if (g == 0 || g == 1 || g == 2 || g == 3)
        motion = static_cast<int>(g);
      else if (g == 17 || g == 21 || g == 90 || g == 94 || g == 40 || g == 49 || g == 80)
        continue;
      else
        throw std::runtime_error("gcode line " + std::to_string(line) + ": unsupported G" + std::to_string(g));
    }
    if (words.count('F')) feed = num(words['F'], line);
    const bool has_xyz = words.count('X') || words.count('Y') || words.count('Z');
    if (!has_xyz) continue;
    if (motion < 0) throw std::runtime_error("gcode line " + std::to_string(line) + ": motion without G mode");
    ReplayMove m;
    m.g = motion;
    m.line = line;
    m.from = {pos[0], pos[1], pos[2]};
    if (!pos_known && !(words.count('X') && words.count('Y')) && motion != 0)
      throw std::runtime_error("gcode line " + std::to_string(line) + ": feed move from an unknown position");
    if (words.count('X')) pos[0] = num(words['X'], line);
    if (words.count('Y')) pos[1] = num(words['Y'], line);
    if (words.count('Z')) pos[2] = num(words['Z'], line);
    if (words.count('X') && words.count('Y')) pos_known = true;
    m.to = {pos[0], pos[1], pos[2]};
    m.feed = motion == 0 ? 0 : feed;
    if (motion != 0 && feed <= 0) r.uses_feed_everywhere = false;
    double xy = std::hypot(m.to[0] - m.from[0], m.to[1] - m.from[1]);
    if (motion == 2 || motion == 3) {
      if (!words.count('I') && !words.count('J'))
        throw std::runtime_error("gcode line " + std::to_string(line) + ": arc without I/J");
      const double I = words.count('I') ? num(words['I'], line) : 0, J = words.count('J') ? num(words['J'], line) : 0;
      m.center = {m.from[0] + I, m.from[1] + J};
      const double rad = std::hypot(I, J);
      const double rad_end = std::hypot(m.to[0] - m.center[0], m.to[1] - m.center[1]);
      if (std::abs(rad - rad_end) > 0.002)
        throw std::runtime_error("gcode line " + std::to_string(line) + ": arc radius mismatch");
      const double a0 = std::atan2(m.from[1] - m.center[1], m.from[0] - m.center[0]);
      const double a1 = std::atan2(m.to[1] - m.center[1], m.to[0] - m.center[0]);
      double sweep = motion == 3 ? a1 - a0 : a0 - a1;
      while (sweep <= 1e-12) sweep += 2 * kPi;  // equal ends = full circle
      xy = rad * sweep;
    }
    if (motion == 0) {
      r.rapid_length += xy;
      if (m.to[2] >= safe_z - 1e-9 && m.from[2] < safe_z - 1e-9 && cut_since_retract) {
        retracted = true;
        cut_since_retract = false;
      }
      last_was_rapid = true;
    } else {
      if (m.to[2] < m.from[2] - 1e-12 && last_was_rapid && m.to[2] < 0) {
        ++r.plunges;
        if (retracted) ++r.retractions;
        retracted = false;
      }
      last_was_rapid = false;
      if (std::min(m.from[2], m.to[2]) < 0) {
        r.cut_length += xy;
        cut_since_retract = true;
        if (std::abs(m.from[2] - m.to[2]) < 1e-9) r.cut_length_by_z[m.to[2]] += xy;
      }
    }
    r.min_z = std::min(r.min_z, m.to[2]);
    r.moves.push_back(m);
  }
  return r;
}

void check_gouge(ReplayResult& r, const ReplayPocket& pocket, double tool_radius, double tol_mm, double step_mm) {
  std::vector<Wall> walls;
  auto add_loop = [&](const ReplayLoop& l) {
    for (std::size_t k = 0; k < l.size(); ++k) {
      const auto& v = l[k];
      const auto& w = l[(k + 1) % l.size()];
      walls.push_back(make_wall({v[0], v[1]}, {w[0], w[1]}, v[2]));
    }
  };
  add_loop(pocket.boundary);
  for (const auto& isl : pocket.islands) add_loop(isl);
  const std::vector<P2> outer = densify(pocket.boundary);
  std::vector<std::vector<P2>> holes;
  for (const auto& isl : pocket.islands) holes.push_back(densify(isl));
  auto region_inside = [&](P2 p) {
    if (!in_poly(outer, p)) return false;
    for (const auto& h : holes)
      if (in_poly(h, p)) return false;
    return true;
  };
  r.samples = 0;
  r.violations = 0;
  r.worst_mm = 0;
  // O(moves · samples · walls): fine for test pockets.
  for (const ReplayMove& m : r.moves) {
    if (std::min(m.from[2], m.to[2]) >= 0) continue;
    double a0 = 0, sweep = 0, rad = 0;
    double L = std::hypot(m.to[0] - m.from[0], m.to[1] - m.from[1]);
    if (m.g == 2 || m.g == 3) {
      rad = std::hypot(m.from[0] - m.center[0], m.from[1] - m.center[1]);
      a0 = std::atan2(m.from[1] - m.center[1], m.from[0] - m.center[0]);
      const double a1 = std::atan2(m.to[1] - m.center[1], m.to[0] - m.center[0]);
      sweep = m.g == 3 ? a1 - a0 : a0 - a1;
      while (sweep <= 1e-12) sweep += 2 * kPi;
      if (m.g == 2) sweep = -sweep;
      L = rad * std::abs(sweep);
    }
    const int n = std::max(1, static_cast<int>(std::ceil(L / step_mm)));
    for (int i = 0; i <= n; ++i) {
      const double t = static_cast<double>(i) / n;
      P2 p;
      if (m.g == 2 || m.g == 3)
        p = {m.center[0] + rad * std::cos(a0 + t * sweep), m.center[1] + rad * std::sin(a0 + t * sweep)};
      else
        p = {m.from[0] + t * (m.to[0] - m.from[0]), m.from[1] + t * (m.to[1] - m.from[1])};
      const double z = m.from[2] + t * (m.to[2] - m.from[2]);
      if (z >= 0) continue;
      ++r.samples;
      double d = std::numeric_limits<double>::infinity();
      for (const Wall& w : walls) d = std::min(d, wall_distance(w, p));
      // The centre changes sides only by crossing a wall (d = 0); samples are step_mm apart, so the
      // side needs testing at the first sample and wherever the centre comes within a step of a wall.
      double intrusion = tool_radius - d;
      if ((i == 0 || d <= step_mm) && !region_inside(p)) intrusion = tool_radius + d;
      if (intrusion > r.worst_mm) r.worst_mm = intrusion;
      if (intrusion > tol_mm) {
        if (r.violations == 0) {
          std::ostringstream os;
          os << "line " << m.line << ": (" << p.x << ", " << p.y << ", " << z << ") intrudes " << intrusion << " mm";
          r.first_violation = os.str();
        }
        ++r.violations;
      }
    }
  }
}

}  // namespace millnet::testing
