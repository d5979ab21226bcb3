#include "millnet/datasets/io/manifest.hpp"

#include "millnet/core/error.hpp"
#include "millnet/datasets/hash.hpp"

#include <nlohmann/json.hpp>

#include <fstream>

namespace millnet::datasets_io {
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

Json read_json_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot open for reading");
  try {
    return Json::parse(in);
  } catch (const std::exception& e) {
    throw Error(path.string() + ": " + e.what());
  }
}

}  // namespace

Manifest read_manifest(const fs::path& path) {
  const Json m = read_json_file(path);
  Manifest out;
  try {
    if (m.contains("strategies") && m["strategies"].is_array())
      out.strategies = m["strategies"].get<std::vector<std::string>>();
    if (m.contains("config") && m["config"].is_object() && m["config"].contains("raster_mm"))
      out.raster_mm = m["config"]["raster_mm"].get<double>();
    if (m.contains("input_files") && m["input_files"].is_array())
      for (const auto& f : m["input_files"])
        out.input_files.push_back({f.value("name", std::string()), f.value("file", std::string()), f.value("label", 0),
                                   f.value("fnv1a64", std::string())});
  } catch (const std::exception& e) {
    throw Error(path.string() + ": " + e.what());
  }
  return out;
}

bool table_up_to_date(const fs::path& dir, const datasets::Recipe& recipe) {
  if (!fs::exists(dir / "vectors.csv") || !fs::exists(dir / "manifest.json")) return false;
  try {
    const Json m = read_json_file(dir / "manifest.json");
    bool same = m.contains("config") && m["config"] == Json::parse(datasets::recipe_json(recipe)) &&
                m.contains("input_files") && m["input_files"].size() == recipe.parts.size();
    for (std::size_t k = 0; same && k < recipe.parts.size(); ++k)
      same = m["input_files"][k].value("fnv1a64", "") == datasets::to_hex(datasets::fnv1a64_file(recipe.parts[k].file));
    return same;
  } catch (const std::exception&) {
    return false;  // an unreadable manifest means: rebuild
  }
}

}  // namespace millnet::datasets_io
