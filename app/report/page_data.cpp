// The preview page's embedded data as bytes (preview.hpp): plain JSON while it is small, gzip +
// base64 above kPlainDataBytes (the page inflates it with the browser's DecompressionStream). The
// one owner of that format: preview_html writes it through embed_page_data, tests and tools read it
// back through page_data_json.
#include "millnet/report/page_data.hpp"

#include "millnet/core/error.hpp"

#include <zlib.h>

#include <array>
#include <cstdint>
#include <optional>

namespace millnet::report {

namespace {

constexpr std::string_view kPlainOpen = "<script type=\"application/json\" id=\"millnet-data\">";
constexpr std::string_view kPackedOpen = "<script type=\"application/gzip+base64\" id=\"millnet-data-gz\">";
constexpr std::string_view kClose = "</script>";
constexpr std::string_view kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// gzip (RFC 1952) at zlib's level 6 with no name and mtime 0: the same bytes for the same input.
std::string gzip(std::string_view in) {
  z_stream z{};
  if (deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw Error("preview: zlib init failed");
  std::string out(deflateBound(&z, static_cast<uLong>(in.size())), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  z.avail_in = static_cast<uInt>(in.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  if (rc != Z_STREAM_END) throw Error("preview: zlib could not compress the page's data");
  return out;
}

std::string gunzip(std::string_view in) {
  z_stream z{};
  if (inflateInit2(&z, 15 + 16) != Z_OK) throw Error("preview: zlib init failed");
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  z.avail_in = static_cast<uInt>(in.size());
  std::string out;
  std::array<char, 1 << 16> buf{};
  int rc = Z_OK;
  while (rc == Z_OK) {  // O(output)
    z.next_out = reinterpret_cast<Bytef*>(buf.data());
    z.avail_out = static_cast<uInt>(buf.size());
    rc = inflate(&z, Z_NO_FLUSH);
    out.append(buf.data(), buf.size() - z.avail_out);
  }
  inflateEnd(&z);
  if (rc != Z_STREAM_END) throw Error("preview: the page's packed data is not a whole gzip stream");
  return out;
}

std::string unbase64(std::string_view in) {
  std::array<int, 256> value{};
  value.fill(-1);
  for (std::size_t k = 0; k < kAlphabet.size(); ++k)
    value[static_cast<unsigned char>(kAlphabet[k])] = static_cast<int>(k);
  std::string out;
  std::uint32_t acc = 0;
  int bits = 0;
  for (const char c : in) {  // O(bytes); padding and white space end or are skipped
    const int v = value[static_cast<unsigned char>(c)];
    if (v < 0) continue;
    acc = acc << 6 | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>(acc >> bits & 0xff);
    }
  }
  return out;
}

}  // namespace

std::string base64(std::string_view in) {
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < in.size(); i += 3) {  // O(bytes)
    std::uint32_t v = static_cast<std::uint8_t>(in[i]) << 16;
    if (i + 1 < in.size()) v |= static_cast<std::uint32_t>(static_cast<std::uint8_t>(in[i + 1])) << 8;
    if (i + 2 < in.size()) v |= static_cast<std::uint8_t>(in[i + 2]);
    out += kAlphabet[v >> 18 & 63];
    out += kAlphabet[v >> 12 & 63];
    out += i + 1 < in.size() ? kAlphabet[v >> 6 & 63] : '=';
    out += i + 2 < in.size() ? kAlphabet[v & 63] : '=';
  }
  return out;
}

std::string embed_page_data(const std::string& json) {
  if (json.size() <= kPlainDataBytes) return std::string(kPlainOpen) + json + std::string(kClose);
  return std::string(kPackedOpen) + base64(gzip(json)) + std::string(kClose);
}

std::string page_data_json(const std::string& html) {
  const auto between = [&](std::string_view open) -> std::optional<std::string_view> {
    const std::size_t a = html.find(open);
    if (a == std::string::npos) return std::nullopt;
    const std::size_t b = html.find(kClose, a + open.size());
    if (b == std::string::npos) return std::nullopt;
    return std::string_view(html).substr(a + open.size(), b - a - open.size());
  };
  if (const auto plain = between(kPlainOpen)) return std::string(*plain);
  if (const auto packed = between(kPackedOpen)) return gunzip(unbase64(*packed));
  throw Error("preview: the page holds no millnet data");
}

}  // namespace millnet::report
