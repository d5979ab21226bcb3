// Bounds, numbers, ids and notes shared by the tool-table readers.
#include "common.hpp"

#include "millnet/core/error.hpp"

#include <charconv>
#include <cmath>
#include <limits>

namespace millnet::tooling::io::detail {

void check_size(std::size_t bytes, const std::string& source) {
  if (bytes > kMaxToolFileBytes)
    throw file_error(source, std::to_string(bytes) + " bytes; the limit for a tool table is " +
                                 std::to_string(kMaxToolFileBytes >> 20) + " MiB");
}

void check_count(std::size_t count, const std::string& source) {
  if (count > kMaxImportedTools)
    throw file_error(source, "more than " + std::to_string(kMaxImportedTools) + " tools; the limit of one import is " +
                                 std::to_string(kMaxImportedTools));
}

namespace {
/// `s` without one leading '+' (from_chars reads no '+'); false for "", "+", "++1", "+-1".
bool unsigned_plus(std::string_view& s) {
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
    if (!s.empty() && (s.front() == '+' || s.front() == '-')) return false;
  }
  return !s.empty();
}
}  // namespace

std::optional<double> parse_real(std::string_view s) {
  if (!unsigned_plus(s)) return std::nullopt;
  // from_chars reads "nan" and "inf" too: only digits, sign, point and exponent are numbers here.
  for (const char c : s)
    if (!((c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E')) return std::nullopt;
  double v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<int> parse_int(std::string_view s) {
  if (!unsigned_plus(s)) return std::nullopt;
  int v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

double to_mm(double v, double mm_per_unit) { return mm_per_unit == 1 ? v : std::round(v * mm_per_unit * 1e6) / 1e6; }

std::string shown(std::string_view s) {
  std::string out;
  for (const char c : s.substr(0, 60)) out += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c;
  if (s.size() > 60) out += "...";
  return out;
}

std::string in_quotes(std::string_view s) { return "'" + shown(s) + "'"; }

std::string slug(std::string_view name) {
  std::string out;
  bool dash = false;
  for (const char ch : name) {
    const auto c = static_cast<unsigned char>(ch);
    const bool keep = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || (c >= 'A' && c <= 'Z');
    if (keep) {
      if (dash && !out.empty()) out += '-';
      dash = false;
      out += static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    } else {
      dash = true;
    }
    if (out.size() >= 48) break;
  }
  while (!out.empty() && (out.back() == '-' || out.back() == '.')) out.pop_back();
  while (!out.empty() && out.front() == '.') out.erase(out.begin());
  return out;
}

std::string IdMaker::make(const std::string& base, const std::string& fallback) {
  const std::string b = base.empty() ? fallback : base;
  std::string id = b;
  for (int k = 2; used_.count(id) > 0; ++k) id = b + "-" + std::to_string(k);
  used_.insert(id);
  return id;
}

void Notes::add(const std::string& what, const std::string& who) {
  auto [it, fresh] = who_.try_emplace(what);
  if (fresh) order_.push_back(what);
  it->second.push_back(who);
}

void Notes::line(const std::string& text) { single_.push_back(text); }

std::vector<std::string> Notes::lines(const std::string& source) const {
  std::vector<std::string> out;
  for (const std::string& s : single_) out.push_back(source + ": " + s);
  for (const std::string& what : order_) {
    const std::vector<std::string>& w = who_.at(what);
    std::string s = source + ": " + what + ": ";
    for (std::size_t i = 0; i < w.size() && i < 8; ++i) s += (i ? ", " : "") + w[i];
    if (w.size() > 8) s += ", ... (" + std::to_string(w.size()) + " tools)";
    out.push_back(s);
  }
  return out;
}

std::string who(const Tool& t) { return t.number > 0 ? "T" + std::to_string(t.number) + " " + t.id : t.id; }

}  // namespace millnet::tooling::io::detail
