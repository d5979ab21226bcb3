#pragma once
// The CSV tables `millnet pocket` writes beside a program (adapter millnet::pocket_io): numbers in
// shortest round-trip form (millnet::format_double), readable with numpy, pandas or a spreadsheet.
#include "millnet/pocket/feedmap.hpp"
#include "millnet/pocket/geometry.hpp"

#include <array>
#include <string>
#include <vector>

namespace millnet::pocket {

/// The points as [x, y] pairs (for the metrics' lists of points).
[[nodiscard]] std::vector<std::array<double, 2>> xy_pairs(const std::vector<Vec2>& points);

/// "x,y" then one line per tool point, in the given order.
[[nodiscard]] std::string tool_points_csv(const std::vector<Vec2>& points);

/// "chain,segment,s_mm,length_mm,engagement,width_mm,feed_mm_min,mrr_mm3_min" then one line per piece.
[[nodiscard]] std::string feed_profile_csv(const FeedProfile& profile);

}  // namespace millnet::pocket
