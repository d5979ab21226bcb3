#include "preview.hpp"

#include <cmath>

namespace millnet::app {

namespace {
PreviewSettings g_preview;
}  // namespace

const PreviewSettings& preview_settings() { return g_preview; }
void set_preview_settings(const PreviewSettings& s) { g_preview = s; }

void set_preview_part(report::PreviewInput& in, const ingest::Mesh& mesh, double z_shift) {
  in.part_V = mesh.V.cast<double>();
  in.part_V.col(2).array() += z_shift;
  in.part_F = mesh.F.cast<int>();
}

report::PreviewSurface preview_surface(const simulate::ZMap& z, const std::vector<double>& value,
                                       const std::string& name, const std::string& units) {
  const simulate::GridSpec& g = z.spec();
  report::PreviewSurface s;
  const auto ny = static_cast<Eigen::Index>(g.ny), nx = static_cast<Eigen::Index>(g.nx);
  s.z.resize(ny, nx);
  s.value.resize(ny, nx);
  for (Eigen::Index r = 0; r < ny; ++r)
    for (Eigen::Index c = 0; c < nx; ++c) {
      const auto i = static_cast<std::size_t>(r * nx + c);
      s.z(r, c) = z.heights()[i];
      s.value(r, c) = i < value.size() ? value[i] : std::nan("");
    }
  s.x0 = g.x0;
  s.y0 = g.y0;
  s.cell_mm = g.cell;
  s.value_name = name;
  s.units = units;
  return s;
}

bool write_program_preview(const std::filesystem::path& html, report::PreviewInput in) {
  if (!g_preview.enabled) return false;
  in.limits = g_preview.limits;
  report::write_preview(html, in);
  return true;
}

}  // namespace millnet::app
