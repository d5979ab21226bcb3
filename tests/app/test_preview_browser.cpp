// The preview pages in a real browser (issue 16 §2): headless Chromium opens each kind of page from
// file:// (pocket, rough, finish with simulation, run summary); the test fails on any console error
// or uncaught exception (the page writes them into the DOM, which --dump-dom shows), when the page
// never rendered, on a blank canvas (pixel variance of the screenshot) and when the path colour is
// absent from the 3D view. Skipped only when /usr/bin/chromium is not installed (CI installs it).
#include "app/cli_runner.hpp"
#include "ingest/builders.hpp"

#include "millnet/ingest/io/mesh_io.hpp"
#include "millnet/report/preview.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace millnet::testing {
namespace {
namespace fs = std::filesystem;

constexpr const char* kChromium = "/usr/bin/chromium";

struct Browsed {
  std::string dom;
  cv::Mat shot;  ///< BGR
};

/// Opens `page` twice (DOM, then a 1100 × 700 screenshot) with WebGL on SwiftShader.
Browsed browse(const fs::path& page, const fs::path& work) {
  const std::string common = std::string("DBUS_SESSION_BUS_ADDRESS=disabled: timeout -k 5 120 ") + kChromium +
                             " --headless=new --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader"
                             " --disable-gpu-sandbox --no-first-run --user-data-dir='" +
                             (work / "chrome-profile").string() +
                             "' --window-size=1100,700 --virtual-time-budget=8000 ";
  Browsed b;
  const fs::path dom = work / "dom.html", png = work / "shot.png";
  fs::remove(png);
  EXPECT_EQ(
      std::system((common + "--dump-dom 'file://" + page.string() + "' >'" + dom.string() + "' 2>/dev/null").c_str()),
      0);
  EXPECT_EQ(
      std::system(
          (common + "--screenshot='" + png.string() + "' 'file://" + page.string() + "' >/dev/null 2>&1").c_str()),
      0);
  b.dom = slurp(dom);
  b.shot = cv::imread(png.string(), cv::IMREAD_COLOR);
  return b;
}

/// Pixels of the 3D view (right of the side panel) within `tol` per channel of any of `colours`.
int pixels_near(const cv::Mat& bgr, const std::vector<std::uint32_t>& colours, int tol, int x0) {
  int n = 0;
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = x0; x < bgr.cols; ++x) {
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      for (const std::uint32_t c : colours) {
        const int r = static_cast<int>(c >> 16 & 255), g = static_cast<int>(c >> 8 & 255),
                  bl = static_cast<int>(c & 255);
        if (std::abs(p[2] - r) <= tol && std::abs(p[1] - g) <= tol && std::abs(p[0] - bl) <= tol) {
          ++n;
          break;
        }
      }
    }
  return n;
}

/// The checks every page passes: no page error, rendered, a 3D view that is not blank and shows
/// the path colours.
void expect_good_page(const fs::path& page, const fs::path& work, const std::vector<std::uint32_t>& path_colours) {
  ASSERT_TRUE(fs::exists(page)) << page;
  const Browsed b = browse(page, work);
  EXPECT_EQ(b.dom.find("MILLNET_PAGE_ERROR"), std::string::npos) << b.dom.substr(
      b.dom.find("MILLNET_PAGE_ERROR") == std::string::npos ? 0 : b.dom.find("MILLNET_PAGE_ERROR"), 400);
  EXPECT_NE(b.dom.find("data-rendered=\"1\""), std::string::npos) << page << ": the page never rendered a frame";
  ASSERT_FALSE(b.shot.empty()) << "no screenshot of " << page;
  const int x0 = report::kPanelWidthPx + 2;
  const cv::Mat view = b.shot(cv::Rect(x0, 0, b.shot.cols - x0, b.shot.rows));
  cv::Scalar mean, sd;
  cv::meanStdDev(view, mean, sd);
  EXPECT_GT(sd[0] + sd[1] + sd[2], 6.0) << page << ": blank 3D view";
  if (!path_colours.empty()) {
    EXPECT_GE(pixels_near(b.shot, path_colours, 24, x0), 30) << page << ": no path colour in the view";
  }
}

std::vector<std::uint32_t> feed_colours() { return {report::kFeedRamp.begin(), report::kFeedRamp.end()}; }

bool have_chromium() { return fs::exists(kChromium); }

fs::path write_part_stl(const fs::path& dir) {
  const auto m = testing_ingest::solid(
      [](double x, double y) {
        const double r2 = (x - 10) * (x - 10) / 49 + (y - 8) * (y - 8) / 25;
        return 1 + 5 * std::max(0.0, 1 - r2);
      },
      0, 20, 0, 16, 40, 32);
  const fs::path p = dir / "dome.stl";
  millnet::ingest::save_stl_binary(m, p);
  return p;
}

TEST(PreviewBrowser, PocketPageRendersItsPathsWithoutErrors) {
  if (!have_chromium()) GTEST_SKIP() << kChromium << " is not installed (scripts/setup.sh installs chromium)";
  const fs::path d = fresh_dir("preview_pocket");
  std::ofstream(d / "p.json")
      << R"({"units":"mm","boundary":[[0,0,0],[40,0,0],[40,30,0],[0,30,0]],"islands":[[[15,10,0],[15,20,0],[25,20,0],[25,10,0]]]})";
  const auto r = run_millnet(
      "pocket --pocket p.json --planner zigzag --tool-diameter 6 --stepover 3 --depth 2 --quiet --out o", d);
  ASSERT_EQ(r.code, 0) << r.err;
  expect_good_page(d / "o" / "p.html", d, feed_colours());
  const auto off = run_millnet(
      "pocket --pocket p.json --planner zigzag --tool-diameter 6 --stepover 3 --depth 2 --quiet --no-preview --out o2",
      d);
  ASSERT_EQ(off.code, 0) << off.err;
  EXPECT_TRUE(fs::exists(d / "o2" / "p.nc"));
  EXPECT_FALSE(fs::exists(d / "o2" / "p.html"));
}

TEST(PreviewBrowser, RoughPageRendersPartStockAndPaths) {
  if (!have_chromium()) GTEST_SKIP() << kChromium << " is not installed (scripts/setup.sh installs chromium)";
  const fs::path d = fresh_dir("preview_rough");
  const fs::path stl = write_part_stl(d);
  const auto r = run_millnet("rough --mesh '" + stl.string() +
                                 "' --planner zigzag --tool-diameter 4 --stepover 2 --step-down 2 --quiet --out o",
                             d);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string html = slurp(d / "o" / "dome.html");
  EXPECT_NE(html.find("\"part\":{\"V\":"), std::string::npos);
  EXPECT_NE(html.find("\"stock\":["), std::string::npos);
  expect_good_page(d / "o" / "dome.html", d, feed_colours());
}

TEST(PreviewBrowser, FinishPageWithSimulationShowsTheSurfaceAndPaths) {
  if (!have_chromium()) GTEST_SKIP() << kChromium << " is not installed (scripts/setup.sh installs chromium)";
  const fs::path d = fresh_dir("preview_finish");
  const fs::path stl = write_part_stl(d);
  std::ofstream(d / "fast.json") << R"({"simulate": {"cell_mm": 0.1}})";
  const auto r = run_millnet("finish --quiet --config fast.json --mesh '" + stl.string() +
                                 "' --strategy 1 --simulate --stepover 1 --step-down 1 --out o",
                             d);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string html = slurp(d / "o" / "dome.s1.html");
  EXPECT_NE(html.find("\"surface\":{"), std::string::npos);
  expect_good_page(d / "o" / "dome.s1.html", d, feed_colours());
}

TEST(PreviewBrowser, APackedPageInflatesItsDataAndRenders) {
  if (!have_chromium()) GTEST_SKIP() << kChromium << " is not installed (scripts/setup.sh installs chromium)";
  const fs::path d = fresh_dir("preview_packed");
  std::ofstream g(d / "long.nc");
  g << "G21 G90 G17\nG0 Z5\nG0 X0 Y0\nG1 Z-1 F200\n";
  for (int i = 0; i < 30000; ++i) g << "G1 X" << (i % 2 ? 60 : 0) << " Y" << i * 0.002 << " F" << 500 + i % 7 << "\n";
  g << "G0 Z5\nM30\n";
  g.close();
  const auto r = run_millnet("view long.nc --quiet --out o", d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(slurp(d / "o" / "long.html").find("id=\"millnet-data-gz\""), std::string::npos);  // data over 1 MB
  expect_good_page(d / "o" / "long.html", d, feed_colours());
}

TEST(PreviewBrowser, SetupSheetDrawsThePartStockAndOrigin) {
  if (!have_chromium()) GTEST_SKIP() << kChromium << " is not installed (scripts/setup.sh installs chromium)";
  const fs::path d = fresh_dir("preview_setup");
  const fs::path stl = write_part_stl(d);
  std::ofstream(d / "fast.json") << R"({"simulate": {"cell_mm": 0.1}})";
  const auto r =
      run_millnet("job --quiet --no-preview --config fast.json --mesh '" + stl.string() + "' --strategy 2 --out o", d);
  ASSERT_EQ(r.code, 0) << r.err;
  const Browsed b = browse(d / "o" / "dome.setup.html", d);
  EXPECT_EQ(b.dom.find("MILLNET_PAGE_ERROR"), std::string::npos) << b.dom;
  EXPECT_NE(b.dom.find("data-rendered=\"1\""), std::string::npos);
  ASSERT_FALSE(b.shot.empty());
  // The part picture's ramp ends (viridis: the dome's base and top), the front view's silhouette,
  // and the origin's X arrow.
  EXPECT_GE(pixels_near(b.shot, {0x440154, 0x482878}, 12, 0), 100);
  EXPECT_GE(pixels_near(b.shot, {0xfde725, 0xb5de2b}, 12, 0), 30);
  EXPECT_GE(pixels_near(b.shot, {0x3b528b}, 12, 0), 100);
  EXPECT_GE(pixels_near(b.shot, {0xcc0000}, 30, 0), 10);
}

TEST(PreviewBrowser, SummaryPageDrawsItsCharts) {
  if (!have_chromium()) GTEST_SKIP() << kChromium << " is not installed (scripts/setup.sh installs chromium)";
  const fs::path d = fresh_dir("preview_summary");
  report::SummaryPage s;
  s.title = "run summary";
  s.header = {"part", "strategy", "preview"};
  s.rows = {{"a", "1", "link:a|parts/a/a.html"}, {"b", "3", "link:b|parts/b/b.html"}};
  s.charts.push_back({"time per part", "min", {"a", "b"}, {{"rough", {3, 5}}, {"finish", {7, 2}}}});
  report::write_summary_html(d / "summary.html", s);
  // The whole window is the page here: the bars' colours must be in it.
  const Browsed b = browse(d / "summary.html", d);
  EXPECT_EQ(b.dom.find("MILLNET_PAGE_ERROR"), std::string::npos) << b.dom;
  EXPECT_NE(b.dom.find("data-rendered=\"1\""), std::string::npos);
  ASSERT_FALSE(b.shot.empty());
  EXPECT_GE(pixels_near(b.shot, {report::kProgramColours[0]}, 10, 0), 200);
  EXPECT_GE(pixels_near(b.shot, {report::kProgramColours[1]}, 10, 0), 200);
}

}  // namespace
}  // namespace millnet::testing
