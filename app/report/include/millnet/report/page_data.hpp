#pragma once
// The preview page's embedded data (page_data.cpp): plain JSON up to kPlainDataBytes, gzip + base64
// above it, so that a finishing page with its path, G-code lines and machined surface stays within
// PreviewLimits::max_page_bytes (issue 37 §3: 8–18 MB pages became ≤ 5 MB).
#include <cstddef>
#include <string>
#include <string_view>

namespace millnet::report {

/// Data up to this many bytes stays readable JSON in the page's source; larger data is packed.
inline constexpr std::size_t kPlainDataBytes = std::size_t{1} << 20;

/// RFC 4648 base64 with padding (the packed data, the setup sheet's PNG data URIs).
[[nodiscard]] std::string base64(std::string_view bytes);

/// The data's script element: `<script type="application/json" id="millnet-data">…</script>` or
/// `<script type="application/gzip+base64" id="millnet-data-gz">…</script>` (gzip level 6, mtime 0:
/// the same bytes for the same data).
[[nodiscard]] std::string embed_page_data(const std::string& json);

/// The data JSON of a page written by preview_html, plain or packed. Throws millnet::Error when the
/// page has none or its packed data is damaged.
[[nodiscard]] std::string page_data_json(const std::string& html);

}  // namespace millnet::report
