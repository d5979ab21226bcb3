#include "millnet/pocket/io/tables.hpp"

#include "millnet/core/atomic_file.hpp"

#include <sstream>

namespace millnet::pocket {

std::vector<std::array<double, 2>> xy_pairs(const std::vector<Vec2>& points) {
  std::vector<std::array<double, 2>> out;
  out.reserve(points.size());
  for (const Vec2& p : points) out.push_back({p.x(), p.y()});  // O(points)
  return out;
}

std::string tool_points_csv(const std::vector<Vec2>& points) {
  std::ostringstream pts;
  pts << "x,y\n";
  for (const auto& p : points) pts << format_double(p.x()) << "," << format_double(p.y()) << "\n";
  return pts.str();
}

std::string feed_profile_csv(const FeedProfile& profile) {
  std::ostringstream feed;
  feed << "chain,segment,s_mm,length_mm,engagement,width_mm,feed_mm_min,mrr_mm3_min,swept_width_mm\n";
  for (const auto& p : profile.pieces)
    feed << p.chain << "," << p.segment << "," << format_double(p.s_mm) << "," << format_double(p.length_mm) << ","
         << format_double(p.engagement) << "," << format_double(p.width_mm) << "," << format_double(p.feed) << ","
         << format_double(p.mrr_mm3_min) << "," << format_double(p.swept_width_mm) << "\n";
  return feed.str();
}

}  // namespace millnet::pocket
