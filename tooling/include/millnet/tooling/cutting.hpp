#pragma once
// Cutting data: a tool and a workpiece material in, spindle speed and feeds out — what a
// commercial CAM system's tool and material libraries do (Fusion's tool library, FreeCAD's
// ToolBits, HSMAdvisor). Plain structs; the JSON libraries (configs/tools.json,
// configs/materials.json) are read in app/.
//
// The formulas (all mm, m/min, rpm, mm/min):
//   D_eff  effective cutting diameter at axial depth a_p:
//            flat, drill:  D
//            ball (R = D/2):  2·√(a_p·(D − a_p))            for a_p < R, else D
//            bull (corner r): (D − 2r) + 2·√(a_p·(2r − a_p))  for a_p < r, else D
//   n      = 1000·V_c / (π·D_eff), then capped by the tool's and the machine's max rpm
//            (the cut then runs at a lower V_c; fz is kept, so the feed drops with n).
//   f      = f_z·z·n  (z flutes), capped at the machine's max feed.
//   Radial chip thinning: below half-diameter engagement the chip is thinner than f_z; the feed
//   that restores the chip thickness is f·RCTF with
//            RCTF(a_e) = D / (2·√(a_e·(D − a_e)))   for a_e < D/2, else 1,
//          capped at FeedFactors::max_chip_thinning (1.667 at a_e = 10 % D).
//   Slot (a_e = D): f·slot (full engagement, chips evacuate worse); plunge f·plunge, ramp and
//   helix entries f·ramp: the documented fractions of FeedFactors.
#include "millnet/tooling/cutter.hpp"

#include <string>
#include <vector>

namespace millnet::tooling {

/// Largest tool number (T) and length-offset register (H) a tool library holds.
inline constexpr int kMaxToolNumber = 99999;
/// Largest holder diameter and length a tool library holds, mm.
inline constexpr double kMaxHolderMm = 10000;

/// A tool's type is its cutter's (cutter.hpp): one enumeration for both.
using ToolType = CutterType;
enum class ToolMaterial { Carbide, HSS };

[[nodiscard]] const char* to_string(ToolType t);
[[nodiscard]] const char* to_string(ToolMaterial m);
/// "flat" | "ball" | "bull" | "drill"; throws millnet::Error naming the accepted values.
[[nodiscard]] ToolType parse_tool_type(const std::string& s);
/// "carbide" | "hss"; throws millnet::Error naming the accepted values.
[[nodiscard]] ToolMaterial parse_tool_material(const std::string& s);

struct Tool {
  std::string id;  ///< library id; empty for a tool given inline (by its geometry)
  std::string description;
  ToolType type = ToolType::Flat;
  double diameter_mm = 10;
  double corner_radius_mm = 0;  ///< bull only; ball = D/2, flat = 0
  int flutes = 2;
  double flute_length_mm = 0;  ///< 0 = not stated (no depth check)
  double stickout_mm = 0;      ///< length out of the holder; 0 = not stated
  ToolMaterial material = ToolMaterial::Carbide;
  double max_rpm = 0;  ///< the tool's own limit; 0 = none
  /// Drill only: the included angle of the tip, degrees, in (0, 180) (Cutter::point_angle_deg).
  double point_angle_deg = kDefaultPointAngleDeg;
  // Where the tool sits on the machine (issue 40). None of these is part of label(): programs'
  // headers and metrics name a tool as before.
  int number = 0;         ///< T: the tool changer's tool number, in [0, kMaxToolNumber]; 0 = not assigned
  int length_offset = 0;  ///< H: the length-offset register G43 reads, in [0, kMaxToolNumber]; 0 = the tool's number
  /// The holder, as a cylinder around the tool from its face (where the stick-out ends) up to the
  /// spindle: its largest diameter and its length, mm; 0 = not stated. A stated holder is at least as
  /// wide as the tool (the tool's shank sits inside it).
  double holder_diameter_mm = 0;
  double holder_length_mm = 0;
  /// Throws millnet::Error "<who>: <field> …" on a non-finite or out-of-range field, and
  /// "<who>: cutter: …" when its shape fails Cutter::check (a flat tool with a corner radius).
  void check(const std::string& who) const;
  /// The H register G43 reads: length_offset, or the tool's number when length_offset is 0.
  [[nodiscard]] int length_offset_register() const { return length_offset > 0 ? length_offset : number; }
  /// Its cutting shape with its flute length and stick-out (the one every module takes).
  [[nodiscard]] Cutter cutter() const;
  /// "em10-3f: D10 mm 3-flute carbide flat end mill" (or "D10 mm 2-flute carbide flat end mill
  /// (inline)"); ASCII, fit for a G-code comment.
  [[nodiscard]] std::string label() const;
};

/// One row of a material's table: V_c and f_z for a tool material over a diameter range.
struct CuttingRange {
  ToolMaterial tool_material = ToolMaterial::Carbide;
  double d_min_mm = 0, d_max_mm = 0;  ///< applies to D_nominal in [d_min, d_max)
  double vc_m_min = 0;
  double fz_mm = 0;
  std::string source;  ///< where the figure comes from (handbook, paper, shop)
};

struct Material {
  std::string id, name;
  std::vector<CuttingRange> ranges;
  /// The row for this tool material and nominal diameter; throws millnet::Error naming the
  /// material, the tool material and the diameter when none covers it.
  [[nodiscard]] const CuttingRange& range_for(ToolMaterial tm, double diameter_mm) const;
};

struct MachineLimits {
  double max_rpm = 24000;
  double min_rpm = 0;  ///< a computed speed below this is an error
  double max_feed_mm_min = 5000;
};

struct FeedFactors {
  double slot = 0.8;             ///< full-width slot feed / half-width feed
  double plunge = 0.3;           ///< straight plunge (a drill: 1, its own f_z·n)
  double ramp = 0.5;             ///< ramp and helix entries
  double max_chip_thinning = 3;  ///< cap of RCTF (≈ a_e 2.9 % of D)
};

/// Optional overrides of the library's figures (0 = from the table).
struct Overrides {
  double vc_m_min = 0, fz_mm = 0, rpm = 0;
};

[[nodiscard]] double effective_diameter(const Tool& tool, double axial_depth_mm);
/// RCTF above, uncapped; radial_mm in (0, D].
[[nodiscard]] double chip_thinning_factor(double diameter_mm, double radial_mm);

struct CuttingData {
  double vc_m_min = 0;  ///< from the table (or override)
  double fz_mm = 0;
  int flutes = 0;
  double axial_depth_mm = 0, d_eff_mm = 0;
  double rpm_computed = 0;     ///< 1000·V_c/(π·D_eff)
  double rpm = 0;              ///< what the program runs at
  std::string rpm_limited_by;  ///< "" | "tool max rpm" | "machine max rpm" | "override"
  double feed_mm_min = 0;      ///< half-width or more: f_z·z·n (capped by the machine)
  bool feed_limited = false;   ///< capped at the machine's max feed
  double feed_slot_mm_min = 0;
  double feed_plunge_mm_min = 0, feed_ramp_mm_min = 0;  ///< ramp: ramp and helix entries
  double feed_max_mm_min = 0;                           ///< highest thinned feed: min(machine max, feed·max RCTF)
  double max_chip_thinning = 1;
  std::string source;  ///< the material row's source
  /// Feed at radial engagement a_e (mm): feed·RCTF(a_e) capped at feed_max_mm_min;
  /// a_e ≥ D/2 ⇒ feed (the caller interpolates towards the slot feed).
  [[nodiscard]] double feed_at(double diameter_mm, double radial_mm) const;
};

/// The cutting data of `tool` in `material` at axial depth `axial_depth_mm` (> 0; for a ball or
/// bull nose it sets D_eff). Throws millnet::Error naming which limit and by how much when the
/// speed falls below the machine's minimum or an override exceeds the machine's or tool's limits.
[[nodiscard]] CuttingData cutting_data(const Tool& tool, const Material& material, double axial_depth_mm,
                                       const MachineLimits& machine, const FeedFactors& factors,
                                       const Overrides& overrides = {});

}  // namespace millnet::tooling
