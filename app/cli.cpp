#include "cli.hpp"
#include "preview.hpp"
#include "mpi_cluster.hpp"

#include "millnet/core/error.hpp"
#include "millnet/core/progress.hpp"
#include "millnet/gcode/writer.hpp"
#include "millnet/ingest/io/mesh_io.hpp"
#include "millnet/pocket/planner_registry.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <iostream>
#include <set>
#include <mutex>
#include <omp.h>

namespace millnet::app {
namespace fs = std::filesystem;

namespace {
bool g_quiet = false;
WorkLimits g_limits;
}  // namespace

CLI::Validator schema_range(const std::string& pointer) {
  const Json* rule = &schema();
  for (std::size_t b = 1; b < pointer.size();) {
    std::size_t e = pointer.find('/', b);
    if (e == std::string::npos) e = pointer.size();
    rule = &(*rule)["properties"][pointer.substr(b, e - b)];
    b = e + 1;
  }
  std::string range;
  std::optional<double> lo, hi;
  bool lo_open = false;
  if (rule->contains("exclusiveMinimum")) {
    lo = (*rule)["exclusiveMinimum"].get<double>();
    lo_open = true;
    range = " > " + (*rule)["exclusiveMinimum"].dump();
  } else if (rule->contains("minimum")) {
    lo = (*rule)["minimum"].get<double>();
    range = " ≥ " + (*rule)["minimum"].dump();
  }
  bool hi_open = false;
  if (rule->contains("exclusiveMaximum")) {
    hi = (*rule)["exclusiveMaximum"].get<double>();
    hi_open = true;
    range += (range.empty() ? " < " : " and < ") + (*rule)["exclusiveMaximum"].dump();
  } else if (rule->contains("maximum")) {
    hi = (*rule)["maximum"].get<double>();
    range += (range.empty() ? " ≤ " : " and ≤ ") + (*rule)["maximum"].dump();
  }
  const bool integer = rule->value("type", "") == "integer";
  const std::string expected =
      std::string("expected ") + (integer ? "an integer" : "a finite number") + range + " (" + pointer + ")";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0;
        const char* b = text.data();
        const char* e = text.data() + text.size();
        if (b < e && *b == '+') ++b;
        const auto r = std::from_chars(b, e, v);
        bool ok = r.ec == std::errc() && r.ptr == e && std::isfinite(v);
        // An integer flag is plain decimal digits: CLI11 reads "15.5" as nothing (a usage error) and
        // "010" as octal 8, "0x10" as 16 (issue 15: a grid of 15.5 became 15;
        // tests/corpus/cli/flag_grid_15_5.args).
        if (ok && integer) {
          const char* d = text.data();
          if (d < e && (*d == '+' || *d == '-')) ++d;
          ok = d < e && std::all_of(d, e, [](char c) { return c >= '0' && c <= '9'; }) && !(*d == '0' && e - d > 1);
        }
        if (ok && lo) ok = lo_open ? v > *lo : v >= *lo;
        if (ok && hi) ok = hi_open ? v < *hi : v <= *hi;
        return ok ? std::string() : expected + ", got " + text.substr(0, 40);
      },
      (integer ? "INT" : "NUMBER") + range);
}

CLI::Validator output_path() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        // Issue 15: `--out ""` wrote into the current folder (tests/corpus/cli/flag_out_empty.args).
        if (text.find_first_not_of(" \t\r\n") == std::string::npos)
          return "expected a folder to write into, got an empty path";
        return std::string();
      },
      "PATH");
}

void add_common(CLI::App* sub, Common& common, bool with_config) {
  sub->add_flag("--quiet,-q", common.quiet, "no progress or information on stderr (errors still printed)");
  sub->add_option("--threads", common.threads, "OpenMP threads (0 = all cores, at most 1024; default from the config)")
      ->check(schema_range("/threads"));
  sub->add_option("--max-work", common.max_work,
                  "items (points, cells, lines) one stage may make before it is refused (default /limits/max_work)")
      ->check(schema_range("/limits/max_work"));
  sub->add_option("--max-memory-mb", common.max_memory_mb,
                  "MiB one stage may hold before it is refused (default /limits/max_memory_mb)")
      ->check(schema_range("/limits/max_memory_mb"));
  sub->add_option(
         "--max-pairs", common.max_pairs,
         "vector pairs the classifier's leave-one-out may compare before it is refused (default /limits/max_pairs)")
      ->check(schema_range("/limits/max_pairs"));
  sub->add_flag("--no-preview", common.no_preview,
                "do not write the <stem>.html 3D preview pages next to programs and height fields (/report/preview)");
  if (with_config)
    sub->add_option("--config", common.config, "JSON config (configs/schema/millnet.schema.json)")
        ->check(CLI::ExistingFile);
}

void add_post_flag(CLI::App* sub, std::optional<std::string>& post) {
  sub->add_option("--post", post, "the controller's G-code dialect of every program written (default /machine/post)")
      ->check(CLI::IsMember(gcode::dialect_names()));
}

void MeshFlags::add_to(CLI::App* sub, const std::string& what) {
  sub->add_option("--units", units, "units of the " + what)->check(CLI::IsMember({"mm", "inch", "in", "m"}));
  sub->add_option("--up", up, "axis of the " + what + " that points up")
      ->check(CLI::IsMember({"+z", "-z", "+y", "-y", "+x", "-x", "z", "y", "x", "auto"}));
  sub->add_option(
      "--body", body,
      "STEP/IGES: keep one body, by name or 1-based index (default: every solid, shell and face; /mesh/cad_body)");
}

ingest::CadOptions cad_options(const Json& config) {
  ingest::CadOptions c;
  if (!config.contains("mesh")) return c;
  const Json& m = config["mesh"];
  c.chord_tolerance_mm = m.value("chord_tolerance_mm", c.chord_tolerance_mm);
  c.angular_deflection_rad = m.value("angular_deflection_rad", c.angular_deflection_rad);
  c.body = m.value("cad_body", std::string());
  c.allow_partial = m.value("allow_partial_cad", false);
  c.limits = work_limits();  // the tessellation's estimate and the reader's memory (issue 42)
  return c;
}

job::Part load_part(const fs::path& file, const ingest::PrepareOptions& prep) {
  ingest::MeshReport rep;
  job::Part part;
  part.mesh = ingest::load_prepared(file, prep, &rep);
  part.name = file.stem().string();
  part.file = file;
  part.triangles = rep.triangles;
  if (rep.is_cad) {
    part.cad = rep.cad;
    // The note once per file and process: a batch under MPI loads a part once per unit.
    static std::mutex noted_mutex;
    static std::set<std::string> noted;
    bool first = false;
    {
      std::lock_guard<std::mutex> lock(noted_mutex);
      first = noted.insert(file.string()).second;
    }
    // info(): silent under --quiet, where the note and an error made two lines (issue 42 §10;
    // tests/corpus/cli/quiet_cad_note_and_error.args).
    if (first && !rep.cad.units_note.empty()) info("note: " + rep.cad.units_note);
  }
  return part;
}

Json cad_metrics(const job::Part& part) {
  if (!part.cad) return Json();
  const ingest::CadReport& c = *part.cad;
  return {{"format", c.format},
          {"file_unit", c.file_unit},
          {"file_unit_mm", c.file_unit_mm},
          {"units_overridden", c.units_overridden},
          {"chord_tolerance_mm", c.chord_tolerance_mm},
          {"angular_deflection_rad", c.angular_deflection_rad},
          {"body", c.body.empty() ? Json("all") : Json(c.body)},
          {"bodies", c.bodies},
          {"faces", c.faces},
          {"triangles", part.triangles}};
}

void PocketFlags::add_to(CLI::App* sub, bool with_planner_flags, bool with_depth) {
  auto* by_id = sub->add_option("--tool", tool_id, "roughing tool: an id of the tool library (configs/tools.json)");
  sub->add_option("--tool-diameter", tool_diameter, "flat end mill diameter, mm (a tool given inline)")
      ->check(schema_range("/pocket/tool_diameter"))
      ->excludes(by_id);
  sub->add_option("--material", material, "workpiece material id (configs/materials.json)");
  sub->add_option("--stepover", stepover, "grid spacing / pass distance, mm")->check(schema_range("/pocket/stepover"));
  if (with_depth)
    sub->add_option("--depth", depth, "pocket depth, mm (floor Z = -depth)")->check(schema_range("/pocket/depth"));
  sub->add_option("--step-down", step_down, "maximum depth of cut per level, mm")
      ->check(schema_range("/pocket/step_down"));
  sub->add_option("--safe-z", safe_z, "retract height, mm")->check(schema_range("/pocket/safe_z"));
  sub->add_option("--stock-to-leave", stock_to_leave, "radial allowance on walls and islands, mm")
      ->check(schema_range("/pocket/stock_to_leave"));
  sub->add_option("--entry", entry, "entry into uncut material")->check(CLI::IsMember({"predrill", "helix", "ramp"}));
  add_post_flag(sub, post);
  auto* with = sub->add_flag("--contour", contour, "cut the wall pass (the default: /pocket/contour true)");
  sub->add_flag("--no-contour", no_contour,
                "leave the wall pass out: parts of the reachable region near the walls stay uncut")
      ->excludes(with);
  if (with_planner_flags) {
    sub->add_option("--planner", planner, "planner")->check(CLI::IsMember(pocket::planner_names()));
    sub->add_option("--partition", partition, "zigzag partition (T: Tang, I: Suh & Kim)")
        ->check(CLI::IsMember({"t", "i", "T", "I"}));
    sub->add_option("--angle", angle, "zigzag reference angle in degrees, or auto");
  }
}

ingest::PrepareOptions MeshFlags::prepare(const Json* section, const Json* config) const {
  ingest::PrepareOptions prep;
  const std::string u = units.value_or(section ? (*section)["units"].get<std::string>() : "mm");
  prep.units = ingest::parse_units(u);
  prep.units_explicit = units.has_value() || u != "mm";
  prep.up = ingest::parse_up(up.value_or(section ? (*section)["up"].get<std::string>() : "+z"));
  if (config) prep.cad = cad_options(*config);
  if (body) prep.cad.body = *body;
  return prep;
}

Json setup(const Common& common) {
  // Under MPI only rank 0 talks (the others' errors still print).
  g_quiet = common.quiet || !cluster_root();
  Progress::set_quiet(g_quiet);
  Json config = common.config.empty() ? default_config(fs::current_path()) : load_config(common.config);
  int threads = common.threads >= 0 ? common.threads : config.value("threads", 0);
  if (threads > 0) omp_set_num_threads(threads);
  const Json& lim = config["limits"];
  g_limits.max_work = common.max_work.value_or(lim["max_work"].get<double>());
  g_limits.max_memory_bytes = common.max_memory_mb.value_or(lim["max_memory_mb"].get<double>()) * 1024.0 * 1024.0;
  g_limits.max_pairs = common.max_pairs.value_or(lim["max_pairs"].get<double>());
  const Json& rep = config["report"];
  PreviewSettings ps;
  ps.enabled = !common.no_preview && rep["preview"].get<bool>();
  ps.limits.max_path_points = rep["max_path_points"].get<std::size_t>();
  ps.limits.max_surface_cells = rep["max_surface_cells"].get<std::size_t>();
  set_preview_settings(ps);
  return config;
}

const WorkLimits& work_limits() { return g_limits; }

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
        std::transform(ext.begin(), ext.end(), ext.begin(),
                       [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        if (std::find(extensions.begin(), extensions.end(), ext) != extensions.end()) found.push_back(e.path());
      }
      std::sort(found.begin(), found.end());
      if (found.empty()) throw file_error(p.string(), "folder holds no input files");
      out.insert(out.end(), found.begin(), found.end());
    } else {
      // A missing file given by name is found before anything is written (issue 15: `rough` with a
      // missing second mesh left the first mesh's outputs; tests/corpus/cli/rough_second_mesh_missing.args).
      // A file that exists but cannot be read is reported per file by whoever reads it.
      if (!fs::exists(p, ec)) throw file_error(p.string(), "no such file");
      out.push_back(p);
    }
  }
  return out;
}

}  // namespace millnet::app
