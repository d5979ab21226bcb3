// The preview page writer (app/report/preview.hpp): decimation keeps the first and last point and
// stays under its budget, the embedded data round-trips the program's moves, entries are marked by
// kind, arcs are tessellated on their circle, a big job stays under 50 MB and says what it dropped,
// and a missing Debian script is one clear error.
#include "millnet/core/error.hpp"
#include "millnet/gcode/reader.hpp"
#include "millnet/report/page_data.hpp"
#include "millnet/report/preview.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace millnet::report {
namespace {

using nlohmann::json;

TEST(PreviewDecimate, KeepsAllUnderTheBudgetAndFirstLastEvenlyOver) {
  EXPECT_TRUE(decimate_indices(0, 10).empty());
  const auto all = decimate_indices(7, 7);
  ASSERT_EQ(all.size(), 7u);
  for (std::size_t i = 0; i < 7; ++i) EXPECT_EQ(all[i], i);
  for (const auto& [n, budget] :
       std::vector<std::pair<std::size_t, std::size_t>>{{8, 7}, {1000, 2}, {1000001, 1000}, {5, 3}, {10, 1}}) {
    const auto k = decimate_indices(n, budget);
    const std::size_t b = std::max<std::size_t>(budget, 2);
    ASSERT_EQ(k.size(), b) << n << " " << budget;
    EXPECT_EQ(k.front(), 0u);
    EXPECT_EQ(k.back(), n - 1);
    for (std::size_t i = 1; i < k.size(); ++i) EXPECT_LT(k[i - 1], k[i]);
    // evenly spaced: no gap more than one stride + 1
    const std::size_t stride = (n - 1) / (b - 1);
    for (std::size_t i = 1; i < k.size(); ++i) EXPECT_LE(k[i] - k[i - 1], stride + 1);
  }
}

constexpr const char* kProgram =
    "G21 G90 G17\n"               // 1
    "G0 Z5\n"                     // 2
    "G0 X10 Y0\n"                 // 3
    "G1 Z-1 F100\n"               // 4  plunge
    "G1 X20 Y0 F600\n"            // 5  cut
    "G1 X30 Y0 Z-2 F300\n"        // 6  down while cutting: a cut, not an entry ramp
    "G3 X30 Y0 Z-3 I0 J5 F400\n"  // 7  helix: a full circle round (30, 5), 1 mm down
    "G2 X40 Y10 I10 J0 F800\n"    // 8  arc cut, quarter circle round (40, 0)
    "G0 Z5\n"                     // 9
    "M30\n";

TEST(PreviewPath, RoundTripsTheMovesWithTheirKindFeedAndLine) {
  const PreviewProgram p = read_preview_program("t", kProgram, "t.nc");
  const PreviewPath path = preview_path(p, 1000000, 6);
  EXPECT_EQ(path.moves, 8u);
  EXPECT_EQ(path.points_before, path.kind.size());
  // Every move's end point is on the path at its line, in order, with its kind and feed.
  struct End {
    std::uint32_t line;
    double x, y, z;
    StepKind kind;
    double feed;
  };
  const std::vector<End> ends = {{3, 10, 0, 5, StepKind::Rapid, 0},    {4, 10, 0, -1, StepKind::Plunge, 100},
                                 {5, 20, 0, -1, StepKind::Cut, 600},   {6, 30, 0, -2, StepKind::Cut, 300},
                                 {7, 30, 0, -3, StepKind::Helix, 400}, {8, 40, 10, -3, StepKind::Cut, 800},
                                 {9, 40, 10, 5, StepKind::Rapid, 0}};
  std::size_t at = 0;
  for (const End& e : ends) {
    std::size_t last = path.line.size();
    for (std::size_t i = at; i < path.line.size(); ++i)
      if (path.line[i] == e.line) last = i;
    ASSERT_LT(last, path.line.size()) << "line " << e.line;
    EXPECT_NEAR(path.xyz[3 * last], e.x, 1e-4) << e.line;
    EXPECT_NEAR(path.xyz[3 * last + 1], e.y, 1e-4) << e.line;
    EXPECT_NEAR(path.xyz[3 * last + 2], e.z, 1e-4) << e.line;
    EXPECT_EQ(path.kind[last], static_cast<std::uint8_t>(e.kind)) << e.line;
    EXPECT_FLOAT_EQ(path.feed[last], static_cast<float>(e.feed)) << e.line;
    at = last + 1;
  }
  EXPECT_EQ(at, path.line.size());
  // Arc points lie on their circles: the helix (line 7) round (30, 5) r 5 with 60 steps of 6°,
  // the quarter (line 8) round (40, 0) r 10.
  std::size_t helix = 0, quarter = 0;
  for (std::size_t i = 0; i < path.line.size(); ++i) {
    const double x = path.xyz[3 * i], y = path.xyz[3 * i + 1];
    if (path.line[i] == 7) {
      ++helix;
      EXPECT_NEAR(std::hypot(x - 30, y - 5), 5, 1e-4);
    }
    if (path.line[i] == 8) {
      ++quarter;
      EXPECT_NEAR(std::hypot(x - 40, y), 10, 1e-4);
    }
  }
  EXPECT_EQ(helix, 60u);
  EXPECT_EQ(quarter, 15u);
}

TEST(PreviewPath, ARampIsALineDownEnteringFromARapid) {
  const PreviewPath path = preview_path(
      read_preview_program("r", "G21\nG0 X0 Y0 Z1\nG1 X5 Y0 Z-0.5 F300\nG1 X0 Y0 Z-1\nG1 X5 Y0\nM30\n", "r.nc"), 100,
      6);
  ASSERT_EQ(path.kind.size(), 4u);
  EXPECT_EQ(path.kind[1], static_cast<std::uint8_t>(StepKind::Ramp));
  EXPECT_EQ(path.kind[2], static_cast<std::uint8_t>(StepKind::Ramp));  // the zigzag ramp goes on
  EXPECT_EQ(path.kind[3], static_cast<std::uint8_t>(StepKind::Cut));
}

TEST(PreviewData, EmbedsThePathTheLinesTextAndSaysWhatWasDecimated) {
  PreviewInput in;
  in.title = "t";
  in.programs.push_back(read_preview_program("t", kProgram, "t.nc"));
  const json full = json::parse(preview_data_json(in));
  const PreviewPath path = preview_path(in.programs[0], 1000000, 6);
  ASSERT_EQ(full["programs"][0]["xyz"].size(), path.xyz.size());
  for (std::size_t i = 0; i < path.xyz.size(); ++i)
    EXPECT_NEAR(full["programs"][0]["xyz"][i].get<double>(), path.xyz[i], 6e-4);
  EXPECT_EQ(full["programs"][0]["text"]["6"], "G1 X30 Y0 Z-2 F300");
  EXPECT_TRUE(full["notes"].empty());
  in.limits.max_path_points = 10;
  const json small = json::parse(preview_data_json(in));
  const auto& xyz = small["programs"][0]["xyz"];
  ASSERT_EQ(xyz.size(), 30u);
  EXPECT_NEAR(xyz[0].get<double>(), 0, 1e-9);  // first point kept: G0 Z5 from X0 Y0
  EXPECT_NEAR(xyz[2].get<double>(), 5, 1e-9);
  EXPECT_NEAR(xyz[29].get<double>(), 5, 1e-9);  // last point kept (Z of the final rapid)
  ASSERT_EQ(small["notes"].size(), 1u);
  EXPECT_NE(small["notes"][0].get<std::string>().find("decimated"), std::string::npos);
}

TEST(PreviewData, SurfaceOverTheBudgetIsStridedAndKeepsItsValues) {
  PreviewInput in;
  in.programs.push_back(read_preview_program("t", kProgram, "t.nc"));
  PreviewSurface s;
  s.z = Eigen::MatrixXd::Zero(100, 80);
  s.value.resize(100, 80);
  for (int r = 0; r < 100; ++r)
    for (int c = 0; c < 80; ++c) s.value(r, c) = r * 0.01 + c * 0.0001;
  s.cell_mm = 0.5;
  in.surface = s;
  in.limits.max_surface_cells = 2000;  // 8000 cells → every 2nd: 50 × 40 = 2000
  const json j = json::parse(preview_data_json(in));
  EXPECT_EQ(j["surface"]["rows"], 50);
  EXPECT_EQ(j["surface"]["cols"], 40);
  EXPECT_DOUBLE_EQ(j["surface"]["cell"].get<double>(), 1.0);
  EXPECT_NEAR(j["surface"]["v"][41].get<double>(), 2 * 0.01 + 2 * 0.0001, 1e-9);  // row 1, col 1 = cell (2, 2)
  EXPECT_EQ(j["notes"].size(), 1u);
}

TEST(PreviewPage, BigJobStaysWithinItsPageBudgetInlinesThreeJsAndNeverClosesItsScriptEarly) {
  std::ostringstream g;
  g << "G21 G90 G17\nG0 Z5\nG0 X0 Y0\nG1 Z-1 F200\n";
  for (int i = 0; i < 400000; ++i) g << "G1 X" << (i % 2 ? 100 : 0) << " Y" << i * 0.01 << " F" << 500 + i % 7 << "\n";
  g << "G0 Z5\nM30\n";
  PreviewInput in;
  in.title = "big </script> <b>";
  in.programs.push_back(read_preview_program("big", g.str(), "big.nc"));
  const std::string html = preview_html(in);
  EXPECT_LE(html.size(), in.limits.max_page_bytes);  // issue 37 §3: pages ≤ 5 MB
  EXPECT_NE(html.find("OrbitControls"), std::string::npos);
  EXPECT_NE(html.find("id=\"millnet-data-gz\""), std::string::npos);  // packed: gzip + base64
  EXPECT_NE(page_data_json(html).find("decimated for display: path points 400004 → 200000"), std::string::npos);
  // A smaller page budget: decimated further than the point budget until the page fits.
  PreviewInput tight = in;
  tight.limits.max_page_bytes = 2000000;
  const std::string small = preview_html(tight);
  EXPECT_LE(small.size(), tight.limits.max_page_bytes);
  const json data = json::parse(page_data_json(small));
  const std::string note = data["notes"][0].get<std::string>();
  EXPECT_NE(note.find("decimated for display: path points 400004 → "), std::string::npos) << note;
  const auto shown = data["programs"][0]["kind"].size();
  EXPECT_LT(shown, 200000u);
  EXPECT_GT(shown, 20000u);  // shrunk in proportion to the excess, not to nothing
  // exactly the page's own script elements close: three.js, OrbitControls, data, page script, error trap
  std::size_t closes = 0;
  for (std::size_t p = html.find("</script"); p != std::string::npos; p = html.find("</script", p + 1)) ++closes;
  EXPECT_EQ(closes, 5u);
  EXPECT_EQ(html.find("<b>"), std::string::npos);
  EXPECT_EQ(preview_html(in), html);  // same input, same bytes
}

TEST(PreviewPage, DataOverAMegabyteIsPackedAndReadsBackToTheSameJson) {
  PreviewInput in;
  in.title = "t";
  in.programs.push_back(read_preview_program("t", kProgram, "t.nc"));
  const std::string small = preview_html(in);  // small data stays readable JSON in the page
  EXPECT_NE(small.find("id=\"millnet-data\""), std::string::npos);
  EXPECT_EQ(page_data_json(small), preview_data_json(in));
  std::ostringstream g;
  g << "G21 G90 G17\nG0 Z5\nG0 X0 Y0\nG1 Z-1 F200\n";
  for (int i = 0; i < 30000; ++i) g << "G1 X" << (i % 2 ? 100 : 0) << " Y" << i * 0.013 << " F" << 500 + i % 7 << "\n";
  g << "G0 Z5\nM30\n";
  in.programs = {read_preview_program("mid", g.str(), "mid.nc")};
  const std::string plain = preview_data_json(in);
  ASSERT_GT(plain.size(), kPlainDataBytes);
  const std::string packed = preview_html(in);
  EXPECT_NE(packed.find("id=\"millnet-data-gz\""), std::string::npos);
  EXPECT_EQ(packed.find("id=\"millnet-data\""), std::string::npos);
  EXPECT_EQ(page_data_json(packed), plain);  // under the page budget: nothing decimated, bytes kept
  EXPECT_LT(packed.size(), plain.size());
  EXPECT_EQ(preview_html(in), packed);  // gzip without a time stamp: same input, same bytes
  EXPECT_EQ(base64("Man"), "TWFu");     // RFC 4648 §10's vectors
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_THROW((void)page_data_json("<html></html>"), Error);
}

TEST(PreviewPage, MissingDebianScriptIsOneClearError) {
  ::setenv("MILLNET_JS_DIR", "/nonexistent/js", 1);
  PreviewInput in;
  in.programs.push_back(read_preview_program("t", kProgram, "t.nc"));
  try {
    (void)preview_html(in);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("/nonexistent/js/three/build/three.min.js"), std::string::npos) << m;
    EXPECT_NE(m.find("libjs-three"), std::string::npos) << m;
  }
  ::unsetenv("MILLNET_JS_DIR");
}

TEST(PreviewPage, UnreadableProgramNamesTheFile) {
  try {
    (void)read_preview_program("bad", "G21\nG1 X1 Q7\nM30\n", "bad.nc");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.nc"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace millnet::report
