#pragma once
// The 3D preview page every command writes next to a program or height field (issue 16 §2):
// <stem>.html, on unless --no-preview or /report/preview = false. The page itself: app/report
// (millnet/report/preview.hpp).
#include "millnet/ingest/mesh.hpp"
#include "millnet/report/preview.hpp"
#include "millnet/simulate/zmap.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace millnet::app {

/// What setup() settled from /report and --no-preview.
struct PreviewSettings {
  bool enabled = true;
  report::PreviewLimits limits;
};
[[nodiscard]] const PreviewSettings& preview_settings();
void set_preview_settings(const PreviewSettings& s);

/// The part as the page shows it: V shifted by z_shift in Z (program Z = part z + z_shift).
void set_preview_part(report::PreviewInput& in, const ingest::Mesh& mesh, double z_shift = 0);

/// The machined surface of a z-map coloured by its deviation from `design`, for the page: only the
/// cells the page shows (report::zmap_surface).
[[nodiscard]] report::PreviewSurface preview_surface(const simulate::ZMap& z, const std::vector<double>& design,
                                                     const std::string& name = "deviation, machined − design",
                                                     const std::string& units = "mm");

/// Writes `html` (atomically) when previews are on; the programs are given as text. Returns whether it wrote.
bool write_program_preview(const std::filesystem::path& html, report::PreviewInput in);

}  // namespace millnet::app
