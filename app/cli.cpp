#include "cli.hpp"

#include "millnet/core/error.hpp"
#include "millnet/core/progress.hpp"

#include <algorithm>
#include <iostream>
#include <omp.h>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {
bool g_quiet = false;
}

void add_common(CLI::App* sub, Common& common, bool with_config) {
  sub->add_flag("--quiet,-q", common.quiet, "no progress or information on stderr (errors still printed)");
  sub->add_option("--threads", common.threads, "OpenMP threads (0 = all cores; default from the config)")
      ->check(CLI::NonNegativeNumber);
  if (with_config)
    sub->add_option("--config", common.config, "JSON config (configs/schema/millnet.schema.json)")
        ->check(CLI::ExistingFile);
}

void MeshFlags::add_to(CLI::App* sub, const std::string& what) {
  sub->add_option("--units", units, "units of the " + what)->check(CLI::IsMember({"mm", "inch", "in", "m"}));
  sub->add_option("--up", up, "axis of the " + what + " that points up")
      ->check(CLI::IsMember({"+z", "-z", "+y", "-y", "+x", "-x", "z", "y", "x", "auto"}));
}

void PocketFlags::add_to(CLI::App* sub, bool with_planner_flags, bool with_depth) {
  sub->add_option("--tool-diameter", tool_diameter, "flat end mill diameter, mm")->check(CLI::PositiveNumber);
  sub->add_option("--stepover", stepover, "grid spacing / pass distance, mm")->check(CLI::PositiveNumber);
  if (with_depth) sub->add_option("--depth", depth, "pocket depth, mm (floor Z = -depth)")->check(CLI::PositiveNumber);
  sub->add_option("--step-down", step_down, "maximum depth of cut per level, mm")->check(CLI::PositiveNumber);
  sub->add_option("--safe-z", safe_z, "retract height, mm")->check(CLI::PositiveNumber);
  sub->add_option("--stock-to-leave", stock_to_leave, "radial allowance on walls and islands, mm")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--entry", entry, "entry into uncut material")->check(CLI::IsMember({"predrill", "helix", "ramp"}));
  sub->add_flag("--contour", contour, "finish with a contour pass along the walls");
  if (with_planner_flags) {
    sub->add_option("--planner", planner, "planner")->check(CLI::IsMember({"som", "zigzag"}));
    sub->add_option("--partition", partition, "zigzag partition (T: Tang, I: Suh & Kim)")
        ->check(CLI::IsMember({"t", "i", "T", "I"}));
    sub->add_option("--angle", angle, "zigzag reference angle in degrees, or auto");
  }
}

ingest::PrepareOptions MeshFlags::prepare(const Json* section) const {
  ingest::PrepareOptions prep;
  prep.units = ingest::parse_units(units.value_or(section ? (*section)["units"].get<std::string>() : "mm"));
  prep.up = ingest::parse_up(up.value_or(section ? (*section)["up"].get<std::string>() : "+z"));
  return prep;
}

Json setup(const Common& common) {
  g_quiet = common.quiet;
  Progress::set_quiet(common.quiet);
  Json config = common.config.empty() ? default_config(fs::current_path()) : load_config(common.config);
  int threads = common.threads >= 0 ? common.threads : config.value("threads", 0);
  if (threads > 0) omp_set_num_threads(threads);
  return config;
}

void info(const std::string& msg) {
  if (!g_quiet) std::cerr << msg << "\n";
}
void warn(const std::string& msg) { std::cerr << "warning: " << msg << "\n"; }

std::vector<fs::path> expand_inputs(const std::vector<std::string>& items, const std::vector<std::string>& extensions) {
  std::vector<fs::path> out;
  for (const auto& item : items) {
    fs::path p(item);
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      std::vector<fs::path> found;
      for (const auto& e : fs::directory_iterator(p)) {
        if (!e.is_regular_file()) continue;
        std::string ext = e.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        if (std::find(extensions.begin(), extensions.end(), ext) != extensions.end()) found.push_back(e.path());
      }
      std::sort(found.begin(), found.end());
      if (found.empty()) throw file_error(p.string(), "folder holds no input files");
      out.insert(out.end(), found.begin(), found.end());
    } else {
      out.push_back(p);  // existence is checked (and reported per file) by whoever reads it
    }
  }
  return out;
}

}  // namespace millnet::app
