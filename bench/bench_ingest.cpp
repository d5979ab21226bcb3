// Height sampling throughput (issue 2 goal: ≥ 20 M triangles/s per core for the rasterization)
// and the load time of the same mesh as binary STL, reported separately.
//   bench_ingest --benchmark_filter=Rasterize
#include "millnet/ingest/heightfield.hpp"
#include "millnet/ingest/io/mesh_io.hpp"

#include <benchmark/benchmark.h>
#if MILLNET_HAVE_CAD
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <STEPControl_Writer.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_ListOfShape.hxx>
#include <gp_Ax2.hxx>
#endif
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

using namespace millnet::ingest;

namespace {

// A wavy 200 × 200 mm surface from a 1000 × 500 cell grid: exactly 1,000,000 triangles
// (cells 0.2 × 0.4 mm, so at a 1 mm raster most triangles cover no raster point).
const Mesh& wavy() {
  static const Mesh m = [] {
    const int nx = 1000, ny = 500;
    Mesh w;
    w.V.resize((nx + 1) * (ny + 1), 3);
    for (int i = 0; i <= ny; ++i)
      for (int j = 0; j <= nx; ++j) {
        const double x = 200.0 * j / nx, y = 200.0 * i / ny;
        w.V.row(i * (nx + 1) + j) << x, y, 10 + 4 * std::sin(x / 7) * std::cos(y / 11) + 0.02 * x;
      }
    w.F.resize(2 * nx * ny, 3);
    int t = 0;
    for (int i = 0; i < ny; ++i)
      for (int j = 0; j < nx; ++j) {
        const int a = i * (nx + 1) + j, b = a + 1, c = a + nx + 1, d = c + 1;
        w.F.row(t++) << a, b, d;
        w.F.row(t++) << a, d, c;
      }
    return w;
  }();
  return m;
}

// Args: raster in 0.1 mm units, threads.
void BM_Rasterize(benchmark::State& state) {
  const Mesh& m = wavy();
  const double raster = 0.1 * static_cast<double>(state.range(0));
  omp_set_num_threads(static_cast<int>(state.range(1)));
  std::size_t hits = 0;
  for (auto _ : state) {
    HeightField f = rasterize_top(m, raster);
    hits = f.z.size();
    benchmark::DoNotOptimize(f.z.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * m.F.rows());
  state.counters["raster_points"] = static_cast<double>(hits);
  state.counters["threads"] = static_cast<double>(state.range(1));
}
BENCHMARK(BM_Rasterize)
    ->Args({10, 1})
    ->Args({10, 2})
    ->Args({1, 1})
    ->Args({1, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_SampleGrid15(benchmark::State& state) {
  const Mesh& m = wavy();
  omp_set_num_threads(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(sample_grid(m, 1.0, 15).h.data());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * m.F.rows());
}
BENCHMARK(BM_SampleGrid15)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_LoadBinaryStl(benchmark::State& state) {
  const Mesh& m = wavy();
  const auto path =
      std::filesystem::temp_directory_path() / ("millnet_bench_wavy_" + std::to_string(::getpid()) + ".stl");
  save_stl_binary(m, path);
  for (auto _ : state) {
    Mesh back = load_mesh(path);
    benchmark::DoNotOptimize(back.V.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * m.F.rows());
  state.counters["MB"] = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
  std::filesystem::remove(path);
}
BENCHMARK(BM_LoadBinaryStl)->Unit(benchmark::kMillisecond)->UseRealTime();

#if MILLNET_HAVE_CAD
// Read + tessellate a STEP part of a few hundred faces (issue 16): a 130 × 130 × 10 mm plate with
// a 12 × 12 grid of Ø6 mm bosses 4 mm high (2 faces each) fused on top, written once as STEP.
const std::filesystem::path& bosses_step(std::size_t* faces) {
  static std::size_t n = 0;
  static const std::filesystem::path path = [] {
    TopTools_ListOfShape args, tools;
    args.Append(BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 130, 130, 10).Shape());
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j)
        tools.Append(
            BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(10 + 10 * i, 10 + 10 * j, 10), gp_Dir(0, 0, 1)), 3, 4).Shape());
    BRepAlgoAPI_Fuse fuse;
    fuse.SetArguments(args);
    fuse.SetTools(tools);
    fuse.Build();
    const TopoDS_Shape part = fuse.Shape();
    for (TopExp_Explorer x(part, TopAbs_FACE); x.More(); x.Next()) ++n;
    const auto p =
        std::filesystem::temp_directory_path() / ("millnet_bench_bosses_" + std::to_string(::getpid()) + ".step");
    STEPControl_Writer w;
    w.Transfer(part, STEPControl_AsIs);
    w.Write(p.string().c_str());
    return p;
  }();
  *faces = n;
  return path;
}

void BM_LoadStepTessellate(benchmark::State& state) {
  std::size_t faces = 0;
  const auto& path = bosses_step(&faces);
  CadOptions cad;
  cad.chord_tolerance_mm = state.range(0) == 0 ? 0.005 : 0.05;
  std::int64_t triangles = 0;
  for (auto _ : state) {
    Mesh m = load_mesh(path, cad);
    triangles = m.F.rows();
    benchmark::DoNotOptimize(m.V.data());
  }
  state.counters["faces"] = static_cast<double>(faces);
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["chord_mm"] = cad.chord_tolerance_mm;
}
BENCHMARK(BM_LoadStepTessellate)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
#endif

}  // namespace

BENCHMARK_MAIN();
