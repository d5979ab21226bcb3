// millnet's own PLY and OFF readers (see ply_off.hpp for why they are not assimp's).
#include "ply_off.hpp"

#include "millnet/core/error.hpp"

#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <string_view>
#include <vector>

namespace millnet::ingest::detail {

namespace {

constexpr std::int64_t kMaxVertices = std::numeric_limits<std::int32_t>::max();  // Faces are int32

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

/// Whitespace-separated words of one line.
std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> w;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t b = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > b) w.push_back(line.substr(b, i - b));
  }
  return w;
}

std::string shorten(std::string_view s, std::size_t n = 40) {
  std::string out(s.substr(0, n));
  for (char& c : out)
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  return s.size() > n ? out + "…" : out;
}

std::optional<std::int64_t> to_int(std::string_view s) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  std::int64_t v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

std::optional<double> to_double(std::string_view s) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  double v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

/// Appends the fan (v0, vi, vi+1) of one polygon.
void fan(const std::vector<std::int64_t>& poly, std::vector<std::int32_t>& F) {
  for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
    F.push_back(static_cast<std::int32_t>(poly[0]));
    F.push_back(static_cast<std::int32_t>(poly[i]));
    F.push_back(static_cast<std::int32_t>(poly[i + 1]));
  }
}

Mesh to_mesh(const std::vector<double>& V, const std::vector<std::int32_t>& F) {
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(V.size() / 3), 3);
  if (!V.empty()) std::memcpy(m.V.data(), V.data(), V.size() * sizeof(double));  // both row-major
  m.F.resize(static_cast<Eigen::Index>(F.size() / 3), 3);
  if (!F.empty()) std::memcpy(m.F.data(), F.data(), F.size() * sizeof(std::int32_t));
  return m;
}

// ---------------------------------------------------------------- PLY

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };

std::optional<Type> ply_type(std::string_view s) {
  if (s == "char" || s == "int8") return Type::i8;
  if (s == "uchar" || s == "uint8") return Type::u8;
  if (s == "short" || s == "int16") return Type::i16;
  if (s == "ushort" || s == "uint16") return Type::u16;
  if (s == "int" || s == "int32") return Type::i32;
  if (s == "uint" || s == "uint32") return Type::u32;
  if (s == "float" || s == "float32") return Type::f32;
  if (s == "double" || s == "float64") return Type::f64;
  return std::nullopt;
}

std::size_t type_size(Type t) {
  switch (t) {
    case Type::i8:
    case Type::u8: return 1;
    case Type::i16:
    case Type::u16: return 2;
    case Type::i32:
    case Type::u32:
    case Type::f32: return 4;
    case Type::f64: return 8;
  }
  return 8;
}

bool is_integer(Type t) { return t != Type::f32 && t != Type::f64; }

struct Property {
  std::string name;
  Type type = Type::f32;  ///< the value's (or a list item's) type
  bool list = false;
  Type count_type = Type::u8;  ///< lists only
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
  long line = 0;
};

enum class Format { ascii, binary_le, binary_be };

struct Header {
  Format format = Format::ascii;
  std::vector<Element> elements;
  std::size_t body = 0;  ///< byte offset of the first byte after end_header's line
  long body_line = 0;    ///< 1-based line of the body's first byte (ASCII)
};

Header parse_ply_header(const std::string& bytes, const std::string& name) {
  Header h;
  std::size_t pos = 0;
  long line_no = 0;
  bool ended = false, have_format = false;
  while (pos < bytes.size()) {
    if (pos > kMaxPlyHeaderBytes)
      throw file_error(
          name, "PLY header has no end_header line in its first " + std::to_string(kMaxPlyHeaderBytes) + " bytes");
    std::size_t end = bytes.find('\n', pos);
    const bool last = end == std::string::npos;
    if (last) end = bytes.size();
    if (end - pos > kMaxPlyHeaderBytes)
      throw file_error(
          name, "PLY header has no end_header line in its first " + std::to_string(kMaxPlyHeaderBytes) + " bytes");
    const std::string_view line(bytes.data() + pos, end - pos);
    pos = last ? end : end + 1;
    ++line_no;
    const auto w = words(line);
    if (line_no == 1) {
      if (w.size() != 1 || w[0] != "ply")
        throw line_error(name, 1, "not a PLY file (expected \"ply\" on the first line)");
      continue;
    }
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") {
      ended = true;
      break;
    }
    if (w[0] == "format") {
      if (w.size() != 3 || w[2] != "1.0")
        throw line_error(name, line_no, "expected \"format ascii|binary_little_endian|binary_big_endian 1.0\"");
      if (w[1] == "ascii")
        h.format = Format::ascii;
      else if (w[1] == "binary_little_endian")
        h.format = Format::binary_le;
      else if (w[1] == "binary_big_endian")
        h.format = Format::binary_be;
      else
        throw line_error(name, line_no, "unknown PLY format \"" + shorten(w[1]) + "\"");
      have_format = true;
    } else if (w[0] == "element") {
      if (w.size() != 3) throw line_error(name, line_no, "expected \"element <name> <count>\"");
      const auto n = to_int(w[2]);
      if (!n || *n < 0)
        throw line_error(name, line_no, "element count \"" + shorten(w[2]) + "\" is not a non-negative integer");
      h.elements.push_back(Element{std::string(w[1]), static_cast<std::uint64_t>(*n), {}, line_no});
    } else if (w[0] == "property") {
      if (h.elements.empty()) throw line_error(name, line_no, "property before any element");
      Property p;
      if (w.size() == 5 && w[1] == "list") {
        const auto ct = ply_type(w[2]), it = ply_type(w[3]);
        if (!ct || !it) throw line_error(name, line_no, "unknown property type in \"" + shorten(line, 80) + "\"");
        if (!is_integer(*ct)) throw line_error(name, line_no, "a list's count type must be an integer type");
        p = Property{std::string(w[4]), *it, true, *ct};
      } else if (w.size() == 3) {
        const auto t = ply_type(w[1]);
        if (!t) throw line_error(name, line_no, "unknown property type \"" + shorten(w[1]) + "\"");
        p = Property{std::string(w[2]), *t, false, Type::u8};
      } else {
        throw line_error(name, line_no,
                         "expected \"property <type> <name>\" or \"property list <count type> <type> <name>\"");
      }
      h.elements.back().props.push_back(std::move(p));
    } else {
      throw line_error(name, line_no, "unexpected header line \"" + shorten(line, 60) + "\"");
    }
  }
  if (!ended) throw file_error(name, "PLY header has no end_header line (the file ends first)");
  if (!have_format) throw file_error(name, "PLY header has no format line");
  h.body = pos;
  h.body_line = line_no + 1;
  return h;
}

/// Reads values of the body, ASCII or binary, and names where it is in every error.
class PlyBody {
public:
  PlyBody(const std::string& bytes, const std::string& name, const Header& h)
      : b_(bytes), name_(name), format_(h.format), pos_(h.body), line_(h.body_line) {}

  /// A value of type t as double (integers exactly up to 2^53).
  double value(Type t) {
    if (format_ == Format::ascii) {
      const std::string_view w = word();
      if (is_integer(t)) {
        const auto v = to_int(w);
        if (!v) throw error("expected an integer, got \"" + shorten(w) + "\"");
        return static_cast<double>(*v);
      }
      const auto v = to_double(w);
      if (!v) throw error("expected a number, got \"" + shorten(w) + "\"");
      return *v;
    }
    return binary(t);
  }

  /// An integer value (list counts, indices); floats are refused by the header check before.
  std::int64_t integer(Type t) {
    if (format_ == Format::ascii) {
      const std::string_view w = word();
      const auto v = to_int(w);
      if (!v) throw error("expected an integer, got \"" + shorten(w) + "\"");
      return *v;
    }
    return static_cast<std::int64_t>(binary(t));
  }

  /// Whether `n` more values of type t can still follow (each takes ≥ 2 bytes in ASCII, its size in binary).
  bool can_hold(std::uint64_t n, Type t) const {
    const std::size_t left = b_.size() - pos_;
    const std::uint64_t each = format_ == Format::ascii ? 2 : type_size(t);
    return n <= (left + 1) / each;
  }

  /// "<file>:<line>: what" (ASCII) or "<file>: byte <offset>: what" (binary), at the last value read.
  Error error(const std::string& what) const {
    if (format_ == Format::ascii) return line_error(name_, at_line_, what);
    return file_error(name_, "byte " + std::to_string(at_) + ": " + what);
  }

  void set_context(const std::string* context) { context_ = context; }

private:
  std::string_view word() {
    while (pos_ < b_.size() && is_space(b_[pos_])) {
      if (b_[pos_] == '\n') ++line_;
      ++pos_;
    }
    at_ = pos_;
    at_line_ = line_;
    if (pos_ >= b_.size()) throw error("the file ends inside " + *context_);
    const std::size_t start = pos_;
    while (pos_ < b_.size() && !is_space(b_[pos_])) ++pos_;
    return std::string_view(b_.data() + start, pos_ - start);
  }

  double binary(Type t) {
    const std::size_t n = type_size(t);
    at_ = pos_;
    if (b_.size() - pos_ < n) throw error("the file ends inside " + *context_);
    unsigned char raw[8];
    std::memcpy(raw, b_.data() + pos_, n);
    pos_ += n;
    if ((format_ == Format::binary_be) == (std::endian::native == std::endian::little))
      for (std::size_t i = 0; i < n / 2; ++i) std::swap(raw[i], raw[n - 1 - i]);
    switch (t) {
      case Type::i8: {
        std::int8_t v;
        std::memcpy(&v, raw, 1);
        return v;
      }
      case Type::u8: {
        std::uint8_t v;
        std::memcpy(&v, raw, 1);
        return v;
      }
      case Type::i16: {
        std::int16_t v;
        std::memcpy(&v, raw, 2);
        return v;
      }
      case Type::u16: {
        std::uint16_t v;
        std::memcpy(&v, raw, 2);
        return v;
      }
      case Type::i32: {
        std::int32_t v;
        std::memcpy(&v, raw, 4);
        return v;
      }
      case Type::u32: {
        std::uint32_t v;
        std::memcpy(&v, raw, 4);
        return v;
      }
      case Type::f32: {
        float v;
        std::memcpy(&v, raw, 4);
        return static_cast<double>(v);
      }
      case Type::f64: {
        double v;
        std::memcpy(&v, raw, 8);
        return v;
      }
    }
    return 0;
  }

  const std::string& b_;
  const std::string& name_;
  Format format_;
  std::size_t pos_;
  long line_;
  std::size_t at_ = 0;
  long at_line_ = 0;
  const std::string* context_ = nullptr;
};

bool is_index_list(const Property& p) { return p.list && (p.name == "vertex_indices" || p.name == "vertex_index"); }

}  // namespace

Mesh parse_ply(const std::string& bytes, const std::string& name) {
  const Header h = parse_ply_header(bytes, name);
  const bool ascii = h.format == Format::ascii;

  // Which element holds what; every count checked against the bytes left before anything is allocated.
  const Element* vertex = nullptr;
  const Element* face = nullptr;
  long double need = 0;  // least bytes the announced elements take
  for (const Element& e : h.elements) {
    std::uint64_t each = 0;
    for (const Property& p : e.props) {
      // a lower bound: a value takes ≥ 2 bytes in ASCII ("0 "), its size in binary; a list ≥ its count
      if (ascii)
        each += 2;
      else
        each += type_size(p.list ? p.count_type : p.type);
    }
    need += static_cast<long double>(e.count) * static_cast<long double>(each);
    if (e.name == "vertex") {
      if (vertex) throw line_error(name, e.line, "a second element \"vertex\"");
      vertex = &e;
    } else if (e.name == "face") {
      if (face) throw line_error(name, e.line, "a second element \"face\"");
      face = &e;
    }
  }
  if (!vertex) throw file_error(name, "PLY header has no element \"vertex\"");
  if (!face) throw file_error(name, "PLY header has no element \"face\" (a point set, expected a triangle mesh)");
  const std::size_t left = bytes.size() - h.body;
  if (need > static_cast<long double>(left) + 1)
    throw file_error(name, "the header announces " + std::to_string(vertex->count) + " vertices and " +
                               std::to_string(face->count) + " faces, more than the " + std::to_string(left) +
                               " bytes after the header can hold (truncated or a wrong count)");
  if (vertex->count > static_cast<std::uint64_t>(kMaxVertices))
    throw line_error(name, vertex->line, "more than 2^31 − 1 vertices");
  int axis_of[3] = {-1, -1, -1};
  for (std::size_t k = 0; k < vertex->props.size(); ++k) {
    const Property& p = vertex->props[k];
    const int axis = p.name == "x" ? 0 : p.name == "y" ? 1 : p.name == "z" ? 2 : -1;
    if (axis < 0) continue;
    if (p.list) throw line_error(name, vertex->line, "vertex property \"" + p.name + "\" is a list, expected a number");
    axis_of[axis] = static_cast<int>(k);
  }
  for (int a = 0; a < 3; ++a)
    if (axis_of[a] < 0)
      throw line_error(name, vertex->line, std::string("element \"vertex\" has no property \"") + "xyz"[a] + "\"");
  const Property* indices = nullptr;
  for (const Property& p : face->props)
    if (is_index_list(p)) indices = &p;
  if (!indices) throw line_error(name, face->line, "element \"face\" has no list property \"vertex_indices\"");
  if (!is_integer(indices->type))
    throw line_error(name, face->line, "\"" + indices->name + "\" holds non-integer values, expected vertex indices");

  const auto nv = static_cast<std::int64_t>(vertex->count);
  std::vector<double> V(static_cast<std::size_t>(vertex->count) * 3);
  std::vector<std::int32_t> F;  // grows with what the file holds, not with what its header claims
  std::vector<std::int64_t> poly;
  PlyBody in(bytes, name, h);
  std::string context;
  for (const Element& e : h.elements) {
    if (e.props.empty()) continue;  // nothing to read, whatever the count
    const bool is_vertex = &e == vertex, is_face = &e == face;
    for (std::uint64_t i = 0; i < e.count; ++i) {
      context = e.name + " " + std::to_string(i) + " of " + std::to_string(e.count);
      in.set_context(&context);
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const Property& p = e.props[k];
        if (!p.list) {
          const double v = in.value(p.type);
          if (is_vertex)
            for (int a = 0; a < 3; ++a)
              if (axis_of[a] == static_cast<int>(k)) V[3 * i + static_cast<std::size_t>(a)] = v;
          continue;
        }
        const std::int64_t n = in.integer(p.count_type);
        if (n < 0) throw in.error(context + ": list length " + std::to_string(n) + " is negative");
        if (!in.can_hold(static_cast<std::uint64_t>(n), p.type))
          throw in.error(context + ": list length " + std::to_string(n) + " is more than the rest of the file holds");
        if (is_face && &p == indices) {
          if (n < 3)
            throw in.error("face " + std::to_string(i) + " lists " + std::to_string(n) +
                           " vertices, expected at least 3");
          poly.resize(static_cast<std::size_t>(n));
          for (std::int64_t j = 0; j < n; ++j) {
            const std::int64_t v = in.integer(p.type);
            if (v < 0 || v >= nv)
              throw in.error("face " + std::to_string(i) + " refers to vertex " + std::to_string(v) + ", expected 0…" +
                             std::to_string(nv - 1));
            poly[static_cast<std::size_t>(j)] = v;
          }
          fan(poly, F);
        } else {
          for (std::int64_t j = 0; j < n; ++j) (void)in.value(p.type);
        }
      }
    }
  }
  return to_mesh(V, F);
}

// ---------------------------------------------------------------- OFF

namespace {

/// The meaningful lines of a text mesh file: blank lines, and with a comment character (OFF: '#')
/// the rest of a line after it, dropped.
class TextLines {
public:
  TextLines(const std::string& bytes, const std::string& name, char comment = '\0')
      : b_(bytes), name_(name), comment_(comment) {}

  /// The next non-empty line's words, or false (and no words) at the end of the file.
  bool next(std::vector<std::string_view>& w) {
    while (pos_ < b_.size()) {
      std::size_t end = b_.find('\n', pos_);
      if (end == std::string::npos) end = b_.size();
      std::string_view line(b_.data() + pos_, end - pos_);
      pos_ = end + 1;
      ++line_;
      if (comment_ != '\0')
        if (const auto c = line.find(comment_); c != std::string_view::npos) line = line.substr(0, c);
      w = words(line);
      if (!w.empty()) return true;
    }
    w.clear();
    return false;
  }
  long line() const { return line_; }
  std::size_t left() const { return pos_ >= b_.size() ? 0 : b_.size() - pos_; }
  Error error(const std::string& what) const { return line_error(name_, line_, what); }

private:
  const std::string& b_;
  const std::string& name_;
  char comment_;
  std::size_t pos_ = 0;
  long line_ = 0;
};

/// "OFF" with optional prefixes ST (texture), C (colour), N (normals); "4OFF"/"nOFF" are not 3D.
bool off_keyword(std::string_view w) {
  if (w.size() < 3 || w.substr(w.size() - 3) != "OFF") return false;
  w.remove_suffix(3);
  if (w.substr(0, 2) == "ST") w.remove_prefix(2);
  if (!w.empty() && w[0] == 'C') w.remove_prefix(1);
  if (!w.empty() && w[0] == 'N') w.remove_prefix(1);
  return w.empty();
}

}  // namespace

Mesh parse_off(const std::string& bytes, const std::string& name) {
  TextLines in(bytes, name, '#');
  std::vector<std::string_view> w;
  if (!in.next(w)) throw file_error(name, "empty OFF file");
  std::size_t first = 0;  // where the counts start on this line
  if (w[0].find("OFF") != std::string_view::npos) {
    if (!off_keyword(w[0]))
      throw in.error("\"" + shorten(w[0]) + "\" is not a 3D OFF keyword (expected OFF, COFF, NOFF, CNOFF or STOFF)");
    if (w.size() > 1 && w[1] == "BINARY") throw in.error("binary OFF is not supported (write it as text)");
    first = 1;
    if (w.size() == 1) {  // the counts are on the next line
      if (!in.next(w)) throw file_error(name, "the file ends before the counts line \"#vertices #faces #edges\"");
      first = 0;
    }
  }
  if (w.size() < first + 2) throw in.error("expected the counts \"#vertices #faces [#edges]\"");
  const auto nv = to_int(w[first]), nf = to_int(w[first + 1]);
  if (!nv || !nf || *nv < 0 || *nf < 0)
    throw in.error("expected the counts \"#vertices #faces [#edges]\" as non-negative integers, got \"" +
                   shorten(w[first]) + " " + shorten(w[first + 1]) + "\"");
  // The smallest vertex line is "0 0 0\n" (6 bytes), the smallest face line 2 bytes.
  const long double need = static_cast<long double>(*nv) * 6 + static_cast<long double>(*nf) * 2;
  if (need > static_cast<long double>(in.left()) + 1)
    throw in.error("the counts announce " + std::to_string(*nv) + " vertices and " + std::to_string(*nf) +
                   " faces, more than the " + std::to_string(in.left()) +
                   " bytes after this line can hold (truncated or a wrong count)");
  if (*nv > kMaxVertices) throw in.error("more than 2^31 − 1 vertices");
  std::vector<double> V(static_cast<std::size_t>(*nv) * 3);
  for (std::int64_t i = 0; i < *nv; ++i) {
    if (!in.next(w))
      throw file_error(name, "the file ends after " + std::to_string(i) + " of " + std::to_string(*nv) + " vertices");
    if (w.size() < 3) throw in.error("vertex " + std::to_string(i) + ": expected \"x y z\"");
    for (std::size_t k = 0; k < 3; ++k) {
      const auto v = to_double(w[k]);
      if (!v) throw in.error("vertex " + std::to_string(i) + ": \"" + shorten(w[k]) + "\" is not a number");
      V[3 * static_cast<std::size_t>(i) + k] = *v;
    }
  }
  std::vector<std::int32_t> F;  // grows with what the file holds
  std::vector<std::int64_t> poly;
  for (std::int64_t f = 0; f < *nf; ++f) {
    if (!in.next(w))
      throw file_error(name, "the file ends after " + std::to_string(f) + " of " + std::to_string(*nf) + " faces");
    const auto n = to_int(w[0]);
    if (!n) throw in.error("face " + std::to_string(f) + ": \"" + shorten(w[0]) + "\" is not a vertex count");
    if (*n < 3)
      throw in.error("face " + std::to_string(f) + " lists " + std::to_string(*n) + " vertices, expected at least 3");
    if (static_cast<std::uint64_t>(*n) > w.size() - 1)
      throw in.error("face " + std::to_string(f) + " announces " + std::to_string(*n) + " vertices but lists " +
                     std::to_string(w.size() - 1));
    poly.resize(static_cast<std::size_t>(*n));
    for (std::size_t j = 0; j < poly.size(); ++j) {
      const auto v = to_int(w[j + 1]);
      if (!v) throw in.error("face " + std::to_string(f) + ": \"" + shorten(w[j + 1]) + "\" is not a vertex index");
      if (*v < 0 || *v >= *nv)
        throw in.error("face " + std::to_string(f) + " refers to vertex " + std::to_string(*v) + ", expected 0…" +
                       std::to_string(*nv - 1));
      poly[j] = *v;
    }
    fan(poly, F);  // extra values after the indices (a colour) are ignored
  }
  return to_mesh(V, F);
}

// ---------------------------------------------------------------- ASCII STL

Mesh parse_stl_ascii(const std::string& bytes, const std::string& name) {
  std::vector<double> V;
  std::vector<std::int32_t> F;
  std::map<std::array<double, 3>, std::int32_t> index;  // identical vertices joined; O(log #V)
  std::vector<std::int64_t> poly;
  TextLines in(bytes, name);
  std::vector<std::string_view> w;
  auto next = [&] { return in.next(w); };
  auto fail = [&](const std::string& what) { return in.error(what); };
  auto is = [](std::string_view word, std::string_view key) {
    if (word.size() != key.size()) return false;
    for (std::size_t i = 0; i < key.size(); ++i)
      if (std::tolower(static_cast<unsigned char>(word[i])) != key[i]) return false;
    return true;
  };
  auto found = [&]() { return w.empty() ? std::string("the end of the file") : "\"" + shorten(w[0]) + "\""; };
  bool in_solid = false;
  std::size_t solids = 0;
  while (next()) {
    if (!in_solid) {
      if (!is(w[0], "solid")) throw fail("expected \"solid\", found " + found());
      in_solid = true;
      ++solids;
      continue;
    }
    if (is(w[0], "endsolid")) {
      in_solid = false;
      continue;
    }
    if (!is(w[0], "facet")) throw fail("expected \"facet\" or \"endsolid\", found " + found());
    if (!next() || !is(w[0], "outer") || w.size() < 2 || !is(w[1], "loop"))
      throw fail("expected \"outer loop\", found " + found());
    poly.clear();
    while (next() && is(w[0], "vertex")) {
      if (w.size() < 4) throw fail("expected \"vertex x y z\"");
      std::array<double, 3> p{};
      for (std::size_t k = 0; k < 3; ++k) {
        const auto v = to_double(w[k + 1]);
        if (!v || !std::isfinite(*v)) throw fail("\"" + shorten(w[k + 1]) + "\" is not a finite number");
        p[k] = *v;
      }
      const auto [it, inserted] = index.try_emplace(p, static_cast<std::int32_t>(V.size() / 3));
      if (inserted) {
        if (V.size() / 3 >= static_cast<std::size_t>(kMaxVertices)) throw fail("more than 2^31 − 1 vertices");
        V.insert(V.end(), p.begin(), p.end());
      }
      poly.push_back(it->second);
    }
    if (w.empty() || !is(w[0], "endloop")) throw fail("expected \"vertex x y z\" or \"endloop\", found " + found());
    if (poly.size() < 3) throw fail("a facet with " + std::to_string(poly.size()) + " vertices, expected 3");
    fan(poly, F);
    if (!next() || !is(w[0], "endfacet")) throw fail("expected \"endfacet\", found " + found());
  }
  if (in_solid) throw file_error(name, "the file ends inside a solid (no \"endsolid\": truncated?)");
  if (solids == 0) throw file_error(name, "empty ASCII STL file");
  return to_mesh(V, F);
}

}  // namespace millnet::ingest::detail
