#include "millnet/datasets/io/manifest.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/json_input.hpp"
#include "millnet/core/json_text.hpp"
#include "millnet/datasets/hash.hpp"

#include <nlohmann/json.hpp>

#include <fstream>
#include <set>

#ifndef MILLNET_VERSION
#define MILLNET_VERSION "unknown"
#endif

namespace millnet::datasets_io {
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

Json read_json_file(const fs::path& path) {
  const std::string text = read_file(path);  // refuses what is not a regular file
  check_json_nesting(text, path.string());
  try {
    return Json::parse(text);
  } catch (const std::exception& e) {
    throw file_error(path.string(), "not valid JSON (" + json_error_text(e.what()) + ")");
  }
}

/// config.raster_mm when config is an object that has it.
std::optional<double> config_raster_mm(const Json& config) {
  if (!config.is_object() || !config.contains("raster_mm")) return std::nullopt;
  if (!config["raster_mm"].is_number()) throw Error("config echo: raster_mm: expected a number");
  return config["raster_mm"].get<double>();
}

// Reader with the key path in every message.
struct Reader {
  std::string file;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw file_error(file, key + ": " + what);
  }
  const Json& at(const Json& obj, const std::string& key, const std::string& path) const {
    const std::string full = path.empty() ? key : path + "." + key;
    if (!obj.is_object())
      fail(path.empty() ? "(top level)" : path, std::string("expected an object, got ") + obj.type_name());
    const auto it = obj.find(key);
    if (it == obj.end()) fail(full, "missing key");
    return *it;
  }
  std::string string(const Json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, std::string("expected a string, got ") + j.type_name());
    return j.get<std::string>();
  }
  template <class Int>
  Int integer(const Json& j, const std::string& path) const {
    if (!j.is_number_integer() || (std::is_unsigned_v<Int> && !j.is_number_unsigned()))
      fail(path, std::string("expected ") + (std::is_unsigned_v<Int> ? "a count" : "an integer") + ", got " +
                     (j.is_number() ? j.dump() : j.type_name()));
    return j.get<Int>();
  }
  bool boolean(const Json& j, const std::string& path) const {
    if (!j.is_boolean()) fail(path, std::string("expected true or false, got ") + j.type_name());
    return j.get<bool>();
  }
  const Json& array(const Json& j, const std::string& path) const {
    if (!j.is_array()) fail(path, std::string("expected an array, got ") + j.type_name());
    return j;
  }
  // Shorthands for a key of an object at `path`.
  std::string string_at(const Json& o, const std::string& k, const std::string& path) const {
    return string(at(o, k, path), path.empty() ? k : path + "." + k);
  }
  template <class Int>
  Int integer_at(const Json& o, const std::string& k, const std::string& path) const {
    return integer<Int>(at(o, k, path), path.empty() ? k : path + "." + k);
  }
};

}  // namespace

Manifest manifest_of(const datasets::Table& table, std::string_view csv) {
  Manifest m;
  m.program_version = MILLNET_VERSION;
  m.csv_fnv1a64 = datasets::to_hex(datasets::fnv1a64(csv));
  m.csv_bytes = csv.size();
  m.grid = table.grid_n;
  m.aspect_column = table.has_aspect;
  m.wall_share_column = table.has_wall_share;
  std::set<std::string> parts;
  for (const datasets::Row& r : table.rows) {  // O(rows)
    ++m.rows_per_label[r.label];
    parts.insert(r.source);
  }
  m.rows = table.rows.size();
  m.parts = parts.size();
  m.strategies.assign(table.strategies.begin(), table.strategies.end());
  for (const datasets::SourceFile& s : table.sources)
    m.input_files.push_back(
        {s.name, s.file, s.label, datasets::to_hex(s.fnv1a64), s.bytes, s.triangles, s.degenerate_triangles});
  m.labelling_json = table.labelling_json;
  if (!table.config_json.empty()) {
    m.config_json = table.config_json;
    try {
      m.raster_mm = config_raster_mm(Json::parse(table.config_json));
    } catch (const std::exception& e) {
      throw Error(std::string("manifest: the table's config echo is not valid JSON (") + json_error_text(e.what()) +
                  ")");
    }
  }
  return m;
}

std::string manifest_text(const Manifest& m) {
  const std::size_t inputs = static_cast<std::size_t>(m.grid) * static_cast<std::size_t>(m.grid);
  std::string j = "{\n";
  j += "  \"format\": \"millnet-vectors\",\n  \"format_version\": " + std::to_string(kManifestFormatVersion) + ",\n";
  j += "  \"program\": \"millnet\",\n  \"program_version\": " + json_string(m.program_version) + ",\n";
  j += "  \"csv\": \"vectors.csv\",\n";
  j += "  \"csv_fnv1a64\": \"" + m.csv_fnv1a64 + "\",\n";
  j += "  \"csv_bytes\": " + std::to_string(m.csv_bytes) + ",\n";
  j += "  \"grid\": " + std::to_string(m.grid) + ",\n";
  j += "  \"inputs\": " + std::to_string(inputs) + ",\n";
  j += "  \"outputs\": " + std::to_string(datasets::kStrategySlots) + ",\n";
  j += std::string("  \"aspect_column\": ") + (m.aspect_column ? "true" : "false") + ",\n";
  if (m.wall_share_column) j += "  \"wall_share_column\": true,\n";  // left out when false (older manifests)
  j += "  \"counts\": {\"rows\": " + std::to_string(m.rows) + ", \"parts\": " + std::to_string(m.parts) +
       ", \"rows_per_label\": {";
  bool first = true;
  for (const auto& [label, count] : m.rows_per_label) {
    j += (first ? "" : ", ") + json_string(std::to_string(label)) + ": " + std::to_string(count);
    first = false;
  }
  j += "}},\n  \"strategies\": [";
  for (std::size_t k = 0; k < m.strategies.size(); ++k) j += (k ? ", " : "") + json_string(m.strategies[k]);
  j += "],\n  \"hash\": \"fnv1a64\",\n  \"input_files\": [";
  for (std::size_t k = 0; k < m.input_files.size(); ++k) {
    const ManifestFile& s = m.input_files[k];
    j += (k ? ",\n    " : "\n    ");
    j += "{\"name\": " + json_string(s.name) + ", \"file\": " + json_string(s.file) +
         ", \"label\": " + std::to_string(s.label) + ", \"fnv1a64\": \"" + s.fnv1a64 +
         "\", \"bytes\": " + std::to_string(s.bytes) + ", \"triangles\": " + std::to_string(s.triangles) +
         ", \"degenerate_triangles\": " + std::to_string(s.degenerate_triangles) + "}";
  }
  j += m.input_files.empty() ? "],\n" : "\n  ],\n";
  j += "  \"config\": " + m.config_json;
  if (!m.labelling_json.empty()) j += ",\n  \"labelling\": " + m.labelling_json;
  j += "\n}\n";
  return j;
}

void write_table(const datasets::Table& table, const fs::path& dir) {
  const std::string csv = datasets::table_csv(table);
  const std::string manifest = manifest_text(manifest_of(table, csv));
  // CSV first: a manifest never describes a CSV that is not there.
  write_file_atomic(dir / "vectors.csv", csv);
  write_file_atomic(dir / "manifest.json", manifest);
}

struct TableWriter::Impl {
  AtomicOFStream csv;
  std::uint64_t hash = 0xCBF29CE484222325ULL;  // fnv1a64's basis, continued chunk by chunk
  std::size_t bytes = 0;
  std::map<int, std::size_t> rows_per_label;
  std::set<std::string> sources;  // every source seen: O(parts)
  std::string current_source;
  std::set<std::string> current_ids;  // the ids of the current source's rows: O(variants)
  std::string line;
  explicit Impl(const fs::path& path) : csv(path) {}
  void write(const std::string& text) {
    csv.stream().write(text.data(), static_cast<std::streamsize>(text.size()));
    hash = datasets::fnv1a64(text, hash);
    bytes += text.size();
  }
};

TableWriter::TableWriter(const fs::path& dir, int grid_n, bool has_aspect, datasets::StrategyNames strategies,
                         bool has_wall_share)
    : dir_(dir),
      grid_n_(grid_n),
      has_aspect_(has_aspect),
      has_wall_share_(has_wall_share),
      strategies_(std::move(strategies)) {
  const std::string header = datasets::csv_header(grid_n, has_aspect, has_wall_share);  // throws for a bad grid
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error(dir.string() + ": cannot create the folder (" + ec.message() + ")");
  impl_ = std::make_unique<Impl>(dir / "vectors.csv");
  impl_->write(header);
}

TableWriter::~TableWriter() = default;

void TableWriter::add(const datasets::Row& r) {
  Impl& w = *impl_;
  if (r.source != w.current_source || w.sources.empty()) {
    if (!w.sources.insert(r.source).second)
      throw Error("table: the rows of source '" + r.source + "' are not consecutive");
    w.current_source = r.source;
    w.current_ids.clear();
  }
  if (!w.current_ids.insert(r.id).second) throw Error("table: duplicate row id '" + r.id + "'");
  w.line.clear();
  datasets::append_csv_row(w.line, r, grid_n_, has_aspect_, has_wall_share_);
  w.write(w.line);
  ++w.rows_per_label[r.label];
  ++rows_;
}

void TableWriter::finish(const std::vector<datasets::SourceFile>& sources, const std::string& config_json,
                         const std::string& labelling_json) {
  Impl& w = *impl_;
  Manifest m;
  m.program_version = MILLNET_VERSION;
  m.csv_fnv1a64 = datasets::to_hex(w.hash);
  m.csv_bytes = w.bytes;
  m.grid = grid_n_;
  m.aspect_column = has_aspect_;
  m.wall_share_column = has_wall_share_;
  m.rows = rows_;
  m.parts = w.sources.size();
  m.rows_per_label = w.rows_per_label;
  m.strategies.assign(strategies_.begin(), strategies_.end());
  for (const datasets::SourceFile& s : sources)
    m.input_files.push_back(
        {s.name, s.file, s.label, datasets::to_hex(s.fnv1a64), s.bytes, s.triangles, s.degenerate_triangles});
  m.labelling_json = labelling_json;
  if (!config_json.empty()) {
    m.config_json = config_json;
    try {
      m.raster_mm = config_raster_mm(Json::parse(config_json));
    } catch (const std::exception& e) {
      throw Error(std::string("manifest: the table's config echo is not valid JSON (") + json_error_text(e.what()) +
                  ")");
    }
  }
  const std::string manifest = manifest_text(m);
  w.csv.commit();  // CSV first: a manifest never describes a CSV that is not there
  write_file_atomic(dir_ / "manifest.json", manifest);
}

Manifest read_manifest(const fs::path& path) {
  const Json j = read_json_file(path);
  const Reader rd{path.string()};
  if (const std::string f = rd.string_at(j, "format", ""); f != "millnet-vectors")
    rd.fail("format", "expected \"millnet-vectors\", got \"" + f + "\"");
  if (const int v = rd.integer_at<int>(j, "format_version", ""); v != kManifestFormatVersion)
    rd.fail("format_version", "this millnet reads manifest version " + std::to_string(kManifestFormatVersion) +
                                  ", the file is version " + std::to_string(v));
  Manifest m;
  m.program_version = rd.string_at(j, "program_version", "");
  m.csv_fnv1a64 = rd.string_at(j, "csv_fnv1a64", "");
  m.csv_bytes = rd.integer_at<std::size_t>(j, "csv_bytes", "");
  m.grid = rd.integer_at<int>(j, "grid", "");
  m.aspect_column = rd.boolean(rd.at(j, "aspect_column", ""), "aspect_column");
  if (j.contains("wall_share_column"))
    m.wall_share_column = rd.boolean(rd.at(j, "wall_share_column", ""), "wall_share_column");
  const Json& counts = rd.at(j, "counts", "");
  m.rows = rd.integer_at<std::size_t>(counts, "rows", "counts");
  m.parts = rd.integer_at<std::size_t>(counts, "parts", "counts");
  const Json& per_label = rd.at(counts, "rows_per_label", "counts");
  if (!per_label.is_object())
    rd.fail("counts.rows_per_label", std::string("expected an object, got ") + per_label.type_name());
  for (const auto& [label, rows] : per_label.items()) {
    const std::string key = "counts.rows_per_label." + label;
    int l = 0;
    try {
      std::size_t used = 0;
      l = std::stoi(label, &used);
      if (used != label.size()) throw std::invalid_argument(label);
    } catch (const std::exception&) {
      rd.fail(key, "expected a label number as the key");
    }
    m.rows_per_label[l] = rd.integer<std::size_t>(rows, key);
  }
  const Json& strategies = rd.array(rd.at(j, "strategies", ""), "strategies");
  for (std::size_t k = 0; k < strategies.size(); ++k)
    m.strategies.push_back(rd.string(strategies[k], "strategies[" + std::to_string(k) + "]"));
  const Json& files = rd.array(rd.at(j, "input_files", ""), "input_files");
  for (std::size_t k = 0; k < files.size(); ++k) {
    const std::string p = "input_files[" + std::to_string(k) + "]";
    ManifestFile f;
    f.name = rd.string_at(files[k], "name", p);
    f.file = rd.string_at(files[k], "file", p);
    f.label = rd.integer_at<int>(files[k], "label", p);
    f.fnv1a64 = rd.string_at(files[k], "fnv1a64", p);
    f.bytes = rd.integer_at<std::uintmax_t>(files[k], "bytes", p);
    f.triangles = rd.integer_at<std::size_t>(files[k], "triangles", p);
    f.degenerate_triangles = rd.integer_at<std::size_t>(files[k], "degenerate_triangles", p);
    m.input_files.push_back(std::move(f));
  }
  const Json& config = rd.at(j, "config", "");
  if (!config.is_null() && !config.is_object())
    rd.fail("config", std::string("expected an object or null, got ") + config.type_name());
  m.config_json = config.dump();
  if (config.is_object() && config.contains("raster_mm") && !config["raster_mm"].is_number())
    rd.fail("config.raster_mm", std::string("expected a number, got ") + config["raster_mm"].type_name());
  m.raster_mm = config_raster_mm(config);
  if (j.contains("labelling")) {
    if (!j["labelling"].is_object())
      rd.fail("labelling", std::string("expected an object, got ") + j["labelling"].type_name());
    m.labelling_json = j["labelling"].dump();
  }
  return m;
}

bool table_up_to_date(const fs::path& dir, const datasets::Recipe& recipe) {
  if (!fs::exists(dir / "vectors.csv") || !fs::exists(dir / "manifest.json")) return false;
  try {
    const Manifest m = read_manifest(dir / "manifest.json");
    bool same = Json::parse(m.config_json) == Json::parse(datasets::recipe_json(recipe)) &&
                m.input_files.size() == recipe.parts.size();
    for (std::size_t k = 0; same && k < recipe.parts.size(); ++k)
      same = m.input_files[k].fnv1a64 == datasets::to_hex(datasets::fnv1a64_file(recipe.parts[k].file));
    return same;
  } catch (const std::exception&) {
    return false;  // an unreadable manifest means: rebuild
  }
}

}  // namespace millnet::datasets_io
