#include "millnet/simulate/io/zmap_file.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/core/json_input.hpp"

#include <nlohmann/json.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <system_error>

namespace millnet::simulate::io {
namespace fs = std::filesystem;

namespace {

constexpr const char* kMagic = "millnet-zmap 1";
constexpr const char* kMagicSurround = "millnet-zmap 2";  // with the block's surround after the heights
constexpr std::size_t kMaxHeaderBytes = 4096;

static_assert(sizeof(double) == 8 && std::numeric_limits<double>::is_iec559);

std::uint64_t to_le(std::uint64_t v) {
  if constexpr (std::endian::native == std::endian::big) {
    std::uint64_t r = 0;
    for (int i = 0; i < 8; ++i) r = (r << 8) | ((v >> (8 * i)) & 0xffU);
    return r;
  }
  return v;
}

nlohmann::json grid_json(const GridSpec& g) {
  return {{"x0", g.x0}, {"y0", g.y0}, {"cell", g.cell}, {"nx", g.nx}, {"ny", g.ny}};
}

void write_heights(std::ostream& out, const std::vector<double>& z) {
  std::vector<char> buf(std::size_t{1} << 16);
  for (std::size_t i = 0; i < z.size();) {  // O(cells)
    std::size_t n = 0;
    for (; i < z.size() && n + 8 <= buf.size(); ++i, n += 8) {
      const std::uint64_t v = to_le(std::bit_cast<std::uint64_t>(z[i]));
      std::memcpy(buf.data() + n, &v, 8);
    }
    out.write(buf.data(), static_cast<std::streamsize>(n));
  }
}

/// A grid of the header (`what`: "" for the z-map's own, "surround." for the surround's), checked
/// (GridSpec::check, the memory limit) before anything is allocated.
GridSpec parse_grid(const nlohmann::json& h, const std::string& what, const std::string& where, std::size_t max_bytes) {
  GridSpec g;
  for (const char* k : {"x0", "y0", "cell"})
    if (!h.contains(k) || !h[k].is_number())
      throw file_error(where, "line 2: bad header: \"" + what + k + "\" must be a number");
  for (const char* k : {"nx", "ny"})
    if (!h.contains(k) || !h[k].is_number_unsigned())
      throw file_error(where, "line 2: bad header: \"" + what + k + "\" must be a whole number >= 0");
  g.x0 = h["x0"].get<double>();
  g.y0 = h["y0"].get<double>();
  g.cell = h["cell"].get<double>();
  g.nx = h["nx"].get<std::size_t>();
  g.ny = h["ny"].get<std::size_t>();
  try {
    g.check();
  } catch (const Error& e) {
    throw file_error(where, "line 2: " + what + e.what());
  }
  if (g.nx > (std::size_t{1} << 40) / g.ny || ZMap::bytes_needed(g) > max_bytes)
    throw file_error(where, "a " + std::to_string(g.nx) + " × " + std::to_string(g.ny) + " " + what +
                                "z-map is above the " + std::to_string(max_bytes >> 20) + " MiB limit");
  return g;
}

std::vector<double> read_heights(std::ifstream& in, const GridSpec& g, const std::string& what,
                                 const std::string& where) {
  std::vector<double> z(g.cells());
  std::vector<char> buf(std::size_t{1} << 16);
  for (std::size_t i = 0; i < z.size();) {  // O(cells)
    const std::size_t n = std::min(buf.size() / 8, z.size() - i);
    if (!in.read(buf.data(), static_cast<std::streamsize>(n * 8))) throw file_error(where, "truncated heights");
    for (std::size_t k = 0; k < n; ++k, ++i) {
      std::uint64_t v = 0;
      std::memcpy(&v, buf.data() + 8 * k, 8);
      z[i] = std::bit_cast<double>(to_le(v));
      if (!std::isfinite(z[i]))
        throw file_error(where, what + "height " + std::to_string(i) + " (row " + std::to_string(i / g.nx) +
                                    ", column " + std::to_string(i % g.nx) + ") is not finite");
    }
  }
  return z;
}

}  // namespace

void write_zmap(const fs::path& path, const ZMap& zmap, const ZMap* surround) {
  nlohmann::json h = grid_json(zmap.spec());
  h["heights"] = "float64le";
  if (surround != nullptr) h["surround"] = grid_json(surround->spec());
  AtomicOFStream out(path, true);
  out.stream() << (surround != nullptr ? kMagicSurround : kMagic) << "\n" << h.dump() << "\n";
  write_heights(out.stream(), zmap.heights());
  if (surround != nullptr) write_heights(out.stream(), surround->heights());
  out.commit();
}

SavedStock read_saved_stock(const fs::path& path, std::size_t max_bytes) {
  const std::string where = path.string();
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw file_error(where, "not a regular file (expected a .zmap file)");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw file_error(where, "cannot read its size");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw file_error(where, "cannot open");
  std::string magic, header;
  std::getline(in, magic);
  if (magic != kMagic && magic != kMagicSurround)
    throw file_error(
        where, "line 1: expected \"" + std::string(kMagic) + "\" or \"" + kMagicSurround + "\" (not a millnet z-map)");
  // The header line, bounded (a file without a newline must not be read whole into memory).
  for (char c = 0; in.get(c) && c != '\n';) {
    header.push_back(c);
    if (header.size() > kMaxHeaderBytes) throw file_error(where, "line 2: header longer than 4096 bytes");
  }
  if (!in) throw file_error(where, "line 2: missing the header line");
  nlohmann::json h;
  try {
    h = nlohmann::json::parse(header);
  } catch (const std::exception& e) {
    throw file_error(where, "line 2: bad header: " + json_error_text(e.what()));
  }
  if (!h.is_object()) throw file_error(where, "line 2: bad header: not an object");
  if (!h.contains("heights") || !h["heights"].is_string() || h["heights"].get<std::string>() != "float64le")
    throw file_error(where, "line 2: bad header: \"heights\" must be \"float64le\"");
  const GridSpec g = parse_grid(h, "", where, max_bytes);
  const bool has_surround = magic == kMagicSurround;
  if (has_surround != h.contains("surround"))
    throw file_error(where, has_surround ? "line 2: bad header: \"surround\" missing (the file says millnet-zmap 2)"
                                         : "line 2: bad header: \"surround\" in a millnet-zmap 1 file");
  std::optional<GridSpec> sg;
  if (has_surround) {
    if (!h["surround"].is_object()) throw file_error(where, "line 2: bad header: \"surround\" must be an object");
    sg = parse_grid(h["surround"], "surround.", where, max_bytes);
  }
  const auto at = static_cast<std::uintmax_t>(in.tellg());
  const std::uintmax_t want = (static_cast<std::uintmax_t>(g.cells()) + (sg ? sg->cells() : 0)) * 8;
  if (size - at != want)
    throw file_error(where, "expected " + std::to_string(want) + " bytes of heights after the header, found " +
                                std::to_string(size - at));
  SavedStock s{ZMap::from_heights(g, read_heights(in, g, "", where), 0, 0, max_bytes), std::nullopt};
  if (sg) s.surround = ZMap::from_heights(*sg, read_heights(in, *sg, "surround ", where), 0, 0, max_bytes);
  return s;
}

ZMap read_zmap(const fs::path& path, std::size_t max_bytes) { return read_saved_stock(path, max_bytes).zmap; }

}  // namespace millnet::simulate::io
