#include "millnet/core/budget.hpp"

#include "millnet/core/error.hpp"

#include <cmath>
#include <cstdio>

namespace millnet {

std::string format_count(double n, int decimals) {
  if (std::isnan(n)) return "NaN";
  if (std::isinf(n)) return "more than 1e308";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*e", decimals, n);
  // "1.0e+10" → "1.0e10", "2.0e-03" → "2.0e-3"
  std::string s(buf), out;
  const auto e = s.find('e');
  if (e == std::string::npos) return s;
  out = s.substr(0, e + 1);
  std::size_t k = e + 1;
  if (s[k] == '-') out += '-';
  if (s[k] == '+' || s[k] == '-') ++k;
  while (k + 1 < s.size() && s[k] == '0') ++k;
  return out + s.substr(k);
}

std::string format_size(double v) {
  char buf[64];
  const double a = std::abs(v);
  if (a >= 1e6 && a < 1e12)
    std::snprintf(buf, sizeof buf, "%.0f", v);
  else if (a >= 1e-7 && a < 1e-3)
    std::snprintf(buf, sizeof buf, "%.12f", v);
  else
    std::snprintf(buf, sizeof buf, "%.6g", v);
  std::string s(buf);
  if (s.find('.') != std::string::npos && s.find('e') == std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  return s;
}

std::string format_bytes(double bytes) {
  if (std::isnan(bytes)) return "NaN bytes";
  if (std::isinf(bytes)) return "more than 1e308 bytes";
  static const char* const units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  int u = 0;
  while (bytes >= 1000 && u < 6) {
    bytes /= 1000;
    ++u;
  }
  char buf[32];
  if (u == 0 || bytes >= 10)
    std::snprintf(buf, sizeof buf, "%.0f %s", bytes, units[u]);
  else
    std::snprintf(buf, sizeof buf, "%.1f %s", bytes, units[u]);
  return buf;
}

void check_work(const WorkEstimate& est, const WorkLimits& limits) {
  const double limit = est.pairs ? limits.max_pairs : limits.max_work;
  const bool over_count = !est.memory_only && !(est.count <= limit);
  // As many digits as it takes for an estimate just over the limit not to print as the limit.
  int dec = 1;
  while (over_count && dec < 15 && format_count(est.count, dec) == format_count(limit, dec)) ++dec;
  const std::string head =
      est.cause + " makes " + format_count(est.count, dec) + " " + est.unit + " (≈ " + format_bytes(est.bytes) + ")";
  if (over_count)
    throw Error(head + "; the limit is " + format_count(limit, dec) +
                (est.pairs ? " (--max-pairs, /limits/max_pairs)" : " (--max-work, /limits/max_work)"));
  if (!(est.bytes <= limits.max_memory_bytes))
    throw Error(head + "; the memory limit is " + format_size(limits.max_memory_bytes / (1024.0 * 1024.0)) +
                " MiB (--max-memory-mb, /limits/max_memory_mb)");
}

}  // namespace millnet
