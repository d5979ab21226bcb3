// Pocket and tool-path pictures (the seed's Figs. 17-20) and roughing levels (issue 5).
#include "canvas.hpp"

#include "millnet/report/plots.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

namespace millnet::report {

using namespace detail;
using pocket::Vec2;

namespace {

/// Appends the points of the segment a→b (a already in `out`) with bulge = tan(sweep/4)
/// (> 0 counter-clockwise), sampled so that the chords stay within `tol` of the arc.
/// Our own sampler (not pocket::flatten) so the report needs only the pocket headers.
void append_segment(std::vector<Vec2>& out, const Vec2& a, const Vec2& b, double bulge, double tol) {
  const double c = (b - a).norm();
  if (bulge == 0.0 || c < 1e-12) {
    out.push_back(b);
    return;
  }
  const double theta = 4.0 * std::atan(bulge);  // signed sweep
  const Vec2 u = (b - a) / c;
  const Vec2 left_normal(-u.y(), u.x());
  // Signed distance from the chord's midpoint to the centre along the left normal: the centre of a
  // counter-clockwise minor arc lies to the left of the chord.
  const Vec2 centre = 0.5 * (a + b) + left_normal * (c * (1.0 - bulge * bulge) / (4.0 * bulge));
  const double r = c * (1.0 + bulge * bulge) / (4.0 * std::abs(bulge));
  const double a0 = std::atan2(a.y() - centre.y(), a.x() - centre.x());
  const double max_step = 2.0 * std::acos(std::clamp(1.0 - tol / r, -1.0, 1.0));
  const int n = std::clamp(static_cast<int>(std::ceil(std::abs(theta) / std::max(max_step, 1e-6))), 1, 4096);
  for (int i = 1; i < n; ++i) {  // O(n) samples, n from the chord tolerance
    const double ang = a0 + theta * i / n;
    out.emplace_back(centre.x() + r * std::cos(ang), centre.y() + r * std::sin(ang));
  }
  out.push_back(b);
}

std::vector<Vec2> flatten_loop(const pocket::Loop& loop, double tol) {
  std::vector<Vec2> out;
  if (loop.empty()) return out;
  out.push_back(loop[0].p());
  for (std::size_t k = 0; k < loop.size(); ++k)  // O(vertices + arc samples)
    append_segment(out, loop[k].p(), loop[(k + 1) % loop.size()].p(), loop[k].bulge, tol);
  return out;
}

bool finite_vertex(const pocket::Vertex& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.bulge);
}

// Feeds use viridis up to 0.85: its last yellows are too pale for lines on white.
cv::Scalar feed_colour(double t) { return viridis(0.85 * std::clamp(t, 0.0, 1.0)); }

const cv::Scalar kIslandGrey(190, 190, 190), kPocketTint(252, 248, 244), kRapid(0, 94, 213), kNoFeed(178, 114, 0),
    kToolPoint(233, 180, 86);

}  // namespace

Layout pocket_path_png(const std::filesystem::path& path, const std::vector<pocket::Region>& regions,
                       const std::vector<Vec2>& tool_points, const pocket::Path2D& toolpath,
                       const std::string& title_text, const std::vector<std::pair<std::string, std::string>>& metrics,
                       const PocketPlotOptions& opt) {
  // ---- validate and find the extent: O(vertices + tool points + path vertices)
  double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin, ymin = xmin, ymax = -xmin;
  auto grow = [&](double x, double y) {
    xmin = std::min(xmin, x);
    xmax = std::max(xmax, x);
    ymin = std::min(ymin, y);
    ymax = std::max(ymax, y);
  };
  auto check_loop = [&](const pocket::Loop& l, const std::string& what) {
    for (std::size_t i = 0; i < l.size(); ++i) {
      if (!finite_vertex(l[i])) fail(path, "pocket plot: " + what + " vertex " + std::to_string(i) + " is not finite");
      grow(l[i].x, l[i].y);
    }
  };
  bool any_boundary = false, any_island = false;
  for (std::size_t r = 0; r < regions.size(); ++r) {
    const std::string rn = regions.size() > 1 ? "region " + std::to_string(r) + " " : "";
    check_loop(regions[r].boundary, rn + "boundary");
    for (std::size_t k = 0; k < regions[r].islands.size(); ++k)
      check_loop(regions[r].islands[k], rn + "island " + std::to_string(k));
    any_boundary = any_boundary || !regions[r].boundary.empty();
    any_island = any_island || !regions[r].islands.empty();
  }
  for (std::size_t i = 0; i < tool_points.size(); ++i) {
    if (!tool_points[i].allFinite()) fail(path, "pocket plot: tool point " + std::to_string(i) + " is not finite");
    grow(tool_points[i].x(), tool_points[i].y());
  }
  double fmin = std::numeric_limits<double>::infinity(), fmax = -fmin;
  for (std::size_t c = 0; c < toolpath.chains.size(); ++c) {
    const auto& ch = toolpath.chains[c];
    const std::string which = "pocket plot: chain " + std::to_string(c);
    check_loop(ch.pts, "chain " + std::to_string(c));
    if (!ch.feed.empty() && ch.feed.size() + 1 != ch.pts.size())
      fail(path, which + " has " + std::to_string(ch.feed.size()) + " feeds for " + std::to_string(ch.pts.size()) +
                     " points, expected points - 1 (one per segment) or none");
    for (double f : ch.feed) {
      if (!std::isfinite(f) || f < 0) fail(path, which + " has a feed that is negative or not finite");
      if (f > 0) {
        fmin = std::min(fmin, f);
        fmax = std::max(fmax, f);
      }
    }
  }
  const bool have_feeds = fmax >= fmin;
  if (opt.feed_range) {
    if (!std::isfinite(opt.feed_range->first) || !std::isfinite(opt.feed_range->second) ||
        !(opt.feed_range->second > opt.feed_range->first))
      fail(path, "pocket plot: feed_range must be finite with min < max");
    fmin = opt.feed_range->first;
    fmax = opt.feed_range->second;
  }
  if (!(xmax >= xmin)) {  // nothing at all to draw: an empty frame, still a valid picture
    xmin = ymin = 0;
    xmax = ymax = 1;
  }
  // Margin of 4 % (at least 1 mm) so that the walls do not sit on the frame.
  const double span = std::max({xmax - xmin, ymax - ymin, 1e-9});
  const double pad = std::max(0.04 * span, 1.0);
  Axis x, y;
  x.lo = xmin - pad;
  x.hi = xmax + pad;
  y.lo = ymin - pad;
  y.hi = ymax + pad;

  // ---- layout: equal aspect inside at most kMaxW × kMaxH px
  constexpr double kMaxW = 700, kMaxH = 680;
  const double scale = std::min(kMaxW / (x.hi - x.lo), kMaxH / (y.hi - y.lo));  // px per mm
  const int plot_w = std::max(1, cvRound((x.hi - x.lo) * scale));
  const int plot_h = std::max(1, cvRound((y.hi - y.lo) * scale));
  // Recompute the ranges from the rounded pixel box so that one mm is the same on both axes.
  x.hi = x.lo + plot_w / scale;
  y.hi = y.lo + plot_h / scale;
  int yw = 0;
  {
    const double step = nice_step(y.lo, y.hi, 6);
    for (double v : nice_ticks(y.lo, y.hi, 6)) yw = std::max(yw, text_size(tick_label(v, step), kTickFont).width);
  }
  const int right_panel = have_feeds ? 170 : 30;
  const int left = std::max(60 + yw, (kWidth - right_panel - plot_w) / 2 + 30);
  const int top = title_height(title_text) + 6;
  const int bottom = top + plot_h;

  std::vector<LegendItem> items;
  if (any_boundary) items.push_back({"boundary", kBlack, LegendKind::Line});
  if (any_island) items.push_back({"island", kIslandGrey, LegendKind::Box});
  if (opt.show_tool_points && !tool_points.empty())
    items.push_back({"tool point (" + std::to_string(tool_points.size()) + ")", kToolPoint, LegendKind::Dot});
  if (!toolpath.chains.empty())
    items.push_back(
        {have_feeds ? "cut (colour = feed)" : "cut", have_feeds ? feed_colour(0.5) : kNoFeed, LegendKind::Line});
  if (toolpath.chains.size() > 1) items.push_back({"rapid (retract)", kRapid, LegendKind::Dashed});
  std::size_t n_drill = 0;
  for (const auto& ch : toolpath.chains) n_drill += (ch.predrill && !ch.pts.empty()) ? 1U : 0U;
  if (n_drill > 0) items.push_back({"pre-drill (" + std::to_string(n_drill) + ")", kBlack, LegendKind::CircledCross});
  const int lx = 40, lw = kWidth - 80;
  const int legend_h = legend(nullptr, items, lx, 0, lw);

  std::vector<std::string> mtext;
  int mw = 0;
  for (const auto& [k, v] : metrics) {
    mtext.push_back(ascii(k) + ": " + ascii(v));
    mw = std::max(mw, text_size(mtext.back(), kTickFont).width);
  }
  constexpr int kLine = 20;
  const int mcols = mtext.empty() ? 1 : std::clamp(lw / (mw + 30), 1, 4);
  const int mrows =
      static_cast<int>((mtext.size() + static_cast<std::size_t>(mcols) - 1) / static_cast<std::size_t>(mcols));
  const int metrics_h = mtext.empty() ? 0 : mrows * kLine + 14;

  cv::Mat img(bottom + 64 + legend_h + 8 + metrics_h + 10, kWidth, CV_8UC3, kWhite);
  title(img, title_text);
  x.p0 = left;
  x.p1 = left + plot_w;
  y.p0 = bottom;
  y.p1 = top;
  const double tol_mm = 0.2 / scale;  // chords within 0.2 px of the true arcs
  auto px = [&](const Vec2& p) { return cv::Point2d(x.to_px(p.x()), y.to_px(p.y())); };
  auto to_px = [&](const std::vector<Vec2>& pts) {
    std::vector<cv::Point2d> out;
    out.reserve(pts.size());
    for (const auto& p : pts) out.push_back(px(p));
    return out;
  };

  // ---- region: tinted pocket floor, grey islands, outlines on top
  std::vector<std::vector<cv::Point2d>> boundaries_px, islands_px;
  for (const auto& region : regions) {
    boundaries_px.push_back(to_px(flatten_loop(region.boundary, tol_mm)));
    for (const auto& isl : region.islands) islands_px.push_back(to_px(flatten_loop(isl, tol_mm)));
  }
  draw_axes(img, x, y, "x (mm)", "y (mm)");
  // Everything inside the frame is drawn into the plot box so that nothing spills over the axes.
  const cv::Rect box(left + 1, top + 1, plot_w - 1, plot_h - 1);
  cv::Mat plot = img(box);
  const cv::Point2d o(box.x, box.y);
  auto shift = [&](std::vector<cv::Point2d> v) {
    for (auto& p : v) p -= o;
    return v;
  };
  // One fillPoly per region: several disjoint pockets of a roughing level each get their floor.
  for (const auto& b : boundaries_px) fill_polygons(plot, {shift(b)}, kPocketTint);
  {
    std::vector<std::vector<cv::Point2d>> isl;
    for (const auto& i : islands_px) isl.push_back(shift(i));
    fill_polygons(plot, isl, kIslandGrey);
  }
  for (const auto& b : boundaries_px)
    if (b.size() >= 2) polyline(plot, shift(b), kBlack, 2);
  for (const auto& i : islands_px)
    if (i.size() >= 2) polyline(plot, shift(i), kBlack, 2);

  if (opt.show_tool_points)
    for (const auto& p : tool_points) circle_at(plot, px(p) - o, 2.2, kToolPoint, -1);  // O(tool points)

  // ---- path: rapids first (under the cuts), then cuts per segment coloured by feed
  const auto& chains = toolpath.chains;
  for (std::size_t c = 0; c + 1 < chains.size(); ++c) {
    if (chains[c].pts.empty() || chains[c + 1].pts.empty()) continue;
    dashed_polyline(plot, {px(chains[c].pts.back().p()) - o, px(chains[c + 1].pts.front().p()) - o}, kRapid, 1, 7, 5);
  }
  for (const auto& ch : chains) {  // O(path vertices + arc samples)
    for (std::size_t k = 0; k + 1 < ch.pts.size(); ++k) {
      std::vector<Vec2> seg{ch.pts[k].p()};
      append_segment(seg, ch.pts[k].p(), ch.pts[k + 1].p(), ch.pts[k].bulge, tol_mm);
      cv::Scalar colour = kNoFeed;
      if (!ch.feed.empty() && ch.feed[k] > 0)
        colour = feed_colour(fmax > fmin ? (ch.feed[k] - fmin) / (fmax - fmin) : 0.5);
      polyline(plot, shift(to_px(seg)), colour, 2);
    }
    if (ch.pts.size() == 1) circle_at(plot, px(ch.pts[0].p()) - o, 2.5, kNoFeed, -1);
  }
  for (const auto& ch : chains) {
    if (!ch.predrill || ch.pts.empty()) continue;
    const cv::Point2d m = px(ch.pts.front().p()) - o;
    circle_at(plot, m, 7, kBlack, 2);
    line(plot, m + cv::Point2d(-5, -5), m + cv::Point2d(5, 5), kBlack, 2);
    line(plot, m + cv::Point2d(-5, 5), m + cv::Point2d(5, -5), kBlack, 2);
  }

  if (have_feeds) {
    const int ch = std::min(plot_h, 360);
    colour_bar(img, left + plot_w + 30, top, 24, top + ch, fmin, fmax, "feed (mm/min)", &feed_colour);
  }
  int yy = bottom + 64;
  legend(&img, items, lx, yy, lw);
  yy += legend_h + 8;
  if (!mtext.empty()) {
    line(img, {static_cast<double>(lx), yy + 0.5}, {static_cast<double>(lx + lw), yy + 0.5}, kGridGrey, 1);
    const int colw = lw / mcols;
    for (std::size_t i = 0; i < mtext.size(); ++i) {  // column-major so that related rows stay together
      const int col = static_cast<int>(i) / mrows, row = static_cast<int>(i) % mrows;
      put_text(img, mtext[i], {lx + col * colw, yy + 8 + row * kLine}, kTickFont, kBlack, HAlign::Left, VAlign::Top);
    }
  }
  write_png(path, img);
  return make_layout(img, x, y);
}

Layout pocket_path_png(const std::filesystem::path& path, const pocket::Region& region,
                       const std::vector<Vec2>& tool_points, const pocket::Path2D& toolpath,
                       const std::string& title_text, const std::vector<std::pair<std::string, std::string>>& metrics,
                       const PocketPlotOptions& opt) {
  return pocket_path_png(path, std::vector<pocket::Region>{region}, tool_points, toolpath, title_text, metrics, opt);
}

Layout level_png(const std::filesystem::path& path, const pocket::Region& region, const pocket::Path2D& toolpath,
                 double z_mm, const std::string& title_text,
                 const std::vector<std::pair<std::string, std::string>>& metrics, const PocketPlotOptions& opt) {
  return level_png(path, std::vector<pocket::Region>{region}, toolpath, z_mm, title_text, metrics, opt);
}

Layout level_png(const std::filesystem::path& path, const std::vector<pocket::Region>& regions,
                 const pocket::Path2D& toolpath, double z_mm, const std::string& title_text,
                 const std::vector<std::pair<std::string, std::string>>& metrics, const PocketPlotOptions& opt) {
  if (!std::isfinite(z_mm)) fail(path, "level plot: Z is not finite");
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f", z_mm);
  const std::string t =
      title_text.empty() ? std::string("level Z = ") + buf + " mm" : title_text + " - level Z = " + buf + " mm";
  PocketPlotOptions o = opt;
  o.show_tool_points = false;
  return pocket_path_png(path, regions, {}, toolpath, t, metrics, o);
}

}  // namespace millnet::report
