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

/// What the picture must show: the box of every vertex and tool point, which kinds of loop there
/// are, and the feeds' range (feed_range, else the positive feeds'; have_feeds: there are some).
struct Extent {
  double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin, ymin = xmin, ymax = -xmin;
  bool any_boundary = false, any_island = false;
  double fmin = std::numeric_limits<double>::infinity(), fmax = -fmin;
  bool have_feeds = false;
  void grow(double x, double y) {
    xmin = std::min(xmin, x);
    xmax = std::max(xmax, x);
    ymin = std::min(ymin, y);
    ymax = std::max(ymax, y);
  }
};

/// Checks the input (finite vertices and tool points, one feed per segment or none, feeds ≥ 0) and
/// measures its extent. O(vertices + tool points + path vertices).
Extent checked_extent(const std::filesystem::path& path, const std::vector<pocket::Region>& regions,
                      const std::vector<Vec2>& tool_points, const pocket::Path2D& toolpath,
                      const PocketPlotOptions& opt) {
  Extent e;
  auto check_loop = [&](const pocket::Loop& l, const std::string& what) {
    for (std::size_t i = 0; i < l.size(); ++i) {
      if (!finite_vertex(l[i])) fail(path, "pocket plot: " + what + " vertex " + std::to_string(i) + " is not finite");
      e.grow(l[i].x, l[i].y);
    }
  };
  for (std::size_t r = 0; r < regions.size(); ++r) {
    const std::string rn = regions.size() > 1 ? "region " + std::to_string(r) + " " : "";
    check_loop(regions[r].boundary, rn + "boundary");
    for (std::size_t k = 0; k < regions[r].islands.size(); ++k)
      check_loop(regions[r].islands[k], rn + "island " + std::to_string(k));
    e.any_boundary = e.any_boundary || !regions[r].boundary.empty();
    e.any_island = e.any_island || !regions[r].islands.empty();
  }
  for (std::size_t i = 0; i < tool_points.size(); ++i) {
    if (!tool_points[i].allFinite()) fail(path, "pocket plot: tool point " + std::to_string(i) + " is not finite");
    e.grow(tool_points[i].x(), tool_points[i].y());
  }
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
        e.fmin = std::min(e.fmin, f);
        e.fmax = std::max(e.fmax, f);
      }
    }
  }
  e.have_feeds = e.fmax >= e.fmin;
  if (opt.feed_range) {
    if (!std::isfinite(opt.feed_range->first) || !std::isfinite(opt.feed_range->second) ||
        !(opt.feed_range->second > opt.feed_range->first))
      fail(path, "pocket plot: feed_range must be finite with min < max");
    e.fmin = opt.feed_range->first;
    e.fmax = opt.feed_range->second;
  }
  return e;
}

/// The axes' ranges round the extent, at equal aspect inside at most kMaxW × kMaxH px; the plot's
/// size in px into plot_w, plot_h. Returns the scale, px per mm.
double fit_axes(const Extent& e, Axis& x, Axis& y, int& plot_w, int& plot_h) {
  double xmin = e.xmin, xmax = e.xmax, ymin = e.ymin, ymax = e.ymax;
  if (!(xmax >= xmin)) {  // nothing at all to draw: an empty frame, still a valid picture
    xmin = ymin = 0;
    xmax = ymax = 1;
  }
  // Margin of 4 % (at least 1 mm) so that the walls do not sit on the frame.
  const double span = std::max({xmax - xmin, ymax - ymin, 1e-9});
  const double pad = std::max(0.04 * span, 1.0);
  x.lo = xmin - pad;
  x.hi = xmax + pad;
  y.lo = ymin - pad;
  y.hi = ymax + pad;
  constexpr double kMaxW = 700, kMaxH = 680;
  const double scale = std::min(kMaxW / (x.hi - x.lo), kMaxH / (y.hi - y.lo));  // px per mm
  plot_w = std::max(1, cvRound((x.hi - x.lo) * scale));
  plot_h = std::max(1, cvRound((y.hi - y.lo) * scale));
  // Recompute the ranges from the rounded pixel box so that one mm is the same on both axes.
  x.hi = x.lo + plot_w / scale;
  y.hi = y.lo + plot_h / scale;
  return scale;
}

std::vector<LegendItem> legend_items(const Extent& e, const std::vector<Vec2>& tool_points,
                                     const pocket::Path2D& toolpath, const PocketPlotOptions& opt) {
  std::vector<LegendItem> items;
  if (e.any_boundary) items.push_back({"boundary", kBlack, LegendKind::Line});
  if (e.any_island) items.push_back({"island", kIslandGrey, LegendKind::Box});
  if (opt.show_tool_points && !tool_points.empty())
    items.push_back({"tool point (" + std::to_string(tool_points.size()) + ")", kToolPoint, LegendKind::Dot});
  if (!toolpath.chains.empty())
    items.push_back(
        {e.have_feeds ? "cut (colour = feed)" : "cut", e.have_feeds ? feed_colour(0.5) : kNoFeed, LegendKind::Line});
  if (toolpath.chains.size() > 1) items.push_back({"rapid (retract)", kRapid, LegendKind::Dashed});
  std::size_t n_drill = 0;
  for (const auto& ch : toolpath.chains) n_drill += (ch.predrill && !ch.pts.empty()) ? 1U : 0U;
  if (n_drill > 0) items.push_back({"pre-drill (" + std::to_string(n_drill) + ")", kBlack, LegendKind::CircledCross});
  return items;
}

constexpr int kMetricsLine = 20;  ///< line height of the metrics block, px

/// The metrics as "key: value" lines in up to 4 columns of a block lw px wide.
struct MetricsBlock {
  std::vector<std::string> text;
  int cols = 1, rows = 0, height = 0;
};

MetricsBlock metrics_block(const std::vector<std::pair<std::string, std::string>>& metrics, int lw) {
  MetricsBlock m;
  int mw = 0;
  for (const auto& [k, v] : metrics) {
    m.text.push_back(ascii(k) + ": " + ascii(v));
    mw = std::max(mw, text_size(m.text.back(), kTickFont).width);
  }
  m.cols = m.text.empty() ? 1 : std::clamp(lw / (mw + 30), 1, 4);
  m.rows = static_cast<int>((m.text.size() + static_cast<std::size_t>(m.cols) - 1) / static_cast<std::size_t>(m.cols));
  m.height = m.text.empty() ? 0 : m.rows * kMetricsLine + 14;
  return m;
}

/// Draws into the plot box, whose top-left corner is o in the picture: data points map through the
/// axes, then shift by −o.
struct PlotBox {
  cv::Mat plot;
  cv::Point2d o;
  const Axis& x;
  const Axis& y;
  double tol_mm;  ///< arcs are drawn as chords within this of the true arc
  [[nodiscard]] cv::Point2d px(const Vec2& p) const { return cv::Point2d(x.to_px(p.x()), y.to_px(p.y())); }
  [[nodiscard]] std::vector<cv::Point2d> to_px(const std::vector<Vec2>& pts) const {
    std::vector<cv::Point2d> out;
    out.reserve(pts.size());
    for (const auto& p : pts) out.push_back(px(p));
    return out;
  }
  [[nodiscard]] std::vector<cv::Point2d> shift(std::vector<cv::Point2d> v) const {
    for (auto& p : v) p -= o;
    return v;
  }
};

/// The region: tinted pocket floor, grey islands, outlines on top.
void draw_regions(PlotBox& b, const std::vector<pocket::Region>& regions) {
  std::vector<std::vector<cv::Point2d>> boundaries_px, islands_px;
  for (const auto& region : regions) {
    boundaries_px.push_back(b.to_px(flatten_loop(region.boundary, b.tol_mm)));
    for (const auto& isl : region.islands) islands_px.push_back(b.to_px(flatten_loop(isl, b.tol_mm)));
  }
  // One fillPoly per region: several disjoint pockets of a roughing level each get their floor.
  for (const auto& p : boundaries_px) fill_polygons(b.plot, {b.shift(p)}, kPocketTint);
  {
    std::vector<std::vector<cv::Point2d>> isl;
    for (const auto& i : islands_px) isl.push_back(b.shift(i));
    fill_polygons(b.plot, isl, kIslandGrey);
  }
  for (const auto& p : boundaries_px)
    if (p.size() >= 2) polyline(b.plot, b.shift(p), kBlack, 2);
  for (const auto& i : islands_px)
    if (i.size() >= 2) polyline(b.plot, b.shift(i), kBlack, 2);
}

/// The path: rapids first (under the cuts), then cuts per segment coloured by feed in [fmin, fmax],
/// then the pre-drill marks. O(path vertices + arc samples).
void draw_path(PlotBox& b, const pocket::Path2D& toolpath, double fmin, double fmax) {
  const auto& chains = toolpath.chains;
  for (std::size_t c = 0; c + 1 < chains.size(); ++c) {
    if (chains[c].pts.empty() || chains[c + 1].pts.empty()) continue;
    dashed_polyline(b.plot, {b.px(chains[c].pts.back().p()) - b.o, b.px(chains[c + 1].pts.front().p()) - b.o}, kRapid,
                    1, 7, 5);
  }
  for (const auto& ch : chains) {
    for (std::size_t k = 0; k + 1 < ch.pts.size(); ++k) {
      std::vector<Vec2> seg{ch.pts[k].p()};
      append_segment(seg, ch.pts[k].p(), ch.pts[k + 1].p(), ch.pts[k].bulge, b.tol_mm);
      cv::Scalar colour = kNoFeed;
      if (!ch.feed.empty() && ch.feed[k] > 0)
        colour = feed_colour(fmax > fmin ? (ch.feed[k] - fmin) / (fmax - fmin) : 0.5);
      polyline(b.plot, b.shift(b.to_px(seg)), colour, 2);
    }
    if (ch.pts.size() == 1) circle_at(b.plot, b.px(ch.pts[0].p()) - b.o, 2.5, kNoFeed, -1);
  }
  for (const auto& ch : chains) {
    if (!ch.predrill || ch.pts.empty()) continue;
    const cv::Point2d m = b.px(ch.pts.front().p()) - b.o;
    circle_at(b.plot, m, 7, kBlack, 2);
    line(b.plot, m + cv::Point2d(-5, -5), m + cv::Point2d(5, 5), kBlack, 2);
    line(b.plot, m + cv::Point2d(-5, 5), m + cv::Point2d(5, -5), kBlack, 2);
  }
}

/// The metrics block from y on, under a thin rule, column-major so that related rows stay together.
void draw_metrics(cv::Mat& img, const MetricsBlock& m, int lx, int lw, int y) {
  if (m.text.empty()) return;
  line(img, {static_cast<double>(lx), y + 0.5}, {static_cast<double>(lx + lw), y + 0.5}, kGridGrey, 1);
  const int colw = lw / m.cols;
  for (std::size_t i = 0; i < m.text.size(); ++i) {
    const int col = static_cast<int>(i) / m.rows, row = static_cast<int>(i) % m.rows;
    put_text(img, m.text[i], {lx + col * colw, y + 8 + row * kMetricsLine}, kTickFont, kBlack, HAlign::Left,
             VAlign::Top);
  }
}

}  // namespace

Layout pocket_path_png(const std::filesystem::path& path, const std::vector<pocket::Region>& regions,
                       const std::vector<Vec2>& tool_points, const pocket::Path2D& toolpath,
                       const std::string& title_text, const std::vector<std::pair<std::string, std::string>>& metrics,
                       const PocketPlotOptions& opt) {
  const Extent e = checked_extent(path, regions, tool_points, toolpath, opt);
  Axis x, y;
  int plot_w = 1, plot_h = 1;
  const double scale = fit_axes(e, x, y, plot_w, plot_h);
  const int right_panel = e.have_feeds ? 170 : 30;
  const int left = std::max(60 + widest_tick_label(y.lo, y.hi, 6), (kWidth - right_panel - plot_w) / 2 + 30);
  const int top = title_height(title_text) + 6;
  const int bottom = top + plot_h;
  const std::vector<LegendItem> items = legend_items(e, tool_points, toolpath, opt);
  const int lx = 40, lw = kWidth - 80;
  const int legend_h = legend(nullptr, items, lx, 0, lw);
  const MetricsBlock mblock = metrics_block(metrics, lw);

  cv::Mat img(bottom + 64 + legend_h + 8 + mblock.height + 10, kWidth, CV_8UC3, kWhite);
  title(img, title_text);
  x.p0 = left;
  x.p1 = left + plot_w;
  y.p0 = bottom;
  y.p1 = top;
  draw_axes(img, x, y, "x (mm)", "y (mm)");
  // Everything inside the frame is drawn into the plot box so that nothing spills over the axes.
  const cv::Rect box(left + 1, top + 1, plot_w - 1, plot_h - 1);
  PlotBox b{img(box), cv::Point2d(box.x, box.y), x, y, 0.2 / scale};  // chords within 0.2 px of the true arcs
  draw_regions(b, regions);
  if (opt.show_tool_points)
    for (const auto& p : tool_points) circle_at(b.plot, b.px(p) - b.o, 2.2, kToolPoint, -1);  // O(tool points)
  draw_path(b, toolpath, e.fmin, e.fmax);
  if (e.have_feeds) {
    const int ch = std::min(plot_h, 360);
    colour_bar(img, left + plot_w + 30, top, 24, top + ch, e.fmin, e.fmax, "feed (mm/min)", &feed_colour);
  }
  legend(&img, items, lx, bottom + 64, lw);
  draw_metrics(img, mblock, lx, lw, bottom + 64 + legend_h + 8);
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
