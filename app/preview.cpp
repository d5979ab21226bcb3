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

report::PreviewSurface preview_surface(const simulate::ZMap& z, const std::vector<double>& design,
                                       const std::string& name, const std::string& units) {
  return report::zmap_surface(z, design, g_preview.limits.max_surface_cells, name, units);
}

bool write_program_preview(const std::filesystem::path& html, report::PreviewInput in) {
  if (!g_preview.enabled) return false;
  in.limits = g_preview.limits;
  report::write_preview(html, in);
  return true;
}

}  // namespace millnet::app
