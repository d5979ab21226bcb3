// Tool files from disk: the format's reader over a bounded read, and a FreeCAD library's bits.
#include "common.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

#include <algorithm>
#include <cctype>
#include <system_error>

namespace millnet::tooling::io {
using namespace detail;
namespace fs = std::filesystem;

namespace {

/// The file's text, refused before it is read when it is larger than the limit (what is left of it
/// when `budget` counts what a library's bits have read already).
std::string read_bounded(const fs::path& path, std::size_t& budget) {
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) {
    const std::uintmax_t size = fs::file_size(path, ec);
    if (!ec && size > budget)
      throw file_error(path.string(), std::to_string(size) + " bytes; the limit for a tool table is " +
                                          std::to_string(kMaxToolFileBytes >> 20) + " MiB" +
                                          (budget < kMaxToolFileBytes ? " (with its library's other files)" : ""));
  }
  std::string text = read_file(path);  // names the path when it is missing, a folder, a FIFO, …
  if (text.size() > budget) throw file_error(path.string(), "larger than the limit for a tool table");
  budget -= text.size();
  return text;
}

bool is_library(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".fctl";
}

}  // namespace

ToolFormat parse_tool_format(const std::string& s) {
  if (s == "linuxcnc") return ToolFormat::LinuxCnc;
  if (s == "freecad") return ToolFormat::FreeCad;
  if (s == "fusion") return ToolFormat::Fusion;
  throw Error("tool table format " + in_quotes(s) + ": expected linuxcnc, freecad or fusion");
}

ToolImport import_tool_file(const fs::path& path, ToolFormat format, LengthUnit units) {
  std::size_t budget = kMaxToolFileBytes;
  const std::string source = path.string();
  const std::string text = read_bounded(path, budget);
  switch (format) {
    case ToolFormat::LinuxCnc: return read_linuxcnc_tool_table(text, source, units);
    case ToolFormat::Fusion: return read_fusion_library(text, source);
    case ToolFormat::FreeCad: break;
  }
  if (!is_library(path)) return read_freecad_toolbit(text, source);
  // A library names its bits by path: relative to the library, else (FreeCAD's own layout, Tools/Library
  // beside Tools/Bit, library/serializers/fctl.py) in ../Bit/ by file name.
  const fs::path dir = path.parent_path();
  const BitLoader load = [&](const std::string& name) -> BitFile {
    const fs::path p(name);
    std::vector<fs::path> tries{p.is_absolute() ? p : dir / p};
    if (!p.is_absolute()) tries.push_back(dir / ".." / "Bit" / p.filename());
    for (const fs::path& f : tries) {
      std::error_code ec;
      if (fs::exists(f, ec)) return {read_bounded(f, budget), f.lexically_normal().string()};
    }
    std::string looked;
    for (const fs::path& f : tries) looked += (looked.empty() ? "" : " and ") + f.lexically_normal().string();
    throw Error("bit file " + in_quotes(name) + " not found (looked at " + looked + ")");
  };
  return read_freecad_library(text, source, load);
}

}  // namespace millnet::tooling::io
