// millnet sample --mesh FILE [--units] [--up] [--raster 1] [--grid 15] --out DIR
//   → DIR/<stem>.grid.csv (n rows × n columns, mm above the part's lowest point; rows from min y to max y,
//     columns from min x to max x; the grid spans the footprint rectangle corner to corner), DIR/<stem>.png
#include "cli.hpp"
#include "preview.hpp"
#include "report_util.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/ingest/heightfield.hpp"
#include "millnet/ingest/io/grid_csv.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

namespace millnet::app {
namespace fs = std::filesystem;

namespace {

struct SampleOpts {
  Common common;
  MeshFlags mesh_flags;
  std::string mesh, out;
  double raster = 1.0;
  int grid = 15;
};

/// The 3D page of a sampled part (issue 16): the part shaded and its n×n grid as a surface over it,
/// coloured by height. The grid's nodes span the footprint corner to corner, so a node is the centre
/// of a cell of footprint/(n − 1) in x and in y (the page's surface format).
void write_grid_page(const fs::path& html, const ingest::Mesh& mesh, const ingest::Grid& grid,
                     const std::string& stem) {
  const Eigen::RowVector3d lo = mesh.V.colwise().minCoeff().cast<double>();
  const Eigen::RowVector3d hi = mesh.V.colwise().maxCoeff().cast<double>();
  const auto n = grid.h.rows();
  report::PreviewInput page;
  page.title = stem + " — " + std::to_string(n) + "×" + std::to_string(n) + " height grid";
  set_preview_part(page, mesh);
  page.stock = std::array<double, 6>{lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z()};
  report::PreviewSurface s;
  s.z = grid.h.array() + lo.z();
  s.value = grid.h;
  s.cell_mm = grid.footprint_x / static_cast<double>(n - 1);
  s.cell_y_mm = grid.footprint_y / static_cast<double>(n - 1);
  s.x0 = lo.x() - 0.5 * s.cell_mm;
  s.y0 = lo.y() - 0.5 * s.cell_y_mm;
  s.layer = "height grid";
  s.value_name = "height above the part's lowest point";
  page.surface = std::move(s);
  page.notes.push_back("footprint " + format_double(grid.footprint_x) + " × " + format_double(grid.footprint_y) +
                       " mm; the model vector's inputs are these heights");
  (void)write_program_preview(html, std::move(page));
}

/// millnet sample: mesh → prepared mesh → n×n grid → CSV + PNG + 3D page.
int run_sample(const SampleOpts& o) {
  (void)setup(o.common);
  ingest::MeshReport report;
  const ingest::Mesh mesh = ingest::load_prepared(o.mesh, o.mesh_flags.prepare(nullptr), &report);
  if (report.is_cad && !report.cad.units_note.empty()) info("note: " + report.cad.units_note);
  const ingest::Grid grid = ingest::sample_grid(mesh, o.raster, o.grid, work_limits());
  // Before anything is written: the heat map's "extent_mm must be finite … with min < max" was the
  // message for a part without a footprint (issue 15; tests/corpus/cli/sample_footprint_zero.args).
  if (!(grid.footprint_x > 0) || !(grid.footprint_y > 0))
    throw file_error(o.mesh, "the part's footprint seen from " +
                                 (o.mesh_flags.up ? *o.mesh_flags.up : std::string("+z")) + " is " +
                                 format_double(grid.footprint_x) + " × " + format_double(grid.footprint_y) +
                                 " mm, expected an extent in X and in Y (a wall or a line seen from above?)");
  const std::string stem = fs::path(o.mesh).stem().string();
  const fs::path out(o.out);
  write_file_atomic(out / (stem + ".grid.csv"), ingest::grid_csv(grid.h));
  write_grid_png(out / (stem + ".png"), grid, stem);
  write_grid_page(out / (stem + ".html"), mesh, grid, stem);
  info("sample: " + o.mesh + ": " + std::to_string(report.triangles) + " triangles (" +
       std::to_string(report.degenerate_triangles) + " degenerate), footprint " + format_double(grid.footprint_x) +
       " × " + format_double(grid.footprint_y) + " mm → " + (out / (stem + ".grid.csv")).string());
  return 0;
}

}  // namespace

Registered register_sample(CLI::App& app) {
  auto o = std::make_shared<SampleOpts>();
  CLI::App* sub = app.add_subcommand("sample", "sample a mesh into an n×n height grid (CSV + PNG heat map)");
  sub->add_option("--mesh", o->mesh, "mesh file (STL, OBJ, PLY, OFF, 3MF, glTF, … or x y z points)")->required();
  o->mesh_flags.add_to(sub, "file");
  sub->add_option("--raster", o->raster, "raster spacing, mm")->check(schema_range("/dataset/raster_mm"));
  sub->add_option("--grid", o->grid, "grid size n")->check(schema_range("/dataset/grid"));
  sub->add_option("--out", o->out, "output folder")->check(output_path())->required();
  add_common(sub, o->common, false);
  return {sub, [o]() { return run_sample(*o); }};
}

}  // namespace millnet::app
