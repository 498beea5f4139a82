// Legacy VTK reader: DATASET POLYDATA, ASCII or BINARY (big-endian), versions 2.0 to 5.1.
//
// Keywords are read as whitespace-separated tokens (case-insensitive, as vtkDataReader does);
// in BINARY files each data block starts right after the newline that ends its keyword line.
// Cells come in the classic layout ("POLYGONS n size" then n runs of "count i0 i1 ...") or the
// 5.1 layout (OFFSETS and CONNECTIVITY arrays), told apart by the keyword after the cell line.
// VERTICES and LINES are skipped, FIELD arrays and METADATA blocks are skipped, and reading
// stops at POINT_DATA / CELL_DATA (attributes carry no geometry). A file whose cells make no
// triangle is an error ("no triangles"), as in the other readers. Errors name the line for
// ASCII files and header lines, the byte offset inside BINARY files.
#include <algorithm>
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

enum class VtkKind { kSigned, kUnsigned, kFloat };
struct VtkType {
  std::size_t size = 4;
  VtkKind kind = VtkKind::kFloat;
};

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return out;
}

std::optional<VtkType> parse_vtk_type(std::string_view s) {
  const std::string t = lower(s);
  if (t == "unsigned_char" || t == "vtktypeuint8") return VtkType{1, VtkKind::kUnsigned};
  if (t == "char" || t == "signed_char" || t == "vtktypeint8") return VtkType{1, VtkKind::kSigned};
  if (t == "unsigned_short" || t == "vtktypeuint16") return VtkType{2, VtkKind::kUnsigned};
  if (t == "short" || t == "vtktypeint16") return VtkType{2, VtkKind::kSigned};
  if (t == "unsigned_int" || t == "vtktypeuint32") return VtkType{4, VtkKind::kUnsigned};
  if (t == "int" || t == "vtktypeint32") return VtkType{4, VtkKind::kSigned};
  if (t == "unsigned_long" || t == "vtktypeuint64") return VtkType{8, VtkKind::kUnsigned};
  if (t == "long" || t == "vtktypeint64" || t == "vtkidtype") return VtkType{8, VtkKind::kSigned};
  if (t == "float") return VtkType{4, VtkKind::kFloat};
  if (t == "double") return VtkType{8, VtkKind::kFloat};
  return std::nullopt;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

class VtkReader {
 public:
  VtkReader(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {}

  TriMesh read() {
    read_header();
    bool have_dataset = false;
    bool have_points = false;
    bool have_cells = false;
    for (;;) {
      const std::string_view tok = token();
      if (tok.empty()) break;
      const std::string key = lower(tok);
      if (key == "field") {
        skip_field();
      } else if (key == "metadata") {
        skip_metadata();
      } else if (key == "dataset") {
        if (have_dataset) throw error("second DATASET keyword");
        const std::string type = lower(token());
        if (type != "polydata")
          throw error("only DATASET POLYDATA is supported, not '" + type + "'");
        have_dataset = true;
      } else if (key == "point_data" || key == "cell_data") {
        break;  // attributes follow; they carry no geometry
      } else if (!have_dataset) {
        throw error("expected DATASET POLYDATA before '" + std::string(tok) + "'");
      } else if (key == "points") {
        if (have_points) throw error("second POINTS section");
        read_points();
        have_points = true;
      } else if (key == "polygons" || key == "triangle_strips" || key == "vertices" || key == "lines") {
        if (!have_points) throw error("'" + std::string(tok) + "' before POINTS");
        const bool keep = key == "polygons" || key == "triangle_strips";
        read_cells(keep, key == "triangle_strips");
        have_cells = have_cells || keep;
      } else {
        throw error("unknown or unsupported keyword '" + std::string(tok) + "'");
      }
    }
    if (!have_dataset) throw FileError(name_, FileLocation::none(), "no DATASET POLYDATA section");
    if (!have_points) throw FileError(name_, FileLocation::none(), "no POINTS section");
    if (!have_cells) throw FileError(name_, FileLocation::none(), "no POLYGONS or TRIANGLE_STRIPS section");
    // Sections may be empty ("POLYGONS 0 0") or hold only cells of fewer than 3 points.
    if (mesh_.triangles.empty())
      throw FileError(name_, FileLocation::none(), "no triangles (no cell with 3 or more points)");
    return std::move(mesh_);
  }

 private:
  FileError error(const std::string& why) const {
    if (binary_) return FileError(name_, FileLocation::byte(tok_pos_), why);
    return FileError(name_, FileLocation::line(tok_line_), why);
  }

  // --- low-level cursor -------------------------------------------------------------------

  std::size_t remaining() const { return bytes_.size() - pos_; }

  /// A cursor position to come back to after peeking at a token.
  struct Mark {
    std::size_t pos, tok_pos;
    std::uint64_t line, tok_line;
  };
  Mark save() const { return {pos_, tok_pos_, line_, tok_line_}; }
  void restore(const Mark& m) {
    pos_ = m.pos;
    tok_pos_ = m.tok_pos;
    line_ = m.line;
    tok_line_ = m.tok_line;
  }

  /// Next whitespace-separated token; empty at end of file.
  std::string_view token() {
    while (pos_ < bytes_.size() && is_space(bytes_[pos_])) {
      if (bytes_[pos_] == '\n') ++line_;
      ++pos_;
    }
    tok_pos_ = pos_;
    tok_line_ = line_;
    const std::size_t start = pos_;
    while (pos_ < bytes_.size() && !is_space(bytes_[pos_])) ++pos_;
    return bytes_.substr(start, pos_ - start);
  }

  /// A token that must be present.
  std::string_view required(const char* what) {
    const std::string_view t = token();
    if (t.empty()) throw error(std::string("unexpected end of file, expected ") + what);
    return t;
  }

  std::uint64_t count(const char* what) {
    const std::string_view t = required(what);
    std::uint64_t v = 0;
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || ptr != t.data() + t.size())
      throw error(std::string("bad ") + what + " '" + std::string(t) + "'");
    return v;
  }

  /// The rest of the current line (for header lines), consuming its newline.
  std::string_view raw_line() {
    tok_pos_ = pos_;
    tok_line_ = line_;
    const std::size_t nl = bytes_.find('\n', pos_);
    const std::size_t end = nl == std::string_view::npos ? bytes_.size() : nl;
    std::string_view line = bytes_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = nl == std::string_view::npos ? bytes_.size() : nl + 1;
    if (nl != std::string_view::npos) ++line_;
    return line;
  }

  /// In BINARY files, data starts after the newline that ends the keyword line.
  void start_binary_block() {
    if (!binary_) return;
    while (pos_ < bytes_.size() && (bytes_[pos_] == ' ' || bytes_[pos_] == '\t' || bytes_[pos_] == '\r')) ++pos_;
    if (pos_ >= bytes_.size() || bytes_[pos_] != '\n') {
      tok_pos_ = pos_;
      throw error("expected a newline before binary data");
    }
    ++pos_;
    ++line_;
    tok_pos_ = pos_;  // errors about the block's size point at its first byte
  }

  /// Throws unless n values of at least min_size bytes each can still fit in the file.
  void check_fits(std::uint64_t n, std::size_t min_size, const char* what) {
    const std::size_t room = binary_ ? remaining() : remaining() + 1;  // ASCII: last value needs no separator
    if (n > room / min_size)
      throw error(std::string(what) + " count " + std::to_string(n) + " exceeds what the remaining " +
                  std::to_string(remaining()) + " bytes can hold");
  }
  std::size_t min_value_bytes(VtkType t) const { return binary_ ? t.size : 2; }

  double read_value(VtkType t) {
    if (!binary_) {
      const std::string_view tok = required("a number");
      if (t.kind == VtkKind::kFloat) {
        double v = 0;
        const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
        if (ec != std::errc() || ptr != tok.data() + tok.size())
          throw error("bad number '" + std::string(tok) + "'");
        return v;
      }
      std::int64_t v = 0;
      const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
      if (ec != std::errc() || ptr != tok.data() + tok.size())
        throw error("bad integer '" + std::string(tok) + "'");
      return static_cast<double>(v);
    }
    tok_pos_ = pos_;
    if (remaining() < t.size) throw error("unexpected end of file in binary data");
    unsigned char b[8] = {};
    std::memcpy(b, bytes_.data() + pos_, t.size);
    pos_ += t.size;
    if constexpr (std::endian::native == std::endian::little)
      std::reverse(b, b + t.size);  // the file is big-endian
    if (t.kind == VtkKind::kFloat) {
      if (t.size == 4) { float f; std::memcpy(&f, b, 4); return static_cast<double>(f); }
      double d; std::memcpy(&d, b, 8); return d;
    }
    std::uint64_t u = 0;
    for (std::size_t i = 0; i < t.size; ++i) u |= static_cast<std::uint64_t>(b[i]) << (8 * i);
    if (t.kind == VtkKind::kUnsigned) return static_cast<double>(u);
    if (t.size < 8 && (u >> (8 * t.size - 1)) != 0) u |= ~std::uint64_t{0} << (8 * t.size);  // sign-extend
    return static_cast<double>(static_cast<std::int64_t>(u));
  }

  /// An integer value (count or index); exact below 2^53, which any index that fits in a
  /// 32-bit vertex count is.
  std::int64_t read_int(VtkType t) {
    if (!binary_ && t.kind != VtkKind::kFloat) {
      const std::string_view tok = required("an integer");
      std::int64_t v = 0;
      const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
      if (ec != std::errc() || ptr != tok.data() + tok.size())
        throw error("bad integer '" + std::string(tok) + "'");
      return v;
    }
    const double v = read_value(t);
    if (!(v >= -9007199254740992.0 && v <= 9007199254740992.0) || v != std::floor(v))
      throw error("expected an integer value");
    return static_cast<std::int64_t>(v);
  }

  void skip_values(VtkType t, std::uint64_t n, const char* what) {
    check_fits(n, min_value_bytes(t), what);
    if (binary_) {
      pos_ += static_cast<std::size_t>(n * t.size);
      return;
    }
    for (std::uint64_t i = 0; i < n; ++i) read_value(t);
  }

  // --- sections ----------------------------------------------------------------------------

  void read_header() {
    const std::string_view first = raw_line();
    if (first.substr(0, 22) != "# vtk DataFile Version")
      throw error("not a legacy VTK file (first line must be '# vtk DataFile Version x.y')");
    if (pos_ >= bytes_.size()) throw FileError(name_, FileLocation::line(2), "missing title line");
    raw_line();  // title, free text
    const std::string_view mode_line = raw_line();
    std::string mode = lower(mode_line);
    while (!mode.empty() && is_space(mode.back())) mode.pop_back();
    while (!mode.empty() && is_space(mode.front())) mode.erase(mode.begin());
    if (mode == "ascii") binary_ = false;
    else if (mode == "binary") binary_ = true;
    else throw error("third line must be ASCII or BINARY, not '" + std::string(mode_line) + "'");
  }

  void read_points() {
    const std::uint64_t n = count("point count");
    const std::optional<VtkType> type = parse_vtk_type(required("point type"));
    if (!type) throw error("unknown POINTS data type");
    if (n > std::numeric_limits<std::uint32_t>::max()) throw error("too many points");
    start_binary_block();
    check_fits(n, 3 * min_value_bytes(*type), "POINTS");
    mesh_.positions.reserve(static_cast<std::size_t>(n));
    for (std::uint64_t i = 0; i < n; ++i) {
      Vec3 p;
      for (int k = 0; k < 3; ++k) {
        p[k] = read_value(*type);
        if (!std::isfinite(p[k])) throw error("point coordinate is not a finite number");
      }
      mesh_.positions.push_back(p);
    }
  }

  std::uint32_t check_index(std::int64_t i) {
    if (i < 0 || static_cast<std::uint64_t>(i) >= mesh_.positions.size())
      throw error("point index " + std::to_string(i) + " out of range (" +
                  std::to_string(mesh_.positions.size()) + " points)");
    return static_cast<std::uint32_t>(i);
  }

  void emit(const std::vector<std::uint32_t>& cell, bool strip) {
    for (std::size_t k = 2; k < cell.size(); ++k) {
      if (!strip) mesh_.triangles.push_back({cell[0], cell[k - 1], cell[k]});
      else if (k % 2 == 0) mesh_.triangles.push_back({cell[k - 2], cell[k - 1], cell[k]});
      else mesh_.triangles.push_back({cell[k - 1], cell[k - 2], cell[k]});
    }
  }

  void read_cells(bool keep, bool strip) {
    const std::uint64_t a = count("cell count");
    const std::uint64_t b = count("cell array size");
    // Peek: the 5.1 layout continues with an OFFSETS keyword.
    const Mark mark = save();
    if (lower(token()) == "offsets") {
      read_cells_51(a, b, keep, strip);
      return;
    }
    restore(mark);
    const VtkType int32{4, VtkKind::kSigned};
    start_binary_block();
    check_fits(b, min_value_bytes(int32), "cell array size");
    if (a > b) throw error("cell count exceeds the cell array size");
    if (!keep) {
      skip_values(int32, b, "cell array size");
      return;
    }
    std::uint64_t used = 0;
    std::vector<std::uint32_t> cell;
    for (std::uint64_t c = 0; c < a; ++c) {
      const std::int64_t n = read_int(int32);
      if (n < 0) throw error("negative cell size");
      if (static_cast<std::uint64_t>(n) >= b - used) throw error("cells overrun the declared cell array size");
      used += 1 + static_cast<std::uint64_t>(n);
      cell.clear();
      for (std::int64_t k = 0; k < n; ++k) cell.push_back(check_index(read_int(int32)));
      emit(cell, strip);
    }
    if (used != b) throw error("cells do not fill the declared cell array size");
  }

  void read_cells_51(std::uint64_t n_offsets, std::uint64_t n_conn, bool keep, bool strip) {
    const std::optional<VtkType> otype = parse_vtk_type(required("offset type"));
    if (!otype || otype->kind == VtkKind::kFloat) throw error("bad OFFSETS data type");
    start_binary_block();
    check_fits(n_offsets, min_value_bytes(*otype), "OFFSETS");
    std::vector<std::uint64_t> offsets;
    offsets.reserve(static_cast<std::size_t>(keep ? n_offsets : 0));
    std::uint64_t prev = 0;
    for (std::uint64_t i = 0; i < n_offsets; ++i) {
      const std::int64_t o = read_int(*otype);
      if (o < 0 || static_cast<std::uint64_t>(o) < prev || static_cast<std::uint64_t>(o) > n_conn ||
          (i == 0 && o != 0))
        throw error("OFFSETS must start at 0 and increase up to the connectivity size");
      prev = static_cast<std::uint64_t>(o);
      if (keep) offsets.push_back(prev);
    }
    if (n_offsets > 0 && prev != n_conn) {
      throw error("last offset " + std::to_string(prev) + " differs from the connectivity size " +
                  std::to_string(n_conn));
    }
    if (n_offsets == 0 && n_conn != 0) throw error("connectivity without offsets");
    if (lower(required("CONNECTIVITY")) != "connectivity") throw error("expected CONNECTIVITY");
    const std::optional<VtkType> ctype = parse_vtk_type(required("connectivity type"));
    if (!ctype || ctype->kind == VtkKind::kFloat) throw error("bad CONNECTIVITY data type");
    start_binary_block();
    if (!keep) {
      skip_values(*ctype, n_conn, "CONNECTIVITY");
      return;
    }
    check_fits(n_conn, min_value_bytes(*ctype), "CONNECTIVITY");
    std::vector<std::uint32_t> cell;
    for (std::size_t c = 0; c + 1 < offsets.size(); ++c) {
      cell.clear();
      for (std::uint64_t k = offsets[c]; k < offsets[c + 1]; ++k) cell.push_back(check_index(read_int(*ctype)));
      emit(cell, strip);
    }
  }

  /// FIELD name n, then n arrays "name components tuples type" with their values.
  void skip_field() {
    required("field name");
    const std::uint64_t arrays = count("field array count");
    for (std::uint64_t i = 0; i < arrays; ++i) {
      const std::string array_name(required("array name"));
      if (lower(array_name) == "null_array") continue;
      const std::uint64_t components = count("component count");
      const std::uint64_t tuples = count("tuple count");
      const std::string_view type_name = required("array type");
      const std::optional<VtkType> type = parse_vtk_type(type_name);
      if (!type) throw error("unsupported FIELD array type '" + std::string(type_name) + "'");
      if (components != 0 && tuples > std::numeric_limits<std::uint64_t>::max() / components)
        throw error("FIELD array too large");
      start_binary_block();
      skip_values(*type, components * tuples, "FIELD array");
      const Mark mark = save();
      if (lower(token()) == "metadata") skip_metadata();
      else restore(mark);
    }
  }

  /// METADATA blocks (5.1) run to the next empty line.
  void skip_metadata() {
    raw_line();  // the rest of the METADATA line
    while (pos_ < bytes_.size()) {
      const std::string_view line = raw_line();
      if (std::all_of(line.begin(), line.end(), is_space)) break;
    }
  }

  std::string_view bytes_;
  const std::string& name_;
  std::size_t pos_ = 0;
  std::uint64_t line_ = 1;
  std::size_t tok_pos_ = 0;
  std::uint64_t tok_line_ = 1;
  bool binary_ = false;
  TriMesh mesh_;
};

}  // namespace

TriMesh read_vtk(std::string_view bytes, const std::string& name) {
  VtkReader reader(bytes, name);
  return reader.read();
}

}  // namespace trocar
