#pragma once
// SHA-256 (FIPS 180-4) of bytes: the checksums a job's programs are listed with on the setup sheet
// and in <stem>.job.json, so that the operator can check a file at the machine with `sha256sum`.
#include <string>
#include <string_view>

namespace millnet {

/// The 64 lowercase hex digits of SHA-256(bytes). O(bytes).
[[nodiscard]] std::string sha256_hex(std::string_view bytes);

}  // namespace millnet
