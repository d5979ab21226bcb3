#pragma once
// Minimal JSON text writing for files whose layout is written by hand (the dataset manifest and its
// recipe echo), so that modules need no JSON library. Only escaped strings and finite numbers.
#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>

namespace millnet {

inline std::string json_string(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {  // O(|s|)
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  out += '"';
  return out;
}

/// JSON has no NaN/inf: refuse rather than write an unreadable manifest.
inline std::string json_number(double v, std::string_view key) {
  if (!std::isfinite(v)) throw Error("manifest: value of '" + std::string(key) + "' is not finite");
  return format_double(v);
}

}  // namespace millnet
