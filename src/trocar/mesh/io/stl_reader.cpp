// STL reader, binary and ASCII.
//
// Detection by content: binary when the file has at least 84 bytes and its size is exactly
// 84 + 50·n for the little-endian facet count n at byte 80 (binary headers may begin with
// "solid", so that word alone proves nothing); otherwise ASCII when the first non-blank bytes
// are "solid" (any case); otherwise an error. A binary file whose count disagrees with its size
// is an error naming byte 80 (nothing is allocated from the count).
//
// Binary: the 80-byte header, the facet normals and the 16-bit attribute words are ignored;
// a NaN or infinite vertex coordinate is an error naming the facet's byte offset.
// ASCII: `solid name` / `facet normal nx ny nz` / `outer loop` / 3 × `vertex x y z` / `endloop`
// / `endfacet` / `endsolid [name]`, keywords in any case, any whitespace between tokens,
// several solids one after another (merged into one mesh). Errors name the line.
//
// Corners with equal coordinates (exact equality: the same bits, with -0 and +0 treated as
// equal) become one vertex, numbered in order of first appearance. Degenerate facets are kept.
// A file with no facets is an error ("no triangles"). Facet normals are not stored.
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/io/text_scan.h"

namespace trocar {
namespace {

constexpr std::size_t kHeaderBytes = 80;
constexpr std::size_t kPreambleBytes = 84;  // header + facet count
constexpr std::size_t kFacetBytes = 50;     // normal, 3 vertices (12 float32), attribute word

// Merges corners with equal coordinates. Open addressing with linear probing over the vertex
// indices; the keys are the positions themselves. The table stays at most half full.
class Welder {
 public:
  explicit Welder(std::vector<Vec3>& positions) : positions_(positions) { rehash(64); }

  /// The index of the vertex at p, adding it if new. p must be finite.
  std::uint32_t add(Vec3 p) {
    for (int k = 0; k < 3; ++k)
      if (p[k] == 0.0) p[k] = 0.0;  // -0 → +0, so that equal coordinates have equal bits
    if (2 * (positions_.size() + 1) > slots_.size()) rehash(2 * slots_.size());
    std::size_t i = hash(p) & mask_;
    while (slots_[i] != 0) {
      const std::uint32_t v = slots_[i] - 1;
      if (positions_[v] == p) return v;
      i = (i + 1) & mask_;
    }
    const auto v = static_cast<std::uint32_t>(positions_.size());
    positions_.push_back(p);
    slots_[i] = v + 1;
    return v;
  }

 private:
  static std::size_t hash(const Vec3& p) {
    std::uint64_t h = 0x9E3779B97F4A7C15ull;
    for (int k = 0; k < 3; ++k) {
      h ^= std::bit_cast<std::uint64_t>(p[k]);
      h *= 0xFF51AFD7ED558CCDull;
      h ^= h >> 32;
    }
    return static_cast<std::size_t>(h);
  }

  void rehash(std::size_t capacity) {
    slots_.assign(capacity, 0);
    mask_ = capacity - 1;
    for (std::size_t v = 0; v < positions_.size(); ++v) {
      std::size_t i = hash(positions_[v]) & mask_;
      while (slots_[i] != 0) i = (i + 1) & mask_;
      slots_[i] = static_cast<std::uint32_t>(v + 1);
    }
  }

  std::vector<Vec3>& positions_;
  std::vector<std::uint32_t> slots_;  // vertex index + 1; 0 = empty
  std::size_t mask_ = 0;
};

std::uint32_t load_u32_le(const char* p) {
  unsigned char b[4];
  std::memcpy(b, p, 4);
  return static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8) |
         (static_cast<std::uint32_t>(b[2]) << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
}

float load_f32_le(const char* p) { return std::bit_cast<float>(load_u32_le(p)); }

TriMesh read_binary(std::string_view bytes, const std::string& name, std::uint32_t count) {
  TriMesh mesh;
  mesh.triangles.reserve(count);  // justified: the size check proved 50 bytes per facet
  Welder welder(mesh.positions);
  for (std::size_t f = 0; f < count; ++f) {
    const std::size_t offset = kPreambleBytes + kFacetBytes * f;
    const char* corner = bytes.data() + offset + 12;  // skip the facet normal
    Triangle tri;
    for (int c = 0; c < 3; ++c) {
      Vec3 p;
      for (int k = 0; k < 3; ++k) p[k] = load_f32_le(corner + 4 * (3 * c + k));
      if (!p.allFinite()) {
        throw FileError(name, FileLocation::byte(offset),
                        "facet " + std::to_string(f) + " has a non-finite vertex coordinate (NaN or inf)");
      }
      tri[c] = welder.add(p);
    }
    mesh.triangles.push_back(tri);
  }
  return mesh;
}

class AsciiStlParser {
 public:
  AsciiStlParser(std::string_view bytes, const std::string& name) : scan_(bytes), name_(name) {}

  TriMesh parse() {
    TriMesh mesh;
    Welder welder(mesh.positions);
    std::string_view token;
    while (scan_.next(token)) {
      if (!text::istarts_with(token, "solid")) fail("expected 'solid', got " + text::quote(token));
      // The name: the rest of the line after the 5 letters (which may run into it).
      scan_.rest_of_line();
      parse_solid(mesh, welder);
    }
    if (mesh.triangles.empty()) {
      throw FileError(name_, FileLocation::none(), "no triangles (no facets)");
    }
    return mesh;
  }

 private:
  [[noreturn]] void fail(const std::string& reason) const {
    throw FileError(name_, FileLocation::line(scan_.line()), reason);
  }

  std::string_view next(const char* expected) {
    std::string_view token;
    if (!scan_.next(token)) fail(std::string("file ends where '") + expected + "' was expected");
    return token;
  }

  void expect(const char* keyword) {
    const std::string_view token = next(keyword);
    if (!text::iequals(token, keyword)) {
      fail(std::string("expected '") + keyword + "', got " + text::quote(token));
    }
  }

  double number(bool must_be_finite) {
    const std::string_view token = next("a number");
    double value = 0;
    const text::NumberStatus status = text::parse_real(token, value);
    if (status == text::NumberStatus::kOk ||
        (status == text::NumberStatus::kNotFinite && !must_be_finite))
      return value;
    fail(text::quote(token) + " " + text::describe(status));
  }

  void parse_solid(TriMesh& mesh, Welder& welder) {
    for (;;) {
      const std::string_view token = next("facet' or 'endsolid");
      if (text::iequals(token, "endsolid")) {
        scan_.rest_of_line();
        return;
      }
      if (!text::iequals(token, "facet")) {
        fail("expected 'facet' or 'endsolid', got " + text::quote(token));
      }
      expect("normal");
      for (int k = 0; k < 3; ++k) number(false);  // the facet normal is not used
      expect("outer");
      expect("loop");
      Triangle tri{};
      int corners = 0;
      for (;;) {
        const std::string_view word = next("vertex' or 'endloop");
        if (text::iequals(word, "endloop")) break;
        if (!text::iequals(word, "vertex")) {
          fail("expected 'vertex' or 'endloop', got " + text::quote(word));
        }
        if (corners == 3) fail("facet with more than 3 vertices (STL facets are triangles)");
        Vec3 p;
        for (int k = 0; k < 3; ++k) p[k] = number(true);
        tri[corners++] = welder.add(p);
      }
      if (corners != 3) {
        fail("facet with " + std::to_string(corners) + " vertices (STL facets are triangles)");
      }
      expect("endfacet");
      if (mesh.triangles.size() >= 0xFFFFFFFFu) fail("too many facets");
      mesh.triangles.push_back(tri);
    }
  }

  text::TokenScanner scan_;
  const std::string& name_;
};

bool starts_with_solid(std::string_view bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && text::is_space(bytes[i])) ++i;
  return text::istarts_with(bytes.substr(i), "solid");
}

}  // namespace

TriMesh read_stl(std::string_view bytes, const std::string& name) {
  if (bytes.empty()) throw FileError(name, FileLocation::none(), "empty file");
  const std::uint64_t size = bytes.size();
  std::uint32_t count = 0;
  std::uint64_t expected = 0;
  if (size >= kPreambleBytes) {
    count = load_u32_le(bytes.data() + kHeaderBytes);
    expected = kPreambleBytes + kFacetBytes * std::uint64_t{count};
    if (expected == size) {
      if (count == 0) throw FileError(name, FileLocation::byte(kHeaderBytes), "no triangles (binary STL with 0 facets)");
      return read_binary(bytes, name, count);
    }
  }
  const std::string binary_note =
      size >= kPreambleBytes
          ? "read as binary STL, the facet count " + std::to_string(count) + " at byte 80 needs " +
                std::to_string(expected) + " bytes but the file has " + std::to_string(size)
          : "too short for a binary STL (" + std::to_string(size) + " bytes, the header alone is 84)";
  if (starts_with_solid(bytes)) {
    try {
      return AsciiStlParser(bytes, name).parse();
    } catch (const FileError& e) {
      // "solid" followed by binary bytes: most likely a binary STL whose count is wrong.
      if (text::find_binary_byte(bytes) == std::string_view::npos) throw;
      throw FileError(name, e.where(),
                      e.reason() + " (the file starts with 'solid' but holds binary data; " +
                          binary_note + ")");
    }
  }
  if (size < kPreambleBytes) {
    throw FileError(name, FileLocation::none(),
                    "not an STL file: no 'solid' at the start (ASCII) and " + binary_note);
  }
  throw FileError(name, FileLocation::byte(kHeaderBytes),
                  "binary STL facet count " + std::to_string(count) + " needs " +
                      std::to_string(expected) + " bytes but the file has " + std::to_string(size) +
                      (size < expected ? " (truncated, or the count is wrong)"
                                       : " (trailing data, or the count is wrong)"));
}

}  // namespace trocar
