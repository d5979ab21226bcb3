// Cutting data: D_eff, spindle speed, feeds, radial chip thinning (formulas in cutting.hpp).
#include "millnet/tooling/cutting.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace millnet::tooling {

const char* to_string(ToolType t) {
  switch (t) {
    case ToolType::Flat: return "flat";
    case ToolType::Ball: return "ball";
    case ToolType::Bull: return "bull";
    case ToolType::Drill: return "drill";
  }
  return "?";
}

const char* to_string(ToolMaterial m) { return m == ToolMaterial::Carbide ? "carbide" : "hss"; }

ToolType parse_tool_type(const std::string& s) {
  if (s == "flat") return ToolType::Flat;
  if (s == "ball") return ToolType::Ball;
  if (s == "bull") return ToolType::Bull;
  if (s == "drill") return ToolType::Drill;
  throw Error("tool type \"" + s.substr(0, 40) + "\": expected flat, ball, bull or drill");
}

ToolMaterial parse_tool_material(const std::string& s) {
  if (s == "carbide") return ToolMaterial::Carbide;
  if (s == "hss" || s == "HSS") return ToolMaterial::HSS;
  throw Error("tool material \"" + s.substr(0, 40) + "\": expected carbide or hss");
}

void Tool::check(const std::string& who) const {
  const std::string at = who + (id.empty() ? std::string() : " " + id);
  auto in = [&](double v, double lo, double hi, const char* what) {
    if (!(std::isfinite(v) && v >= lo && v <= hi))
      throw Error(at + ": " + what + " " + format_double(v) + " is outside [" + format_double(lo) + ", " +
                  format_double(hi) + "]");
  };
  if (!(diameter_mm > 0 && diameter_mm <= 1000))
    throw Error(at + ": diameter " + format_double(diameter_mm) + " mm must be in (0, 1000]");
  in(corner_radius_mm, 0, diameter_mm / 2, "corner radius (mm)");
  if (type == ToolType::Bull && !(corner_radius_mm > 0))
    throw Error(at + ": a bull-nose tool needs a corner radius > 0");
  if (flutes < 1 || flutes > 64) throw Error(at + ": flutes " + std::to_string(flutes) + " is outside [1, 64]");
  in(flute_length_mm, 0, 10000, "flute length (mm)");
  in(stickout_mm, 0, 10000, "stick-out (mm)");
  if (stickout_mm > 0 && flute_length_mm > stickout_mm)
    throw Error(at + ": flute length " + format_double(flute_length_mm) + " mm exceeds the stick-out " +
                format_double(stickout_mm) + " mm");
  in(max_rpm, 0, 500000, "max rpm");
  if (type == ToolType::Drill && !(point_angle_deg > 0 && point_angle_deg < 180))
    throw Error(at + ": point angle " + format_double(point_angle_deg) + " deg must be in (0, 180)");
  auto whole = [&](int v, const char* what) {
    if (v < 0 || v > kMaxToolNumber)
      throw Error(at + ": " + what + " " + std::to_string(v) + " is outside [0, " + std::to_string(kMaxToolNumber) +
                  "]");
  };
  whole(number, "tool number (T)");
  whole(length_offset, "length offset (H)");
  in(holder_diameter_mm, 0, kMaxHolderMm, "holder diameter (mm)");
  in(holder_length_mm, 0, kMaxHolderMm, "holder length (mm)");
  // The shank sits inside the holder: a stated holder narrower than the tool is a typing error.
  if (holder_diameter_mm > 0 && holder_diameter_mm < diameter_mm)
    throw Error(at + ": holder diameter " + format_double(holder_diameter_mm) + " mm is narrower than the tool (" +
                format_double(diameter_mm) + " mm)");
  try {
    cutter().check();
  } catch (const Error& e) {
    throw Error(at + ": " + e.what());
  }
}

Cutter Tool::cutter() const {
  Cutter c;
  switch (type) {
    case ToolType::Flat: c = Cutter::flat(diameter_mm); break;
    case ToolType::Ball: c = Cutter::ball(diameter_mm); break;
    case ToolType::Bull: c = Cutter::bull(diameter_mm, corner_radius_mm); break;
    case ToolType::Drill: c = Cutter::drill(diameter_mm, point_angle_deg); break;
  }
  // A library's flat tool with a corner radius is not silently made sharp: check() refuses it.
  if (type == ToolType::Flat || type == ToolType::Drill) c.corner_radius = corner_radius_mm;
  c.flute_length_mm = flute_length_mm;
  c.reach_mm = stickout_mm;
  return c;
}

std::string Tool::label() const {
  std::string s = (id.empty() ? std::string() : id + ": ") + "D" + format_double(diameter_mm) + " mm ";
  if (type == ToolType::Bull) s += "r" + format_double(corner_radius_mm) + " ";
  s += std::to_string(flutes) + "-flute " + to_string(material) + " ";
  switch (type) {
    case ToolType::Flat: s += "flat end mill"; break;
    case ToolType::Ball: s += "ball-nose end mill"; break;
    case ToolType::Bull: s += "bull-nose end mill"; break;
    case ToolType::Drill: s += "drill"; break;
  }
  if (id.empty()) s += " (inline)";
  return s;
}

const CuttingRange& Material::range_for(ToolMaterial tm, double d) const {
  for (const CuttingRange& r : ranges)
    if (r.tool_material == tm && d >= r.d_min_mm && d < r.d_max_mm) return r;
  throw Error("material " + id + " has no cutting data for a " + to_string(tm) + " tool of Ø" + format_double(d) +
              " mm");
}

double effective_diameter(const Tool& tool, double ap) {
  const double D = tool.diameter_mm;
  if (!(ap > 0)) throw Error("cutting data: axial depth " + format_double(ap) + " mm must be > 0");
  const double r = tool.type == ToolType::Ball ? D / 2 : tool.type == ToolType::Bull ? tool.corner_radius_mm : 0.0;
  if (r <= 0 || ap >= r) return D;
  return (D - 2 * r) + 2 * std::sqrt(ap * (2 * r - ap));
}

double chip_thinning_factor(double D, double ae) {
  if (!(ae > 0)) throw Error("cutting data: radial engagement " + format_double(ae) + " mm must be > 0");
  if (ae >= D / 2) return 1.0;
  return D / (2 * std::sqrt(ae * (D - ae)));
}

double CuttingData::feed_at(double D, double ae) const {
  if (ae >= D / 2) return feed_mm_min;
  const double k = std::min(chip_thinning_factor(D, std::max(ae, 1e-9 * D)), max_chip_thinning);
  return std::min(feed_mm_min * k, feed_max_mm_min);
}

CuttingData cutting_data(const Tool& tool, const Material& material, double ap, const MachineLimits& m,
                         const FeedFactors& ff, const Overrides& ov) {
  tool.check("tool");
  const CuttingRange& row = material.range_for(tool.material, tool.diameter_mm);
  CuttingData c;
  c.vc_m_min = ov.vc_m_min > 0 ? ov.vc_m_min : row.vc_m_min;
  c.fz_mm = ov.fz_mm > 0 ? ov.fz_mm : row.fz_mm;
  c.flutes = tool.flutes;
  c.axial_depth_mm = ap;
  c.d_eff_mm = effective_diameter(tool, ap);
  c.source = row.source;
  c.rpm_computed = 1000 * c.vc_m_min / (std::numbers::pi * c.d_eff_mm);
  c.rpm = c.rpm_computed;
  const std::string who = "cutting data for " + tool.label() + " in " + material.id;
  if (ov.rpm > 0) {
    if (tool.max_rpm > 0 && ov.rpm > tool.max_rpm)
      throw Error(who + ": spindle speed " + format_double(ov.rpm) + " rpm exceeds the tool's max " +
                  format_double(tool.max_rpm) + " rpm by " + format_double(ov.rpm - tool.max_rpm) + " rpm");
    if (ov.rpm > m.max_rpm)
      throw Error(who + ": spindle speed " + format_double(ov.rpm) + " rpm exceeds the machine's max " +
                  format_double(m.max_rpm) + " rpm by " + format_double(ov.rpm - m.max_rpm) + " rpm");
    c.rpm = ov.rpm;
    c.rpm_limited_by = "override";
  } else {
    if (tool.max_rpm > 0 && c.rpm > tool.max_rpm) {
      c.rpm = tool.max_rpm;
      c.rpm_limited_by = "tool max rpm";
    }
    if (c.rpm > m.max_rpm) {
      c.rpm = m.max_rpm;
      c.rpm_limited_by = "machine max rpm";
    }
    c.rpm = std::round(c.rpm);  // a spindle speed is programmed in whole rpm
  }
  if (c.rpm < m.min_rpm)
    throw Error(who + ": spindle speed " + format_double(std::round(c.rpm)) + " rpm is below the machine's minimum " +
                format_double(m.min_rpm) + " rpm by " + format_double(std::round(m.min_rpm - c.rpm)) + " rpm");
  // Feeds are programmed in whole mm/min (at least 1).
  auto whole = [](double v) { return std::max(1.0, std::round(v)); };
  const double f = c.fz_mm * c.flutes * c.rpm;
  c.feed_mm_min = whole(std::min(f, m.max_feed_mm_min));
  c.feed_limited = f > m.max_feed_mm_min;
  c.feed_slot_mm_min = whole(c.feed_mm_min * ff.slot);
  c.feed_plunge_mm_min = tool.type == ToolType::Drill ? c.feed_mm_min : whole(c.feed_mm_min * ff.plunge);
  c.feed_ramp_mm_min = whole(c.feed_mm_min * ff.ramp);
  c.max_chip_thinning = std::max(1.0, ff.max_chip_thinning);
  c.feed_max_mm_min = std::min(m.max_feed_mm_min, whole(c.feed_mm_min * c.max_chip_thinning));
  if (!(c.feed_mm_min > 0)) throw Error(who + ": feed " + format_double(c.feed_mm_min) + " mm/min is not > 0");
  return c;
}

}  // namespace millnet::tooling
