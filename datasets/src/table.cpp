#include "millnet/datasets/table.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"
#include "millnet/datasets/hash.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <set>
#include <string_view>

namespace millnet::datasets {
namespace fs = std::filesystem;

namespace {

constexpr const char* kFixedColumns[] = {"id", "source", "label", "axis", "angle", "flip"};
constexpr std::size_t kFixed = 6;

std::string csv_text_field(const std::string& s, const char* what) {
  if (s.find_first_of("\r\n") != std::string::npos)
    throw Error(std::string("table: ") + what + " '" + s + "' contains a line break");
  if (s.find_first_of(",\"") == std::string::npos) return s;
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

// Splits one CSV line (RFC 4180 quoting, no embedded line breaks). O(|line|).
std::vector<std::string> split_csv(std::string_view line, const std::string& file, long lineno) {
  std::vector<std::string> fields;
  std::string cur;
  std::size_t i = 0;
  bool field_start = true;
  while (true) {
    if (field_start && i < line.size() && line[i] == '"') {
      ++i;
      while (true) {
        if (i >= line.size()) throw line_error(file, lineno, "unterminated quoted field");
        if (line[i] == '"') {
          if (i + 1 < line.size() && line[i + 1] == '"') {
            cur += '"';
            i += 2;
            continue;
          }
          ++i;
          break;
        }
        cur += line[i++];
      }
      if (i < line.size() && line[i] != ',')
        throw line_error(file, lineno, "text after a closing quote in field " + std::to_string(fields.size() + 1));
    }
    if (i >= line.size()) {
      fields.push_back(std::move(cur));
      return fields;
    }
    if (line[i] == ',') {
      fields.push_back(std::move(cur));
      cur.clear();
      field_start = true;
      ++i;
      continue;
    }
    cur += line[i++];
    field_start = false;
  }
}

double parse_number(const std::string& s, const std::string& column, const std::string& file, long lineno) {
  double v = 0;
  const char* first = s.data();
  const char* last = s.data() + s.size();
  if (!s.empty() && *first == '+') ++first;  // from_chars refuses a leading '+', spreadsheets write it
  const auto r = std::from_chars(first, last, v);
  if (s.empty() || r.ec == std::errc::invalid_argument || r.ptr != last)
    throw line_error(file, lineno, "column '" + column + "': '" + s + "' is not a number");
  if (r.ec == std::errc::result_out_of_range)
    throw line_error(file, lineno, "column '" + column + "': '" + s + "' is out of the range of a double");
  if (!std::isfinite(v)) throw line_error(file, lineno, "column '" + column + "': '" + s + "' is not a finite number");
  return v;
}

}  // namespace

StrategyNames default_strategy_names() {
  return {"profile + Z finishing, slope mode",
          "3D/profile finishing",
          "profile finishing, scallop-height mode",
          "Z-level finishing",
          "profile finishing, equidistant, constant in-feed",
          "spare 6",
          "spare 7",
          "spare 8"};
}

std::array<double, kStrategySlots> one_hot(int label) {
  if (label < 0 || label > static_cast<int>(kStrategySlots))
    throw Error("label " + std::to_string(label) + " outside 0..8 (0 = unknown)");
  std::array<double, kStrategySlots> out{};
  if (label > 0) out[static_cast<std::size_t>(label - 1)] = 1.0;
  return out;
}

Eigen::MatrixXd Table::inputs_matrix(int wall_share_copies) const {
  const auto m = inputs_per_row();
  const auto c = static_cast<Eigen::Index>(std::max(0, wall_share_copies));
  Eigen::MatrixXd X(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(m) + c);
  for (std::size_t i = 0; i < rows.size(); ++i) {  // O(N·(n² + c))
    MILLNET_ASSERT(rows[i].inputs.size() == m, "row input count");
    for (std::size_t k = 0; k < m; ++k)
      X(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = rows[i].inputs[k];
    X.block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(m), 1, c).setConstant(rows[i].wall_share);
  }
  return X;
}

Eigen::MatrixXd Table::outputs_matrix() const {
  Eigen::MatrixXd Y(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(kStrategySlots));
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t k = 0; k < kStrategySlots; ++k)
      Y(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = rows[i].outputs[k];
  return Y;
}

std::vector<std::string> Table::row_sources() const {
  std::vector<std::string> s;
  s.reserve(rows.size());
  for (const auto& r : rows) s.push_back(r.source);
  return s;
}

std::vector<std::string> column_names(int grid_n, bool with_aspect, bool with_wall_share) {
  if (grid_n < 1) throw Error("table: grid n must be ≥ 1, got " + std::to_string(grid_n));
  std::vector<std::string> cols(std::begin(kFixedColumns), std::end(kFixedColumns));
  for (int r = 1; r <= grid_n; ++r)
    for (int c = 1; c <= grid_n; ++c) cols.push_back("in_" + std::to_string(r) + "_" + std::to_string(c));
  for (std::size_t k = 1; k <= kStrategySlots; ++k) cols.push_back("out_" + std::to_string(k));
  if (with_aspect) cols.emplace_back("aspect");
  if (with_wall_share) cols.emplace_back("wall_share");
  return cols;
}

std::string csv_header(int grid_n, bool with_aspect, bool with_wall_share) {
  const auto cols = column_names(grid_n, with_aspect, with_wall_share);
  std::string out;
  for (std::size_t k = 0; k < cols.size(); ++k) {
    if (k) out += ',';
    out += cols[k];
  }
  out += '\n';
  return out;
}

void append_csv_row(std::string& out, const Row& r, int grid_n, bool with_aspect, bool with_wall_share) {
  const std::size_t m = static_cast<std::size_t>(grid_n) * static_cast<std::size_t>(grid_n);
  if (r.inputs.size() != m)
    throw Error("table: row '" + r.id + "' has " + std::to_string(r.inputs.size()) + " inputs, expected " +
                std::to_string(m));
  if (r.label < 0 || r.label > static_cast<int>(kStrategySlots))
    throw Error("table: row '" + r.id + "' has label " + std::to_string(r.label) + " outside 0..8");
  out += csv_text_field(r.id, "id");
  out += ',';
  out += csv_text_field(r.source, "source");
  out += ',';
  out += std::to_string(r.label);
  out += ',';
  out += augment::to_char(r.axis);
  out += ',';
  out += format_double(r.angle_deg);
  out += r.flip ? ",1" : ",0";
  for (const double v : r.inputs) {  // O(n²)
    out += ',';
    out += format_double(v);
  }
  for (const double v : r.outputs) {
    out += ',';
    out += format_double(v);
  }
  if (with_aspect) {
    out += ',';
    out += format_double(r.aspect);
  }
  if (with_wall_share) {
    out += ',';
    out += format_double(r.wall_share);
  }
  out += '\n';
}

std::string table_csv(const Table& table) {
  std::string out = csv_header(table.grid_n, table.has_aspect, table.has_wall_share);
  out.reserve((table.rows.size() + 1) * (table.inputs_per_row() + 16) * 8);
  std::set<std::string> ids;
  for (const Row& r : table.rows) {  // O(N·n²)
    if (!ids.insert(r.id).second) throw Error("table: duplicate row id '" + r.id + "'");
    append_csv_row(out, r, table.grid_n, table.has_aspect, table.has_wall_share);
  }
  return out;
}

namespace {

/// What the header line says about the columns: their names, count and the grid's cell count m.
struct Header {
  std::vector<std::string> names;
  std::size_t n_cols = 0, m = 0;
};

/// Checks the header line (line 1: the fixed columns, an n×n grid of in_* columns, the outputs,
/// maybe aspect, maybe wall_share) and sets t.grid_n, t.has_aspect and t.has_wall_share. Throws naming the
/// first wrong column.
Header read_header(std::vector<std::string> fields, const std::string& file, Table& t) {
  Header h;
  std::vector<std::string>& header = h.names;
  header = std::move(fields);
  for (std::size_t k = 0; k < kFixed; ++k) {
    if (k >= header.size()) throw line_error(file, 1, std::string("header: missing column '") + kFixedColumns[k] + "'");
    if (header[k] != kFixedColumns[k])
      throw line_error(
          file, 1,
          "header: column " + std::to_string(k + 1) + " is '" + header[k] + "', expected '" + kFixedColumns[k] + "'");
  }
  std::size_t k = kFixed;
  while (k < header.size() && header[k].rfind("in_", 0) == 0) ++k;
  h.m = k - kFixed;
  const auto n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(h.m))));
  if (h.m == 0) throw line_error(file, 1, "header: missing column 'in_1_1'");
  if (static_cast<std::size_t>(n) * static_cast<std::size_t>(n) != h.m) {
    // Not a square grid: name the first in_* column that breaks the n×n pattern.
    const bool missing = static_cast<std::size_t>(n) * static_cast<std::size_t>(n) > h.m;
    const auto expect = column_names(n, false);
    for (std::size_t c = kFixed; c < k; ++c)
      if (c >= expect.size() - kStrategySlots || header[c] != expect[c])
        throw line_error(
            file, 1,
            missing ? "header: missing column '" + expect[c] + "'" : "header: unexpected column '" + header[c] + "'");
    throw line_error(file, 1, "header: missing column '" + expect[k] + "'");
  }
  t.grid_n = n;
  const bool wall = header.back() == "wall_share";
  const bool aspect = header.size() >= (wall ? 2U : 1U) && header[header.size() - (wall ? 2 : 1)] == "aspect";
  t.has_aspect = aspect;
  t.has_wall_share = wall;
  const auto expect = column_names(n, aspect, wall);
  for (std::size_t c = 0; c < expect.size(); ++c) {
    if (c >= header.size()) throw line_error(file, 1, "header: missing column '" + expect[c] + "'");
    if (header[c] != expect[c])
      throw line_error(
          file, 1, "header: column " + std::to_string(c + 1) + " is '" + header[c] + "', expected '" + expect[c] + "'");
  }
  if (header.size() > expect.size())
    throw line_error(file, 1, "header: unexpected column '" + header[expect.size()] + "'");
  h.n_cols = header.size();
  return h;
}

int parse_label(const std::string& s, const std::string& file, long lineno) {
  int label = -1;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), label);
  if (s.empty() || res.ec != std::errc() || res.ptr != s.data() + s.size() || label < 0 ||
      label > static_cast<int>(kStrategySlots))
    throw line_error(file, lineno, "column 'label': '" + s + "' is not an integer in 0..8 (0 = unknown)");
  return label;
}

augment::Axis parse_axis(const std::string& s, const std::string& file, long lineno) {
  if (s == "x" || s == "X") return augment::Axis::X;
  if (s == "y" || s == "Y") return augment::Axis::Y;
  if (s == "z" || s == "Z") return augment::Axis::Z;
  throw line_error(file, lineno, "column 'axis': '" + s + "' is not x, y or z");
}

bool parse_flip(const std::string& s, const std::string& file, long lineno) {
  if (s == "0") return false;
  if (s == "1") return true;
  throw line_error(file, lineno, "column 'flip': '" + s + "' is not 0 or 1");
}

/// A labelled row whose outputs point elsewhere is a corrupted table, not a soft target.
void check_label_agrees(const Row& r, const std::string& file, long lineno) {
  if (r.label <= 0) return;
  std::size_t best = 0;
  for (std::size_t k = 1; k < kStrategySlots; ++k)
    if (r.outputs[k] > r.outputs[best]) best = k;
  if (best + 1 != static_cast<std::size_t>(r.label))
    throw line_error(file, lineno,
                     "column 'label': " + std::to_string(r.label) + " disagrees with the outputs (largest is out_" +
                         std::to_string(best + 1) + ")");
}

/// One data line's row. id_line holds the line of every id read so far (duplicates are errors).
Row read_row(const std::vector<std::string>& fields, const Header& h, const Table& t, const std::string& file,
             long lineno, std::map<std::string, long>& id_line) {
  if (fields.size() != h.n_cols)
    throw line_error(
        file, lineno,
        std::to_string(fields.size()) + " fields, expected " + std::to_string(h.n_cols) + " (one per header column)");
  Row r;
  r.id = fields[0];
  r.source = fields[1];
  if (r.id.empty()) throw line_error(file, lineno, "column 'id': empty");
  if (r.source.empty()) throw line_error(file, lineno, "column 'source': empty");
  if (auto [it, fresh] = id_line.emplace(r.id, lineno); !fresh)
    throw line_error(file, lineno,
                     "column 'id': duplicate id '" + r.id + "' (first on line " + std::to_string(it->second) + ")");
  r.label = parse_label(fields[2], file, lineno);
  r.axis = parse_axis(fields[3], file, lineno);
  r.angle_deg = parse_number(fields[4], "angle", file, lineno);
  r.flip = parse_flip(fields[5], file, lineno);
  r.inputs.resize(h.m);
  for (std::size_t k = 0; k < h.m; ++k)
    r.inputs[k] = parse_number(fields[kFixed + k], h.names[kFixed + k], file, lineno);
  for (std::size_t k = 0; k < kStrategySlots; ++k)
    r.outputs[k] = parse_number(fields[kFixed + h.m + k], h.names[kFixed + h.m + k], file, lineno);
  std::size_t extra = kFixed + h.m + kStrategySlots;
  if (t.has_aspect) r.aspect = parse_number(fields[extra++], "aspect", file, lineno);
  if (t.has_wall_share) {
    r.wall_share = parse_number(fields[extra], "wall_share", file, lineno);
    if (!(r.wall_share >= 0 && r.wall_share <= 1))
      throw line_error(file, lineno, "column 'wall_share': " + fields[extra] + " is not a share in [0, 1]");
  }
  check_label_agrees(r, file, lineno);
  return r;
}

}  // namespace

Table read_table(const fs::path& csv_path) {
  const std::string file = csv_path.string();
  const std::string text = read_file(csv_path);  // throws naming the file
  Table t;
  std::size_t pos = 0;
  long lineno = 0;
  Header header;
  std::map<std::string, long> id_line;
  while (pos < text.size()) {  // O(file size)
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    std::string_view line(text.data() + pos, eol - pos);
    pos = eol + 1;
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (lineno == 1 && line.size() >= 3 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);  // UTF-8 BOM
    if (line.empty()) {
      if (pos >= text.size()) break;  // final newline
      throw line_error(file, lineno, "empty line");
    }
    auto fields = split_csv(line, file, lineno);
    if (lineno == 1)
      header = read_header(std::move(fields), file, t);
    else
      t.rows.push_back(read_row(fields, header, t, file, lineno, id_line));
  }
  if (header.names.empty()) throw file_error(file, "empty file, expected a header line");
  if (t.rows.empty()) throw file_error(file, "no rows after the header");
  return t;
}

}  // namespace millnet::datasets
