#pragma once
// Named tolerances of the finishing strategies. Lengths in mm, angles in degrees.
#include <cstddef>

namespace millnet::finish::tol {

/// A straight feed move may pass below the CL surface between its end points by at most this
/// (the simulator calls −0.002 mm a gouge; this keeps the path clear of it).
inline constexpr double chord_below_mm = 0.001;

/// Along a raster pass, CL points are first dropped this far apart (at most a quarter of the
/// cutter radius), then intervals are halved where the chord tests fail.
inline constexpr double initial_sample_mm = 0.1;

/// Adaptive halving stops at this interval length.
inline constexpr double min_sample_mm = 0.002;

/// Grid of CL heights that seeds the waterline contours (at most half the cutter radius); contour
/// points are then refined with the drop-cutter to the chord tolerance.
inline constexpr double waterline_grid_mm = 0.25;

/// Most Z levels of the waterline strategies, counted before any is computed (issue 15: a step-down
/// of 1e-9 mm counted levels in an int that overflowed).
inline constexpr double max_waterline_levels = 20000;

/// Grid of the fast-marching surface distance of the equidistant strategy (at most p_f / 2).
inline constexpr double equidistant_grid_mm = 0.1;

/// Slope mode: raster keeps points shallower than boundary + this, Z-level points steeper than
/// boundary − this, so the two bands overlap.
inline constexpr double slope_overlap_deg = 2.0;

/// Scallop-height mode: passes never come closer than p_f times this (a vertical wall along the
/// passes would otherwise ask for infinitely many).
inline constexpr double scallop_min_spacing_rel = 0.1;

/// Links up to this XY length (times the cutter diameter, plus 4 p_f) follow the surface at feed
/// instead of lifting.
inline constexpr double stay_down_link_diameters = 2.0;

/// Rest finishing: a pass's entry comes down at rapid to this above the stock left before it (an
/// upper bound of it: the reference's envelope, or the simulated stock under the tool), then plunges
/// at the plunge feed, so that an entry feeds through a tenth of a millimetre of air, not the
/// clearance.
inline constexpr double rest_approach_mm = 0.1;

/// Rest finishing: a move that lowers the stock less than this feeds through air (as the job's
/// air_cut_share counts it: job::kAirCutMm).
inline constexpr double rest_air_cut_mm = 0.001;

/// Rest finishing: a stay-down link's run of moves through air this many tool radii long or longer
/// is hopped over (up at rapid, across, down at the plunge feed into the next move that cuts)
/// instead of fed through. 0.6 R (0.3 mm for the Ø1): on s4 of README command 1 the rest program's
/// air 13.0 → 7.6 % of its feed for 6.56 → 7.00 min; 0.3 R: 5.5 % for 7.33 min (docs/finishing.md).
inline constexpr double rest_air_hop_radii = 0.6;

/// Rest finishing: two pieces of one pass that remove rest, this many tool radii apart or closer
/// along the pass, are cut as one (the tool stays on the pass instead of lifting and plunging).
inline constexpr double rest_bridge_radii = 1.0;

/// Rest finishing: a pass is probed every this many tool radii along its path (the drops that
/// decide where it cuts).
inline constexpr double rest_probe_radii = 0.0625;

/// Rest finishing: a pass piece runs on this many tool radii past its last probe over rest. R/32:
/// on s4 of README command 1 it leaves the same rest as R/8 and R/16 (with the design points'
/// test: missed 1.87 mm² at R/16, 1.90 at R/32) and air 10.9 → 9.9 % of the feed path (without
/// it, R/16: 9.3 → 8.1 %); R/8 had left the same rest as R/4 (187.25 vs 187.26 mm² then) with
/// 15 % less feed path.
inline constexpr double rest_run_on_radii = 0.03125;

/// Rest finishing, from a stock: a probe is kept where the tool comes within the threshold of a
/// design point with more than this many thresholds of rest, not yet cleared (detail::RestPoints;
/// issue 41's yardstick: a cell is missed where no program comes that near). 1 (with the run-on
/// at R/32) on s4 of README command 1: missed rest 3.68 → 1.90 mm², air 9.3 → 9.9 % of the feed
/// path, rest time 5.37 → 6.24 min; at 1.25, 2.13 mm² at 9.4 %; at 1.5 (run-on R/16), 2.42 mm²
/// at 10.1 %.
inline constexpr double rest_point_thresholds = 1.0;

/// Rest finishing: a pass is also kept where the tool standing on it would take more than this
/// many rest thresholds off what was left as the pieces kept before it leave it (normal to the
/// tool, RestStock::removal), though its contact reads none: in a crease between two steep faces
/// the tool touches one face or the other while the rest stands between them. 1.5: on s4 of README
/// command 1 (with the links' cuts followed) missed rest 6.15 → 4.33 mm², air 8.5 → 9.3 %; at 1
/// 2.67 mm² but 11.9 % air, at 2 5.96 mm² (without the links' cuts).
inline constexpr double rest_keep_removal_thresholds = 1.5;

/// Rest finishing: the most grid nodes the design points with rest are sampled on
/// (detail::RestPoints; 16 M: 10,000 mm² at 0.025 mm).
inline constexpr double rest_points_max = 1.6e7;

/// Rest finishing: a pass point this far above the tool's drop at its XY, and more than half the
/// rest threshold, hangs beside a vertical wall (a Z-level): it touches the wall at its widest, not
/// at the drop's contact. Nearer its drop (a Z-level point on a sloped wall, refined to the air side
/// of the level within the chord tolerance: 0.009 mm above its drop on a 60° wall at 0.005 mm) the
/// drop's contact is within that of the tool — at its widest the tool would stand off such a wall.
inline constexpr double rest_hanging_mm = 1e-3;

/// Rest finishing's aimed passes (detail::aim_at_rest, stop 74): the pattern search for the tool's
/// placement nearest to a design point the trimmed passes left starts with steps of
/// rest_aim_step_radii · R (halved down to a 32nd of it) and stops once within rest_aim_within
/// thresholds of the point. A placement is kept where it reaches at least rest_aim_min_points
/// points not yet cleared: on README command 1's s1 and s4 (docs/finishing.md, "Passes aimed at
/// what the passes left") every placement took their rest programs' missed rest to 0.34 / 1.49
/// mm² with 10.8 / 9.7 % air, those reaching 2 points to 0.40 / 1.63 mm² with 9.1 / 10.1 %, and
/// those reaching 4 to 0.40 / 1.77 mm² with 8.8 / 9.5 % — the one setting tried with both under
/// the 10 %. Placements are chained within rest_aim_link_radii · R of each other (the
/// tool sweeps the chord between them; on s4, every placement kept, links of R/2, R, 2R and 4R
/// left 1.58, 1.53, 1.49 and 1.46 mm², and 2R took the least time, 5.73 min), and a chord between
/// two of them that rises rest_aim_rise_radii · R over both its ends (over a ridge between two
/// creases) splits the chain.
inline constexpr double rest_aim_step_radii = 0.25;
inline constexpr double rest_aim_within = 0.5;
inline constexpr std::size_t rest_aim_min_points = 4;
/// The same where the stock's rest was measured by the programs that left it (/finish/rest/measure
/// "programs", RestStock::exact_mm): every placement that reaches a point is kept. On s4 / s1 of
/// README command 1 (stop 76) that took the rest operation's missed rest from 0.81 / 0.36 to 0.49 /
/// 0.30 mm², its air from 13.6 / 10.8 to 13.0 / 11.1 % and its time from 6.96 / 7.17 to 6.56 / 6.39
/// min: the confirmed misses there are specks of 1–3 cells that no placement reaching 4 points covers.
inline constexpr std::size_t rest_aim_min_points_measured = 1;
inline constexpr double rest_aim_link_radii = 2.0;
inline constexpr double rest_aim_rise_radii = 0.125;

/// Passes (and pieces of passes) shorter than this are dropped.
inline constexpr double min_pass_mm = 0.01;

/// Machining boundaries: a tool axis within this of a non-vertical face's XY projection is over
/// the part (so that a pass along the footprint's edge, exactly on it, is kept).
inline constexpr double on_part_mm = 1e-6;

/// Machining boundaries: where a pass crosses, the crossing on its segment is found by bisection
/// to this (the segment's own points, so the path stays as safe as planned).
inline constexpr double boundary_crossing_mm = 1e-5;

}  // namespace millnet::finish::tol
