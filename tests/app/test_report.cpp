// Tests of millnet::report (PNG pictures): every picture decodes to the size its Layout states,
// the same data gives the same bytes, and pixels sit where the data says (orientation of heat
// maps, bar heights, islands and arcs of pockets, feed colours).
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/report/plots.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

namespace fs = std::filesystem;
using namespace millnet;
using namespace millnet::report;

namespace {

fs::path out_dir() {
  const fs::path d = fs::path(MILLNET_BINARY_DIR) / "test_report_out";
  fs::create_directories(d);
  return d;
}

cv::Mat decode(const fs::path& p) {
  cv::Mat img = cv::imread(p.string(), cv::IMREAD_COLOR);
  EXPECT_FALSE(img.empty()) << p;
  return img;
}

/// RGB of the pixel under data point (x, y).
std::array<int, 3> rgb_at(const cv::Mat& img, const Layout& l, double x, double y) {
  const auto p = l.to_pixel(x, y);
  const cv::Vec3b c = img.at<cv::Vec3b>(static_cast<int>(std::floor(p[1])), static_cast<int>(std::floor(p[0])));
  return {c[2], c[1], c[0]};
}

std::array<int, 3> viridis_int(double t) {
  const auto c = viridis_rgb(t);
  return {c[0], c[1], c[2]};
}

int max_channel_diff(const std::array<int, 3>& a, const std::array<int, 3>& b) {
  return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

void expect_size(const fs::path& p, const Layout& l) {
  ASSERT_GT(fs::file_size(p), 1000u) << p;
  const cv::Mat img = decode(p);
  EXPECT_EQ(img.cols, l.width);
  EXPECT_EQ(img.rows, l.height);
  EXPECT_GE(img.cols, 900);
  EXPECT_LE(img.cols, 1100);
  EXPECT_LT(l.plot_left, l.plot_right);
  EXPECT_LT(l.plot_top, l.plot_bottom);
  EXPECT_LE(l.plot_right, l.width);
  EXPECT_LE(l.plot_bottom, l.height);
}

std::string bytes(const fs::path& p) { return millnet::read_file(p); }

/// Square 0..100 mm with rounded (r = 10) top-right corner, and a circular island of radius 15
/// at (50, 50) made of two half-circle arcs (bulge 1): drawn as chords it would be a line.
pocket::Region test_region() {
  const double b90 = std::tan(std::numbers::pi / 8);  // 90° CCW arc
  pocket::Region r;
  r.boundary = {{0, 0, 0}, {100, 0, 0}, {100, 90, b90}, {90, 100, 0}, {0, 100, 0}};
  r.islands = {{{35, 50, -1}, {65, 50, -1}}};  // CW island
  return r;
}

}  // namespace

TEST(ReportHeatMap, OrientationRowZeroAtBottomColumnZeroAtLeft) {
  const int n = 15;
  Eigen::MatrixXd g(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) g(i, j) = i * n + j;  // every cell distinct, corners far apart
  const fs::path p = out_dir() / "heat.png";
  const Layout l = heat_map_png(p, g, "Height grid (15x15) of part α", "height (mm)");
  expect_size(p, l);
  const cv::Mat img = decode(p);
  const double vmax = n * n - 1;
  // Cell (row r, col c) is centred at data (c + 1, r + 1).
  EXPECT_EQ(rgb_at(img, l, 1, 1), viridis_int(g(0, 0) / vmax));          // bottom-left = min y, min x
  EXPECT_EQ(rgb_at(img, l, n, n), viridis_int(g(n - 1, n - 1) / vmax));  // top-right
  EXPECT_EQ(rgb_at(img, l, n, 1), viridis_int(g(0, n - 1) / vmax));      // bottom-right: row 0, last col
  EXPECT_EQ(rgb_at(img, l, 1, n), viridis_int(g(n - 1, 0) / vmax));      // top-left: last row, col 0
  EXPECT_EQ(rgb_at(img, l, 8, 4), viridis_int(g(3, 7) / vmax));
  // Pixel rows: the bottom-left cell is below the top-right one in the image.
  EXPECT_GT(l.to_pixel(1, 1)[1], l.to_pixel(n, n)[1]);
  // Determinism: same data, same bytes.
  const fs::path p2 = out_dir() / "heat2.png";
  heat_map_png(p2, g, "Height grid (15x15) of part α", "height (mm)");
  EXPECT_EQ(bytes(p), bytes(p2));
}

TEST(ReportHeatMap, ExtentInMillimetresAndAnnotations) {
  Eigen::MatrixXd g(3, 4);
  g << 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11;
  HeatMapOptions o;
  o.extent_mm = std::array<double, 4>{0, 80, 0, 60};  // 20 mm cells, non-square grid
  const fs::path p = out_dir() / "heat_extent.png";
  const Layout l = heat_map_png(p, g, "extent", "mm", o);
  expect_size(p, l);
  const cv::Mat img = decode(p);
  EXPECT_EQ(rgb_at(img, l, 70, 50), viridis_int(11.0 / 11.0));  // x 60..80 = col 3, y 40..60 = row 2
  EXPECT_EQ(rgb_at(img, l, 30, 10), viridis_int(1.0 / 11.0));   // col 1, row 0
  // Equal mm on both axes when cells are square in mm.
  EXPECT_NEAR((l.plot_right - l.plot_left) / 80.0, (l.plot_bottom - l.plot_top) / 60.0, 0.02);
  o.annotate = true;
  const fs::path pa = out_dir() / "heat_annotated.png";
  heat_map_png(pa, g, "extent", "mm", o);
  EXPECT_NE(bytes(p), bytes(pa));  // the numbers are drawn
}

TEST(ReportHeatMap, AFewExtremeCellsAreLeftOutOfTheScaleAndSaidSo) {
  // 0 … 99 and one cell at 10,000 (an uncut corner's Ra): the 99th percentile (nearest rank: the
  // 100th of 101 values, 99) ends the scale; 1 of 101 cells lies above it; the low end stays 0 (the
  // 1st percentile, 1, is not half the range away from it).
  Eigen::MatrixXd g(1, 101);
  for (int j = 0; j < 100; ++j) g(0, j) = j;
  g(0, 100) = 10000;
  const ColourRange r = robust_range(g);
  EXPECT_EQ(r.lo, 0);
  EXPECT_EQ(r.hi, 99);
  EXPECT_DOUBLE_EQ(r.above_share, 1.0 / 101);
  EXPECT_EQ(r.below_share, 0);
  // Both ends: −10,000 added (102 values): the 2nd smallest, 0, and the 101st, 99.
  Eigen::MatrixXd h(1, 102);
  h(0, 0) = -10000;
  for (int j = 0; j < 101; ++j) h(0, j + 1) = g(0, j);
  const ColourRange b = robust_range(h);
  EXPECT_EQ(b.lo, 0);
  EXPECT_EQ(b.hi, 99);
  EXPECT_DOUBLE_EQ(b.below_share, 1.0 / 102);
  EXPECT_DOUBLE_EQ(b.above_share, 1.0 / 102);
  // Nothing extreme: the whole range, nothing left out.
  const ColourRange w = robust_range(g.leftCols(100));
  EXPECT_EQ(w.lo, 0);
  EXPECT_EQ(w.hi, 99);
  EXPECT_EQ(w.above_share + w.below_share, 0);
  // Drawn: the cells keep their colours on the 0…99 scale, the extreme one the top colour, and the
  // note under the colour bar changes the picture.
  Eigen::MatrixXd sq(10, 10);
  for (int i = 0; i < 100; ++i) sq(i / 10, i % 10) = i;
  sq(9, 9) = 10000;
  const ColourRange rs = robust_range(sq);
  HeatMapOptions o;
  o.value_range = std::pair{rs.lo, rs.hi};
  const fs::path plain = out_dir() / "heat_clipped_plain.png", noted = out_dir() / "heat_clipped.png";
  heat_map_png(plain, sq, "clipped", "Ra (um)", o);
  o.above_share = rs.above_share;
  const Layout l = heat_map_png(noted, sq, "clipped", "Ra (um)", o);
  const cv::Mat img = decode(noted);
  EXPECT_EQ(rgb_at(img, l, 6, 5), viridis_int(45.0 / rs.hi));  // row 4, col 5: 45
  EXPECT_EQ(rgb_at(img, l, 10, 10), viridis_int(1.0));
  EXPECT_NE(bytes(plain), bytes(noted));
}

TEST(ReportHeatMap, RejectsEmptyAndNonFiniteGrids) {
  const fs::path p = out_dir() / "bad_heat.png";
  EXPECT_THROW(heat_map_png(p, Eigen::MatrixXd(0, 0), "t", "mm"), millnet::Error);
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(2, 2);
  g(1, 1) = std::nan("");
  try {
    heat_map_png(p, g, "t", "mm");
    FAIL() << "expected millnet::Error";
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(p));
}

TEST(ReportLinePlot, LogAlphaCurveWithMarker) {
  Series s{"leave-one-out RMS", {}, {}};
  for (int k = 0; k <= 20; ++k) {
    const double a = std::pow(10.0, -2.7 + 0.15 * k);  // 0.002 … 2
    s.xs.push_back(a);
    s.ys.push_back(0.2 + std::pow(std::log10(a) + 1, 2) * 0.05);
  }
  LinePlotOptions o;
  o.log_x = true;
  o.marker = Marker{0.1, "chosen α = 0.1"};
  const fs::path p = out_dir() / "loo.png";
  const Layout l = line_plot_png(p, {s}, "Leave-one-out error against α", "α (penalty)", "RMS error", o);
  expect_size(p, l);
  // Decades around the data.
  EXPECT_DOUBLE_EQ(l.x_min, 1e-3);
  EXPECT_DOUBLE_EQ(l.x_max, 10.0);
  EXPECT_TRUE(l.log_x);
  EXPECT_LE(l.y_min, 0.2);
  EXPECT_GE(l.y_max, 0.2 + std::pow(-1.7, 2) * 0.05);
  const cv::Mat img = decode(p);
  // A point half-way along segment 3→4 (straight in log x) lies on the curve: the series colour
  // (Okabe-Ito blue 0,114,178) within anti-aliasing.
  const double xm = std::sqrt(s.xs[3] * s.xs[4]), ym = 0.5 * (s.ys[3] + s.ys[4]);
  EXPECT_LE(max_channel_diff(rgb_at(img, l, xm, ym), {0, 114, 178}), 60);
  // Far from the curve the plot is white or a grid line.
  const auto bg = rgb_at(img, l, 0.0015, 0.2 + (l.y_max - 0.2) * 0.9);
  EXPECT_GE(std::min({bg[0], bg[1], bg[2]}), 220);
  const fs::path p2 = out_dir() / "loo2.png";
  line_plot_png(p2, {s}, "Leave-one-out error against α", "α (penalty)", "RMS error", o);
  EXPECT_EQ(bytes(p), bytes(p2));
}

TEST(ReportLinePlot, RejectsMismatchedSeriesAndNonPositiveLogX) {
  const fs::path p = out_dir() / "bad_line.png";
  EXPECT_THROW(line_plot_png(p, {Series{"a", {1, 2}, {1}}}, "t", "x", "y"), millnet::Error);
  LinePlotOptions o;
  o.log_x = true;
  try {
    line_plot_png(p, {Series{"a", {0, 1}, {1, 2}}}, "t", "x", "y", o);
    FAIL() << "expected millnet::Error";
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad_line.png"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("log"), std::string::npos) << e.what();
  }
  EXPECT_THROW(line_plot_png(p, {}, "t", "x", "y"), millnet::Error);
}

TEST(ReportLinePlot, MultiLineProbabilitiesPerVector) {
  NamedValues filt{"filtration", {}}, verif{"verification", {}};
  for (int i = 0; i < 120; ++i) {
    filt.values.push_back(0.6 + 0.4 * std::sin(i * 0.3) * std::sin(i * 0.3));
    verif.values.push_back(0.3 + 0.5 * std::cos(i * 0.2) * std::cos(i * 0.2));
  }
  const fs::path p = out_dir() / "strip.png";
  const Layout l = multi_line_png(p, {filt, verif}, "Output of the true class per stored vector", "stored vector",
                                  "probability of the true class");
  expect_size(p, l);
  EXPECT_DOUBLE_EQ(l.x_min, 0.5);
  EXPECT_DOUBLE_EQ(l.x_max, 120.5);
  EXPECT_LE(l.y_min, 0.0);
  EXPECT_GE(l.y_max, 1.0);
  const cv::Mat img = decode(p);
  // Vector 1 of filtration at 0.6: a dot in series colour 0 (blue).
  EXPECT_LE(max_channel_diff(rgb_at(img, l, 1, filt.values[0]), {0, 114, 178}), 60);
}

TEST(ReportBars, BarHeightsFollowTheValues) {
  const std::vector<std::string> cats = {"1 profile + Z finishing", "2 3D/profile", "3 scallop", "4 Z-level",
                                         "5 equidistant",           "spare 6",      "spare 7",   "spare 8"};
  NamedValues a{"part A", {0.05, 0.6, 0.1, 0.05, 0.2, 0, 0, 0}}, b{"part B", {0.3, 0.1, 0.4, 0.1, 0.1, 0, 0, 0}};
  BarOptions o;
  o.y_range = std::pair{0.0, 1.0};
  const fs::path p = out_dir() / "bars.png";
  const Layout l = grouped_bar_png(p, cats, {a, b}, "Predicted strategy probabilities", "probability", o);
  expect_size(p, l);
  const cv::Mat img = decode(p);
  // Bar s of category k is centred at x = k + 0.11 + 0.78·(s + 0.5)/S in the layout's x units.
  auto xc = [](int k, int s) { return k + 0.11 + 0.78 * (s + 0.5) / 2.0; };
  const std::array<int, 3> blue{0, 114, 178}, vermillion{213, 94, 0};
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(rgb_at(img, l, xc(k, 0), a.values[static_cast<std::size_t>(k)] * 0.5), blue) << k;
    EXPECT_EQ(rgb_at(img, l, xc(k, 1), b.values[static_cast<std::size_t>(k)] * 0.5), vermillion) << k;
  }
  // Above the 0.6 bar (by 0.1 = 44 px) there is no bar colour; just below its top there is.
  EXPECT_NE(rgb_at(img, l, xc(1, 0), 0.7), blue);
  EXPECT_EQ(rgb_at(img, l, xc(1, 0), 0.58), blue);
  EXPECT_NE(rgb_at(img, l, xc(1, 0), 0.63), blue);
  const fs::path p2 = out_dir() / "bars2.png";
  grouped_bar_png(p2, cats, {a, b}, "Predicted strategy probabilities", "probability", o);
  EXPECT_EQ(bytes(p), bytes(p2));
}

TEST(ReportBars, LongCategoryNamesAndErrors) {
  const std::vector<std::string> cats = {
      "profile finishing + Z finishing, slope mode", "3D/profile finishing",
      "profile finishing, scallop-height mode with a very long explanatory name that cannot wrap in four lines",
      "Z-level finishing", "profile finishing, equidistant, constant in-feed"};
  const fs::path p = out_dir() / "bars_long.png";
  const Layout l = grouped_bar_png(p, cats, {NamedValues{"", {10, 20, 5, 40, 25}}}, "Votes per strategy", "votes");
  expect_size(p, l);
  EXPECT_LE(l.y_min, 0);
  EXPECT_GE(l.y_max, 40);
  EXPECT_THROW(grouped_bar_png(p, cats, {NamedValues{"x", {1, 2}}}, "t", "y"), millnet::Error);
  EXPECT_THROW(grouped_bar_png(p, {}, {NamedValues{"x", {}}}, "t", "y"), millnet::Error);
}

TEST(ReportPocket, IslandsGreyOutsideWhiteArcsAsArcsFeedColours) {
  const pocket::Region region = test_region();
  std::vector<pocket::Vec2> tps;
  for (double x = 10; x <= 90; x += 10)
    for (double y = 10; y <= 90; y += 10)
      if (std::hypot(x - 50, y - 50) > 22) tps.emplace_back(x, y);
  pocket::Path2D path;
  pocket::Chain slow, fast, ring;
  slow.pts = {{10, 10, 0}, {90, 10, 0}, {90, 20, 0}};
  slow.feed = {50, 80};
  fast.pts = {{10, 90, 0}, {60, 90, 0}};
  fast.feed = {200};
  fast.predrill = false;
  // A full circle around the island (two half arcs) at r = 25, CCW.
  ring.pts = {{75, 50, 1}, {25, 50, 1}, {75, 50, 0}};
  ring.feed = {100, 100};
  path.chains = {slow, ring, fast};
  const fs::path p = out_dir() / "pocket.png";
  const Layout l = pocket_path_png(p, region, tps, path, "SOM tool path - test pocket",
                                   {{"tool points", std::to_string(tps.size())},
                                    {"retractions", "2"},
                                    {"cut length", "512.3 mm"},
                                    {"time (adjusted feed)", "4.2 min"}});
  expect_size(p, l);
  const cv::Mat img = decode(p);
  const std::array<int, 3> grey{190, 190, 190}, white{255, 255, 255};
  EXPECT_EQ(rgb_at(img, l, 50, 50), grey);   // island interior
  EXPECT_EQ(rgb_at(img, l, -2, 50), white);  // outside the boundary (inside the plot margin)
  EXPECT_EQ(rgb_at(img, l, 47, 103), white);
  // The rounded corner is an arc: (99, 99) is outside it (the corner's centre is (90, 90), r 10).
  EXPECT_EQ(rgb_at(img, l, 99, 99), white);
  // Arcs of the island are arcs, not chords: at 45° inside r = 15 grey, outside it not.
  const double c45 = std::cos(std::numbers::pi / 4);
  EXPECT_EQ(rgb_at(img, l, 50 + 12 * c45, 50 + 12 * c45), grey);
  EXPECT_NE(rgb_at(img, l, 50 + 19 * c45, 50 + 19 * c45), grey);
  // The pocket floor is tinted, not white and not grey.
  const auto floor = rgb_at(img, l, 30, 70);
  EXPECT_NE(floor, white);
  EXPECT_NE(floor, grey);
  // Feed colours: slowest cut (50) = viridis(0), fastest (200) = viridis(0.85).
  EXPECT_LE(max_channel_diff(rgb_at(img, l, 40, 10), viridis_int(0.0)), 45);
  EXPECT_LE(max_channel_diff(rgb_at(img, l, 35, 90), viridis_int(0.85)), 45);
  // The ring (an arc path) passes through (50, 75) with feed 100 = viridis(0.85·1/3).
  EXPECT_LE(max_channel_diff(rgb_at(img, l, 50, 75), viridis_int(0.85 / 3)), 45);
  // Equal aspect: one mm is as many pixels across as up.
  EXPECT_NEAR((l.plot_right - l.plot_left) / (l.x_max - l.x_min), (l.plot_bottom - l.plot_top) / (l.y_max - l.y_min),
              1e-9);
  const fs::path p2 = out_dir() / "pocket2.png";
  pocket_path_png(p2, region, tps, path, "SOM tool path - test pocket",
                  {{"tool points", std::to_string(tps.size())},
                   {"retractions", "2"},
                   {"cut length", "512.3 mm"},
                   {"time (adjusted feed)", "4.2 min"}});
  EXPECT_EQ(bytes(p), bytes(p2));
}

TEST(ReportPocket, LevelPictureAndBadFeeds) {
  pocket::Path2D path;
  pocket::Chain c;
  c.pts = {{10, 10, 0}, {90, 10, 0}, {90, 30, 0}, {10, 30, 0}};  // no feeds yet: one colour, no bar
  path.chains = {c};
  const fs::path p = out_dir() / "level.png";
  const Layout l = level_png(p, test_region(), path, -5.0, "part A roughing", {{"level", "1 of 4"}});
  expect_size(p, l);
  const cv::Mat img = decode(p);
  EXPECT_EQ(rgb_at(img, l, 50, 50), (std::array<int, 3>{190, 190, 190}));
  // A tall, narrow pocket keeps equal aspect too.
  pocket::Region tall;
  tall.boundary = {{0, 0, 0}, {20, 0, 0}, {20, 200, 0}, {0, 200, 0}};
  const fs::path pt = out_dir() / "tall.png";
  const Layout lt = pocket_path_png(pt, tall, {}, {}, "tall");
  expect_size(pt, lt);
  EXPECT_NEAR((lt.plot_right - lt.plot_left) / (lt.x_max - lt.x_min),
              (lt.plot_bottom - lt.plot_top) / (lt.y_max - lt.y_min), 1e-9);
  c.feed = {100};  // 3 segments, 1 feed
  path.chains = {c};
  EXPECT_THROW(pocket_path_png(out_dir() / "bad.png", test_region(), {}, path, "t"), millnet::Error);
}

TEST(ReportPocket, SeveralRegionsOnOneLevel) {
  // Two disjoint pockets (0..40 and 60..100 in x), the second with a square island.
  pocket::Region a, b;
  a.boundary = {{0, 0, 0}, {40, 0, 0}, {40, 50, 0}, {0, 50, 0}};
  b.boundary = {{60, 0, 0}, {100, 0, 0}, {100, 50, 0}, {60, 50, 0}};
  b.islands = {{{75, 20, 0}, {75, 30, 0}, {85, 30, 0}, {85, 20, 0}}};
  const fs::path p = out_dir() / "level_two_regions.png";
  const Layout l = level_png(p, std::vector<pocket::Region>{a, b}, {}, -12.5, "two pockets");
  expect_size(p, l);
  const cv::Mat img = decode(p);
  const std::array<int, 3> grey{190, 190, 190}, white{255, 255, 255};
  EXPECT_EQ(rgb_at(img, l, 49, 23), white);  // between the pockets: stock, not floor
  EXPECT_EQ(rgb_at(img, l, 81, 24), grey);   // island of the second region
  const auto fa = rgb_at(img, l, 17, 23), fb = rgb_at(img, l, 67, 43);
  EXPECT_EQ(fa, fb);  // both floors tinted alike
  EXPECT_NE(fa, white);
  EXPECT_NE(fa, grey);
}

TEST(ReportProfile, StackedPanelsOfEngagementFeedAndMrr) {
  // The seed's eq. 9 example: D = 40, grid 4 ⇒ n1 = 10, n2 = 5, f1 = 50, f2 = 100.
  std::vector<double> s, n3, feed, mrr, mrr_const;
  for (int i = 0; i < 30; ++i) {
    s.push_back(i * 20.0);
    const double n = 4 + (i * 3) % 7;  // 4 … 10
    n3.push_back(n);
    const double f = std::clamp(100 + (100.0 - 50.0) / (5 - 10) * (n - 5), 20.0, 200.0);
    feed.push_back(f);
    mrr.push_back(n * 4 * f * 1.0 / 1000.0);
    mrr_const.push_back(n * 4 * 50.0 * 1.0 / 1000.0);
  }
  const fs::path p = out_dir() / "profile.png";
  const Layout l = profile_png(
      p, s,
      {Panel{"engagement n3 (cells)", {NamedValues{"", n3}}}, Panel{"feed (mm/min)", {NamedValues{"", feed}}},
       Panel{"MRR (cm³/min)", {NamedValues{"adjusted feed", mrr}, NamedValues{"slot feed f1", mrr_const}}}},
      "Engagement, feed and MRR along the path", ProfileOptions{true, "s (mm)"});
  expect_size(p, l);
  EXPECT_LE(l.x_min, 0);
  EXPECT_GE(l.x_max, 580);
  const fs::path p2 = out_dir() / "profile2.png";
  profile_png(p2, s,
              {Panel{"engagement n3 (cells)", {NamedValues{"", n3}}}, Panel{"feed (mm/min)", {NamedValues{"", feed}}},
               Panel{"MRR (cm³/min)", {NamedValues{"adjusted feed", mrr}, NamedValues{"slot feed f1", mrr_const}}}},
              "Engagement, feed and MRR along the path", ProfileOptions{true, "s (mm)"});
  EXPECT_EQ(bytes(p), bytes(p2));
  std::vector<double> back = s;
  std::swap(back[3], back[4]);
  EXPECT_THROW(profile_png(p, back, {Panel{"y", {NamedValues{"", n3}}}}, "t"), millnet::Error);
  EXPECT_THROW(profile_png(p, s, {Panel{"y", {NamedValues{"", {1, 2}}}}}, "t"), millnet::Error);
}

TEST(ReportFiles, UnwritableFolderIsAnErrorNamingThePath) {
  const fs::path blocker = out_dir() / "not_a_folder";
  {
    std::ofstream f(blocker);
    f << "x";
  }
  const fs::path p = blocker / "sub" / "heat.png";
  try {
    heat_map_png(p, Eigen::MatrixXd::Ones(2, 2), "t", "mm");
    FAIL() << "expected millnet::Error";
  } catch (const millnet::Error& e) {
    EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
  }
}
