// PLY 1.0 reader (ascii, binary_little_endian, binary_big_endian).
//
// The header is read line by line; the body is read element by element in header order with
// one of two value readers (ASCII tokens or fixed-size binary scalars). Every element count is
// checked against the bytes left before anything is allocated, so a lying header cannot make
// the reader allocate more than the file can justify. Errors name the header line, the body
// line (ascii) or the byte offset (binary).
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

#include "trocar/mesh/io/mesh_io.h"

namespace trocar {
namespace {

enum class PlyType : std::uint8_t { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };
enum class PlyFormat { kAscii, kBinaryLittle, kBinaryBig };

std::size_t type_size(PlyType t) {
  switch (t) {
    case PlyType::kInt8: case PlyType::kUint8: return 1;
    case PlyType::kInt16: case PlyType::kUint16: return 2;
    case PlyType::kInt32: case PlyType::kUint32: case PlyType::kFloat32: return 4;
    case PlyType::kFloat64: return 8;
  }
  return 1;
}

bool is_float_type(PlyType t) { return t == PlyType::kFloat32 || t == PlyType::kFloat64; }

std::optional<PlyType> parse_type(std::string_view s) {
  if (s == "char" || s == "int8") return PlyType::kInt8;
  if (s == "uchar" || s == "uint8") return PlyType::kUint8;
  if (s == "short" || s == "int16") return PlyType::kInt16;
  if (s == "ushort" || s == "uint16") return PlyType::kUint16;
  if (s == "int" || s == "int32") return PlyType::kInt32;
  if (s == "uint" || s == "uint32") return PlyType::kUint32;
  if (s == "float" || s == "float32") return PlyType::kFloat32;
  if (s == "double" || s == "float64") return PlyType::kFloat64;
  return std::nullopt;
}

struct PlyProperty {
  std::string name;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;  ///< lists only
  PlyType value_type = PlyType::kFloat32;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  std::uint64_t line = 0;  ///< header line of the `element` declaration
};

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;
  std::uint64_t body_line = 0;  ///< line number of the first body line
};

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

bool parse_u64(std::string_view s, std::uint64_t& out) {
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size();
}

PlyHeader parse_header(std::string_view bytes, const std::string& name) {
  PlyHeader header;
  std::size_t pos = 0;
  std::uint64_t line_no = 0;
  bool have_format = false;
  auto fail = [&](const std::string& why) -> FileError {
    return FileError(name, FileLocation::line(line_no), why);
  };
  for (;;) {
    ++line_no;
    if (pos >= bytes.size()) {
      if (line_no == 1) throw fail("not a PLY file (first line must be 'ply')");
      throw FileError(name, FileLocation::line(line_no), "PLY header has no end_header line");
    }
    const std::size_t nl = bytes.find('\n', pos);
    const std::size_t end = nl == std::string_view::npos ? bytes.size() : nl;
    const std::string_view line = bytes.substr(pos, end - pos);
    pos = nl == std::string_view::npos ? bytes.size() : nl + 1;
    const std::vector<std::string_view> w = split_words(line);
    if (line_no == 1) {
      if (w.size() != 1 || w[0] != "ply") throw fail("not a PLY file (first line must be 'ply')");
      continue;
    }
    if (w.empty()) continue;
    const std::string_view key = w[0];
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      if (w.size() != 3) throw fail("malformed format line");
      if (w[1] == "ascii") header.format = PlyFormat::kAscii;
      else if (w[1] == "binary_little_endian") header.format = PlyFormat::kBinaryLittle;
      else if (w[1] == "binary_big_endian") header.format = PlyFormat::kBinaryBig;
      else throw fail("unknown PLY format '" + std::string(w[1]) + "'");
      if (w[2] != "1.0") throw fail("unsupported PLY version '" + std::string(w[2]) + "'");
      have_format = true;
    } else if (key == "element") {
      if (w.size() != 3) throw fail("malformed element line");
      PlyElement element;
      element.name = std::string(w[1]);
      if (!parse_u64(w[2], element.count)) throw fail("bad element count '" + std::string(w[2]) + "'");
      element.line = line_no;
      for (const PlyElement& e : header.elements)
        if (e.name == element.name) throw fail("element '" + element.name + "' declared twice");
      header.elements.push_back(std::move(element));
    } else if (key == "property") {
      if (header.elements.empty()) throw fail("property before any element");
      PlyProperty prop;
      if (w.size() == 5 && w[1] == "list") {
        const auto ct = parse_type(w[2]);
        const auto vt = parse_type(w[3]);
        if (!ct || !vt) throw fail("unknown property type in list");
        if (is_float_type(*ct)) throw fail("list count type must be an integer type");
        prop.is_list = true;
        prop.count_type = *ct;
        prop.value_type = *vt;
        prop.name = std::string(w[4]);
      } else if (w.size() == 3) {
        const auto t = parse_type(w[1]);
        if (!t) throw fail("unknown property type '" + std::string(w[1]) + "'");
        prop.value_type = *t;
        prop.name = std::string(w[2]);
      } else {
        throw fail("malformed property line");
      }
      header.elements.back().properties.push_back(std::move(prop));
    } else if (key == "end_header") {
      if (w.size() != 1) throw fail("malformed end_header line");
      if (!have_format) throw fail("PLY header has no format line");
      header.body_offset = pos;
      header.body_line = line_no + 1;
      return header;
    } else {
      throw fail("unknown header keyword '" + std::string(key) + "'");
    }
  }
}

/// Reads whitespace-separated values from an ascii body.
class AsciiValues {
 public:
  AsciiValues(std::string_view bytes, std::size_t pos, std::uint64_t line, const std::string& name)
      : bytes_(bytes), pos_(pos), line_(line), name_(name) {}

  std::size_t remaining() const { return bytes_.size() - pos_; }
  FileLocation where() const { return FileLocation::line(token_line_); }
  static std::size_t min_bytes(PlyType) { return 2; }  // one digit and one separator

  double read(PlyType t) {
    const std::string_view tok = next();
    if (is_float_type(t)) {
      double v = 0;
      const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
      if (ec != std::errc() || ptr != tok.data() + tok.size())
        throw FileError(name_, where(), "bad number '" + std::string(tok) + "'");
      return v;
    }
    return static_cast<double>(read_integer(tok, t));
  }

  std::int64_t read_int(PlyType t) {
    if (is_float_type(t)) return integral(read(t), where(), name_);
    return read_integer(next(), t);
  }

  void skip(PlyType t, std::uint64_t n) {
    for (std::uint64_t i = 0; i < n; ++i) read(t);
  }

  static std::int64_t integral(double v, FileLocation at, const std::string& name) {
    if (!(v >= -9007199254740992.0 && v <= 9007199254740992.0) || v != std::floor(v))
      throw FileError(name, at, "expected an integer value");
    return static_cast<std::int64_t>(v);
  }

 private:
  std::string_view next() {
    while (pos_ < bytes_.size()) {
      const char c = bytes_[pos_];
      if (c == '\n') ++line_;
      else if (c != ' ' && c != '\t' && c != '\r') break;
      ++pos_;
    }
    token_line_ = line_;
    if (pos_ >= bytes_.size()) throw FileError(name_, where(), "unexpected end of file (truncated body)");
    const std::size_t start = pos_;
    while (pos_ < bytes_.size() && bytes_[pos_] != ' ' && bytes_[pos_] != '\t' && bytes_[pos_] != '\r' &&
           bytes_[pos_] != '\n')
      ++pos_;
    return bytes_.substr(start, pos_ - start);
  }

  std::int64_t read_integer(std::string_view tok, PlyType t) {
    std::int64_t v = 0;
    const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (ec != std::errc() || ptr != tok.data() + tok.size())
      throw FileError(name_, where(), "bad integer '" + std::string(tok) + "'");
    std::int64_t lo = 0, hi = 0;
    switch (t) {
      case PlyType::kInt8: lo = -128; hi = 127; break;
      case PlyType::kUint8: lo = 0; hi = 255; break;
      case PlyType::kInt16: lo = -32768; hi = 32767; break;
      case PlyType::kUint16: lo = 0; hi = 65535; break;
      case PlyType::kInt32: lo = std::numeric_limits<std::int32_t>::min(); hi = std::numeric_limits<std::int32_t>::max(); break;
      default: lo = 0; hi = std::numeric_limits<std::uint32_t>::max(); break;
    }
    if (v < lo || v > hi) throw FileError(name_, where(), "integer '" + std::string(tok) + "' out of range for its type");
    return v;
  }

  std::string_view bytes_;
  std::size_t pos_;
  std::uint64_t line_;
  std::uint64_t token_line_ = 0;
  const std::string& name_;
};

/// Reads fixed-size scalars from a binary body of either byte order.
class BinaryValues {
 public:
  BinaryValues(std::string_view bytes, std::size_t pos, bool big_endian, const std::string& name)
      : bytes_(bytes), pos_(pos), big_(big_endian), name_(name) {}

  std::size_t remaining() const { return bytes_.size() - pos_; }
  FileLocation where() const { return FileLocation::byte(value_pos_); }
  static std::size_t min_bytes(PlyType t) { return type_size(t); }

  double read(PlyType t) {
    value_pos_ = pos_;
    const std::size_t n = type_size(t);
    if (remaining() < n) throw FileError(name_, where(), "unexpected end of file (truncated body)");
    unsigned char b[8] = {};
    std::memcpy(b, bytes_.data() + pos_, n);
    pos_ += n;
    const bool swap = big_ == (std::endian::native == std::endian::little);
    if (swap)
      for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    switch (t) {
      case PlyType::kInt8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
      case PlyType::kUint8: return b[0];
      case PlyType::kInt16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      case PlyType::kUint16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      case PlyType::kInt32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
      case PlyType::kUint32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
      case PlyType::kFloat32: { float v; std::memcpy(&v, b, 4); return static_cast<double>(v); }
      case PlyType::kFloat64: { double v; std::memcpy(&v, b, 8); return v; }
    }
    return 0;
  }

  std::int64_t read_int(PlyType t) { return AsciiValues::integral(read(t), where(), name_); }

  void skip(PlyType t, std::uint64_t n) {
    value_pos_ = pos_;
    const std::uint64_t size = type_size(t);
    if (n > remaining() / size) throw FileError(name_, where(), "unexpected end of file (truncated list)");
    pos_ += static_cast<std::size_t>(n * size);
  }

 private:
  std::string_view bytes_;
  std::size_t pos_;
  bool big_;
  std::size_t value_pos_ = 0;
  const std::string& name_;
};

int find_property(const PlyElement& e, std::string_view prop_name) {
  for (std::size_t i = 0; i < e.properties.size(); ++i)
    if (e.properties[i].name == prop_name) return static_cast<int>(i);
  return -1;
}

template <class Values>
TriMesh read_body(const PlyHeader& header, Values& in, const std::string& name) {
  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  for (const PlyElement& e : header.elements) {
    if (e.name == "vertex") vertex = &e;
    if (e.name == "face") face = &e;
  }
  if (!vertex) throw FileError(name, FileLocation::none(), "PLY file has no 'vertex' element");
  if (!face) throw FileError(name, FileLocation::none(), "PLY file has no 'face' element");
  if (vertex->count > std::numeric_limits<std::uint32_t>::max())
    throw FileError(name, FileLocation::line(vertex->line), "too many vertices");
  int xyz[3], nxyz[3];
  const char* const axes[3] = {"x", "y", "z"};
  const char* const normal_axes[3] = {"nx", "ny", "nz"};
  bool have_normals = true;
  for (int k = 0; k < 3; ++k) {
    xyz[k] = find_property(*vertex, axes[k]);
    if (xyz[k] < 0 || vertex->properties[xyz[k]].is_list)
      throw FileError(name, FileLocation::line(vertex->line),
                      std::string("vertex element has no scalar property '") + axes[k] + "'");
    nxyz[k] = find_property(*vertex, normal_axes[k]);
    if (nxyz[k] < 0 || vertex->properties[nxyz[k]].is_list) have_normals = false;
  }
  int index_prop = find_property(*face, "vertex_indices");
  if (index_prop < 0) index_prop = find_property(*face, "vertex_index");
  if (index_prop < 0 || !face->properties[index_prop].is_list)
    throw FileError(name, FileLocation::line(face->line),
                    "face element has no list property 'vertex_indices' or 'vertex_index'");

  TriMesh mesh;
  const std::uint64_t vertex_count = vertex->count;
  for (const PlyElement& e : header.elements) {
    if (e.properties.empty() || e.count == 0) continue;  // nothing to read, whatever the count
    // Smallest number of bytes one instance can occupy: reject lying counts before allocating.
    std::uint64_t min_bytes = 0;
    for (const PlyProperty& p : e.properties)
      min_bytes += Values::min_bytes(p.is_list ? p.count_type : p.value_type);
    if (e.count > (in.remaining() + 1) / min_bytes)
      throw FileError(name, FileLocation::line(e.line),
                      "element '" + e.name + "' declares " + std::to_string(e.count) +
                          " items but only " + std::to_string(in.remaining()) + " bytes remain");
    const bool is_vertex = &e == vertex;
    const bool is_face = &e == face;
    if (is_vertex) {
      mesh.positions.reserve(static_cast<std::size_t>(e.count));
      if (have_normals) mesh.normals.reserve(static_cast<std::size_t>(e.count));
    }
    if (is_face) mesh.triangles.reserve(static_cast<std::size_t>(e.count));
    std::vector<std::uint32_t> polygon;
    for (std::uint64_t i = 0; i < e.count; ++i) {
      double values[6] = {};
      for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
        const PlyProperty& p = e.properties[pi];
        if (!p.is_list) {
          const double v = in.read(p.value_type);
          if (is_vertex) {
            bool used = false;  // only x y z (and nx ny nz) must be finite; other values are dropped
            for (int k = 0; k < 3; ++k) {
              if (static_cast<int>(pi) == xyz[k]) {
                values[k] = v;
                used = true;
              }
              if (have_normals && static_cast<int>(pi) == nxyz[k]) {
                values[3 + k] = v;
                used = true;
              }
            }
            if (used && !std::isfinite(v))
              throw FileError(name, in.where(), "vertex value is not a finite number");
          }
          continue;
        }
        const std::int64_t n = in.read_int(p.count_type);
        if (n < 0) throw FileError(name, in.where(), "negative list count");
        if (!(is_face && static_cast<int>(pi) == index_prop)) {
          in.skip(p.value_type, static_cast<std::uint64_t>(n));
          continue;
        }
        polygon.clear();
        for (std::int64_t k = 0; k < n; ++k) {
          const std::int64_t idx = in.read_int(p.value_type);
          if (idx < 0 || static_cast<std::uint64_t>(idx) >= vertex_count)
            throw FileError(name, in.where(),
                            "vertex index " + std::to_string(idx) + " out of range (" +
                                std::to_string(vertex_count) + " vertices)");
          polygon.push_back(static_cast<std::uint32_t>(idx));
        }
        for (std::size_t k = 2; k < polygon.size(); ++k)  // fan; faces under 3 corners are dropped
          mesh.triangles.push_back({polygon[0], polygon[k - 1], polygon[k]});
      }
      if (is_vertex) {
        mesh.positions.emplace_back(values[0], values[1], values[2]);
        if (have_normals) mesh.normals.emplace_back(values[3], values[4], values[5]);
      }
    }
  }
  // A point cloud (or faces all under 3 corners) is valid PLY but not a surface: say so, as the
  // other readers do, instead of returning an empty mesh.
  if (mesh.triangles.empty()) throw FileError(name, FileLocation::none(), "no triangles (no face with 3 or more corners)");
  return mesh;
}

}  // namespace

TriMesh read_ply(std::string_view bytes, const std::string& name) {
  const PlyHeader header = parse_header(bytes, name);
  if (header.format == PlyFormat::kAscii) {
    AsciiValues in(bytes, header.body_offset, header.body_line, name);
    return read_body(header, in, name);
  }
  BinaryValues in(bytes, header.body_offset, header.format == PlyFormat::kBinaryBig, name);
  return read_body(header, in, name);
}

}  // namespace trocar
