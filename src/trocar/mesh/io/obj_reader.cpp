// Wavefront OBJ reader (polygonal subset).
//
// Accepted: `v x y z [w]` (also `v x y z r g b` vertex colours; extra numbers are checked to be
// numbers and ignored), `vt u [v [w]]`, `vn x y z`, `f` with corners `v`, `v/t`, `v//n`, `v/t/n`
// (1-based; negative = relative to the elements defined so far; positive indices may refer to
// elements defined later in the file), polygons of any size fan-triangulated (0,i,i+1),
// `#` comments (also after a statement), CRLF, tabs, a trailing `\` joining the next line, a
// UTF-8 byte-order mark. `g o s usemtl mtllib l p` and unknown statements are ignored (no .mtl
// is read; lines and points are not surface). A malformed known statement is an error.
//
// Attributes:
//  - normals (TriMesh::normals, per vertex): filled only when every face corner has a `vn`
//    index. A vertex gets the normal of the first corner (in file order) that references it;
//    vertices no face uses get (0,0,0). Normals are stored as written (not renormalised).
//  - texcoords (per corner): filled only when every face corner has a `vt` index.
//
// Errors (FileError, "FILE:LINE: reason"): an empty file, a control byte (binary data),
// non-numeric / out-of-range / non-finite (NaN, inf) numbers, too few numbers, index 0 or out
// of range, a face with fewer than 3 corners, a file with no faces ("no triangles").
#include <cstdint>
#include <string>
#include <vector>

#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/io/text_scan.h"

namespace trocar {
namespace {

using text::NumberStatus;

// What an index refers to, for messages and the deferred range check.
enum class Kind : std::uint8_t { kPosition, kTexcoord, kNormal };

const char* kind_name(Kind kind) {
  switch (kind) {
    case Kind::kPosition: return "vertex";
    case Kind::kTexcoord: return "texture coordinate";
    case Kind::kNormal: return "normal";
  }
  return "vertex";
}

const char* kind_keyword(Kind kind) {
  switch (kind) {
    case Kind::kPosition: return "v";
    case Kind::kTexcoord: return "vt";
    case Kind::kNormal: return "vn";
  }
  return "v";
}

// A positive index beyond what was defined when its face was read: checked at the end, since
// the element may be defined later in the file.
struct ForwardReference {
  std::uint64_t line;
  std::int64_t index;  // 1-based, as written
  Kind kind;
};

constexpr std::uint32_t kNone = 0xFFFFFFFFu;

struct Corner {
  std::uint32_t v = 0;
  std::uint32_t t = kNone;
  std::uint32_t n = kNone;
};

class ObjParser {
 public:
  ObjParser(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {}

  TriMesh parse();

 private:
  [[noreturn]] void fail(const std::string& reason) const {
    throw FileError(name_, FileLocation::line(line_), reason);
  }

  void parse_statement(std::string_view statement);
  void parse_vertex(text::Tokens& tokens);
  void parse_texcoord(text::Tokens& tokens);
  void parse_normal(text::Tokens& tokens);
  void parse_face(text::Tokens& tokens);
  double parse_number(std::string_view token, const char* keyword, bool must_be_finite);
  std::uint32_t resolve(std::string_view token, Kind kind, std::size_t defined);
  void check_count_limit(std::size_t count, Kind kind) const;
  TriMesh finish();

  std::string_view bytes_;
  const std::string& name_;
  std::uint64_t line_ = 0;

  std::vector<Vec3> positions_;
  std::vector<Vec2> texcoords_;
  std::vector<Vec3> normals_;
  std::vector<Triangle> triangles_;
  std::vector<std::uint32_t> corner_texcoords_;  // 3 per triangle while all_texcoords_
  std::vector<std::uint32_t> corner_normals_;    // 3 per triangle while all_normals_
  bool all_texcoords_ = true;
  bool all_normals_ = true;
  std::vector<Corner> face_;  // reused buffer for one face's corners
  std::vector<ForwardReference> forward_;
};

TriMesh ObjParser::parse() {
  if (bytes_.empty()) throw FileError(name_, FileLocation::none(), "empty file");
  text::LineScanner lines(bytes_);
  std::string_view line;
  std::string joined;  // only used for lines continued with a trailing backslash
  while (lines.next(line)) {
    line_ = lines.line_number();
    const std::size_t bad = text::find_binary_byte(line);
    if (bad != std::string_view::npos) {
      fail("binary data (byte " + text::quote(line.substr(bad, 1)) + " at column " +
           std::to_string(bad + 1) + "); this is not a text OBJ file");
    }
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    std::size_t end = line.size();
    while (end > 0 && text::is_blank(line[end - 1])) --end;
    if (end > 0 && line[end - 1] == '\\') {
      // Continuation: join with the following lines; errors name the first line.
      const std::uint64_t first_line = line_;
      joined.assign(line.substr(0, end - 1));
      std::string_view next;
      bool more = true;
      while (more && lines.next(next)) {
        line_ = lines.line_number();
        const std::size_t b = text::find_binary_byte(next);
        if (b != std::string_view::npos) fail("binary data; this is not a text OBJ file");
        const std::size_t h = next.find('#');
        if (h != std::string_view::npos) next = next.substr(0, h);
        std::size_t e = next.size();
        while (e > 0 && text::is_blank(next[e - 1])) --e;
        more = e > 0 && next[e - 1] == '\\';
        joined += ' ';
        joined.append(next.substr(0, more ? e - 1 : e));
      }
      const std::uint64_t last_line = line_;
      line_ = first_line;
      parse_statement(joined);
      line_ = last_line;
    } else {
      parse_statement(line.substr(0, end));
    }
  }
  return finish();
}

void ObjParser::parse_statement(std::string_view statement) {
  text::Tokens tokens(statement);
  std::string_view keyword;
  if (!tokens.next(keyword)) return;
  if (keyword == "v") {
    parse_vertex(tokens);
  } else if (keyword == "f") {
    parse_face(tokens);
  } else if (keyword == "vn") {
    parse_normal(tokens);
  } else if (keyword == "vt") {
    parse_texcoord(tokens);
  }
  // g o s usemtl mtllib l p vp and anything else: ignored.
}

double ObjParser::parse_number(std::string_view token, const char* keyword, bool must_be_finite) {
  double value = 0;
  const NumberStatus status = text::parse_real(token, value);
  if (status == NumberStatus::kOk || (status == NumberStatus::kNotFinite && !must_be_finite))
    return value;
  fail(std::string("'") + keyword + "': " + text::quote(token) + " " + text::describe(status));
}

void ObjParser::check_count_limit(std::size_t count, Kind kind) const {
  if (count >= kNone) {
    fail(std::string("too many '") + kind_keyword(kind) + "' elements (more than 2^32 - 2)");
  }
}

void ObjParser::parse_vertex(text::Tokens& tokens) {
  check_count_limit(positions_.size(), Kind::kPosition);
  Vec3 p;
  std::string_view token;
  int count = 0;
  while (tokens.next(token)) {
    // x y z must be finite; w or r g b are checked to be numbers and otherwise ignored.
    const double value = parse_number(token, "v", count < 3);
    if (count < 3) p[count] = value;
    ++count;
  }
  if (count < 3) fail("'v' needs 3 coordinates x y z, got " + std::to_string(count));
  if (count > 7) fail("'v' has " + std::to_string(count) + " numbers (at most 7: x y z w or x y z r g b)");
  positions_.push_back(p);
}

void ObjParser::parse_texcoord(text::Tokens& tokens) {
  check_count_limit(texcoords_.size(), Kind::kTexcoord);
  Vec2 uv = Vec2::Zero();
  std::string_view token;
  int count = 0;
  while (tokens.next(token)) {
    const double value = parse_number(token, "vt", true);
    if (count < 2) uv[count] = value;
    ++count;
  }
  if (count < 1 || count > 3) fail("'vt' needs 1 to 3 numbers (u [v [w]]), got " + std::to_string(count));
  texcoords_.push_back(uv);
}

void ObjParser::parse_normal(text::Tokens& tokens) {
  check_count_limit(normals_.size(), Kind::kNormal);
  Vec3 n;
  std::string_view token;
  int count = 0;
  while (tokens.next(token)) {
    const double value = parse_number(token, "vn", true);
    if (count < 3) n[count] = value;
    ++count;
  }
  if (count != 3) fail("'vn' needs 3 numbers x y z, got " + std::to_string(count));
  normals_.push_back(n);
}

// Turns one written index into a 0-based one. `defined` is how many elements of the kind exist
// at this point of the file.
std::uint32_t ObjParser::resolve(std::string_view token, Kind kind, std::size_t defined) {
  std::int64_t index = 0;
  const NumberStatus status = text::parse_int(token, index);
  if (status == NumberStatus::kOutOfRange) {
    fail(std::string(kind_name(kind)) + " index " + text::quote(token) + " is out of range");
  }
  if (status != NumberStatus::kOk) {
    fail(std::string("'f': ") + kind_name(kind) + " index " + text::quote(token) +
         " is not an integer");
  }
  if (index == 0) fail(std::string(kind_name(kind)) + " index 0 (OBJ indices start at 1)");
  const auto n = static_cast<std::int64_t>(defined);
  if (index < 0) {
    if (-index > n) {
      fail(std::string("relative ") + kind_name(kind) + " index " + std::to_string(index) +
           " reaches before the first one (" + std::to_string(n) + " '" + kind_keyword(kind) +
           "' defined so far)");
    }
    return static_cast<std::uint32_t>(n + index);
  }
  if (index >= static_cast<std::int64_t>(kNone)) {
    fail(std::string(kind_name(kind)) + " index " + std::to_string(index) + " is out of range");
  }
  if (index > n) forward_.push_back({line_, index, kind});
  return static_cast<std::uint32_t>(index - 1);
}

void ObjParser::parse_face(text::Tokens& tokens) {
  face_.clear();
  std::string_view token;
  while (tokens.next(token)) {
    Corner corner;
    const std::size_t s1 = token.find('/');
    const std::string_view v = token.substr(0, s1);
    if (v.empty()) fail("'f': corner " + text::quote(token) + " has no vertex index");
    corner.v = resolve(v, Kind::kPosition, positions_.size());
    if (s1 != std::string_view::npos) {
      const std::string_view after = token.substr(s1 + 1);
      const std::size_t s2 = after.find('/');
      const std::string_view t = after.substr(0, s2);
      if (!t.empty()) corner.t = resolve(t, Kind::kTexcoord, texcoords_.size());
      if (s2 != std::string_view::npos) {
        const std::string_view nrm = after.substr(s2 + 1);
        if (nrm.empty() || nrm.find('/') != std::string_view::npos) {
          fail("'f': corner " + text::quote(token) + " is not v, v/t, v//n or v/t/n");
        }
        corner.n = resolve(nrm, Kind::kNormal, normals_.size());
      } else if (t.empty()) {
        fail("'f': corner " + text::quote(token) + " is not v, v/t, v//n or v/t/n");
      }
    }
    face_.push_back(corner);
  }
  if (face_.size() < 3) {
    fail("'f' with " + std::to_string(face_.size()) + " vertices (a face needs at least 3)");
  }
  for (const Corner& c : face_) {
    if (c.t == kNone && all_texcoords_) {
      all_texcoords_ = false;
      corner_texcoords_ = {};
    }
    if (c.n == kNone && all_normals_) {
      all_normals_ = false;
      corner_normals_ = {};
    }
  }
  for (std::size_t i = 1; i + 1 < face_.size(); ++i) {
    const Corner& a = face_[0];
    const Corner& b = face_[i];
    const Corner& c = face_[i + 1];
    triangles_.push_back({a.v, b.v, c.v});
    if (all_texcoords_) corner_texcoords_.insert(corner_texcoords_.end(), {a.t, b.t, c.t});
    if (all_normals_) corner_normals_.insert(corner_normals_.end(), {a.n, b.n, c.n});
  }
}

TriMesh ObjParser::finish() {
  // Positive indices past what was defined at their face: now everything is defined.
  for (const ForwardReference& ref : forward_) {
    const std::size_t defined = ref.kind == Kind::kPosition   ? positions_.size()
                                : ref.kind == Kind::kTexcoord ? texcoords_.size()
                                                              : normals_.size();
    if (ref.index > static_cast<std::int64_t>(defined)) {
      throw FileError(name_, FileLocation::line(ref.line),
                      std::string(kind_name(ref.kind)) + " index " + std::to_string(ref.index) +
                          " is out of range (the file has " + std::to_string(defined) + " '" +
                          kind_keyword(ref.kind) + "')");
    }
  }
  if (triangles_.empty()) {
    throw FileError(name_, FileLocation::none(),
                    "no triangles (" + std::to_string(positions_.size()) +
                        " vertices but no 'f' faces)");
  }
  TriMesh mesh;
  mesh.positions = std::move(positions_);
  mesh.triangles = std::move(triangles_);
  if (all_texcoords_) {
    mesh.texcoords.reserve(corner_texcoords_.size());
    for (std::uint32_t t : corner_texcoords_) mesh.texcoords.push_back(texcoords_[t]);
  }
  if (all_normals_) {
    mesh.normals.assign(mesh.positions.size(), Vec3::Zero());
    std::vector<bool> assigned(mesh.positions.size(), false);
    for (std::size_t k = 0; k < corner_normals_.size(); ++k) {
      const std::uint32_t v = mesh.triangles[k / 3][k % 3];
      if (!assigned[v]) {
        assigned[v] = true;
        mesh.normals[v] = normals_[corner_normals_[k]];
      }
    }
  }
  return mesh;
}

}  // namespace

TriMesh read_obj(std::string_view bytes, const std::string& name) {
  return ObjParser(bytes, name).parse();
}

}  // namespace trocar
