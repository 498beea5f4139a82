// Recursive-descent parser for the VRML97 subset the mesh reader needs.
//
// Policy for what it does not model:
// - Known nodes (Group, Transform, Anchor, Billboard, Collision, Switch, Shape,
//   IndexedFaceSet, Coordinate): fields that do not matter for geometry are skipped by value
//   shape (bracketed list, string, run of numbers, single word, or a node statement).
// - Any other node type (Appearance, Box, Inline, Script, PROTO instances...) is skipped by
//   brace matching; DEF names inside it are remembered, so a later USE of them is valid and
//   adds no geometry.
// - PROTO / EXTERNPROTO declarations and ROUTE statements are skipped wherever a statement
//   may appear.
// - An unbalanced or mismatched bracket, an unknown USE name, a malformed number, a NaN or
//   an out-of-range coordIndex is an error with the line it was found on.
#include "trocar/mesh/io/vrml_parser.h"

#include <charconv>
#include <cmath>
#include <unordered_map>

#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/io/vrml_lexer.h"

namespace trocar::vrml {
namespace {

const char* describe(TokenKind k) {
  switch (k) {
    case TokenKind::kWord: return "word";
    case TokenKind::kString: return "string";
    case TokenKind::kOpenBrace: return "'{'";
    case TokenKind::kCloseBrace: return "'}'";
    case TokenKind::kOpenBracket: return "'['";
    case TokenKind::kCloseBracket: return "']'";
    case TokenKind::kEnd: return "end of file";
  }
  return "token";
}

std::string describe(const Token& t) {
  return t.kind == TokenKind::kWord ? quote(t.text) : describe(t.kind);
}

bool looks_numeric(std::string_view w) {
  if (w.empty()) return false;
  const char c = w[0];
  return (c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.';
}

class Parser {
 public:
  Parser(std::string_view bytes, const std::string& name) : lex_(bytes, name) {}

  std::vector<NodePtr> parse() {
    std::vector<NodePtr> roots;
    for (;;) {
      const Token& t = lex_.peek();
      if (t.kind == TokenKind::kEnd) break;
      if (t.kind != TokenKind::kWord)
        throw lex_.error(t.line, "unexpected " + describe(t) + " at top level");
      if (NodePtr n = statement()) roots.push_back(std::move(n));
    }
    return roots;
  }

 private:
  // --- statements and nodes ----------------------------------------------------------------

  /// A node statement, PROTO, EXTERNPROTO or ROUTE; returns the node or null.
  NodePtr statement() {
    const Token& t = lex_.peek();
    if (t.kind == TokenKind::kWord) {
      if (t.text == "PROTO") { skip_proto(); return nullptr; }
      if (t.text == "EXTERNPROTO") { skip_externproto(); return nullptr; }
      if (t.text == "ROUTE") { skip_route(); return nullptr; }
    }
    return node_statement();
  }

  /// DEF name Node | USE name | NULL | Node.
  NodePtr node_statement() {
    const Token t = lex_.next();
    if (t.kind != TokenKind::kWord) throw lex_.error(t.line, "expected a node, found " + describe(t));
    if (t.text == "NULL") return nullptr;
    if (t.text == "USE") {
      const Token n = word("a name after USE");
      const auto it = defs_.find(std::string(n.text));
      if (it == defs_.end()) throw lex_.error(n.line, "USE of unknown name " + quote(n.text));
      return it->second;
    }
    if (t.text == "DEF") {
      const Token n = word("a name after DEF");
      const Token type = word("a node type after DEF " + std::string(n.text));
      NodePtr node = node_body(type);
      defs_[std::string(n.text)] = node;
      return node;
    }
    return node_body(t);
  }

  /// The node whose type name was just read: `{ fields }`.
  NodePtr node_body(const Token& type) {
    const Token open = lex_.next();
    if (open.kind != TokenKind::kOpenBrace)
      throw lex_.error(open.line, "expected '{' after node type " + quote(type.text) + ", found " + describe(open));
    if (++depth_ > kMaxDepth)
      throw lex_.error(type.line, "nodes nested deeper than " + std::to_string(kMaxDepth));
    auto node = std::make_shared<Node>();
    node->line = type.line;
    const std::string_view ty = type.text;
    if (ty == "Group" || ty == "Anchor" || ty == "Billboard" || ty == "Collision") {
      node->kind = Node::Kind::kGroup;
    } else if (ty == "Transform") {
      node->kind = Node::Kind::kTransform;
    } else if (ty == "Switch") {
      node->kind = Node::Kind::kSwitch;
    } else if (ty == "Shape") {
      node->kind = Node::Kind::kShape;
    } else if (ty == "IndexedFaceSet") {
      node->kind = Node::Kind::kFaceSet;
    } else if (ty == "Coordinate") {
      node->kind = Node::Kind::kCoordinate;
    } else {
      skip_to_close(open);
      --depth_;
      return nullptr;
    }
    TransformFields tf;
    std::vector<std::uint64_t> index_lines;
    for (;;) {
      const Token& ahead = lex_.peek();
      if (ahead.kind == TokenKind::kWord &&
          (ahead.text == "ROUTE" || ahead.text == "PROTO" || ahead.text == "EXTERNPROTO")) {
        statement();
        continue;
      }
      const Token f = lex_.next();
      if (f.kind == TokenKind::kCloseBrace) break;
      if (f.kind == TokenKind::kEnd)
        throw lex_.error(open.line, "end of file inside " + quote(ty) + ": its '{' here is never closed");
      if (f.kind != TokenKind::kWord)
        throw lex_.error(f.line, "expected a field name in " + quote(ty) + ", found " + describe(f));
      field(*node, f, tf, index_lines);
    }
    if (node->kind == Node::Kind::kTransform) finish_transform(*node, tf);
    if (node->kind == Node::Kind::kFaceSet) check_face_set(*node, index_lines);
    --depth_;
    return node;
  }

  struct TransformFields {
    Vec3 translation = Vec3::Zero(), center = Vec3::Zero(), scale = Vec3::Ones();
    Eigen::Vector4d rotation{0, 0, 1, 0}, scale_orientation{0, 0, 1, 0};
  };

  void field(Node& node, const Token& f, TransformFields& tf, std::vector<std::uint64_t>& index_lines) {
    const std::string_view n = f.text;
    switch (node.kind) {
      case Node::Kind::kTransform:
        if (n == "translation") return numbers(tf.translation.data(), 3);
        if (n == "center") return numbers(tf.center.data(), 3);
        if (n == "scale") return numbers(tf.scale.data(), 3);
        if (n == "rotation") return numbers(tf.rotation.data(), 4);
        if (n == "scaleOrientation") return numbers(tf.scale_orientation.data(), 4);
        [[fallthrough]];
      case Node::Kind::kGroup:
        if (n == "children") return node_list(node.children);
        break;
      case Node::Kind::kSwitch:
        if (n == "choice" || n == "children") return node_list(node.children);
        if (n == "whichChoice") return int32_value(node.which_choice);
        break;
      case Node::Kind::kShape:
        if (n == "geometry") { node.geometry = node_statement(); return; }
        break;
      case Node::Kind::kFaceSet:
        if (n == "coord") { node.coord = node_statement(); return; }
        if (n == "coordIndex") return int_list(node.coord_index, index_lines);
        if (n == "ccw") { node.ccw = bool_value(); return; }
        break;
      case Node::Kind::kCoordinate:
        if (n == "point") return vec3_list(node.points);
        break;
    }
    skip_value(f);
  }

  // --- values --------------------------------------------------------------------------------

  Token word(const std::string& what) {
    const Token t = lex_.next();
    if (t.kind != TokenKind::kWord) throw lex_.error(t.line, "expected " + what + ", found " + describe(t));
    return t;
  }

  double number() {
    const Token t = lex_.next();
    if (t.kind != TokenKind::kWord) throw lex_.error(t.line, "expected a number, found " + describe(t));
    std::string_view s = t.text;
    if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
    double v = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || ptr != s.data() + s.size())
      throw lex_.error(t.line, "expected a number, found " + quote(t.text));
    if (!std::isfinite(v)) throw lex_.error(t.line, "number " + quote(t.text) + " is not finite");
    return v;
  }

  std::int32_t int32(const Token& t) {
    if (t.kind != TokenKind::kWord) throw lex_.error(t.line, "expected an integer, found " + describe(t));
    std::string_view s = t.text;
    bool negative = false;
    if (!s.empty() && (s[0] == '+' || s[0] == '-')) {
      negative = s[0] == '-';
      s.remove_prefix(1);
    }
    int base = 10;
    if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
      base = 16;
      s.remove_prefix(2);
    }
    std::int64_t v = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v, base);
    if (ec != std::errc() || ptr != s.data() + s.size() || s.empty() || s[0] == '-' || s[0] == '+')
      throw lex_.error(t.line, "expected an integer, found " + quote(t.text));
    if (negative) v = -v;
    if (v < INT32_MIN || v > INT32_MAX) throw lex_.error(t.line, "integer " + quote(t.text) + " out of range");
    return static_cast<std::int32_t>(v);
  }

  void numbers(double* out, int n) {
    for (int i = 0; i < n; ++i) out[i] = number();
  }

  void int32_value(int& out) { out = int32(lex_.next()); }

  bool bool_value() {
    const Token t = lex_.next();
    if (t.kind == TokenKind::kWord && t.text == "TRUE") return true;
    if (t.kind == TokenKind::kWord && t.text == "FALSE") return false;
    throw lex_.error(t.line, "expected TRUE or FALSE, found " + describe(t));
  }

  /// MFInt32: `[ i, j, ... ]` or a single value.
  void int_list(std::vector<std::int32_t>& out, std::vector<std::uint64_t>& lines) {
    out.clear();
    lines.clear();
    if (lex_.peek().kind != TokenKind::kOpenBracket) {
      const Token t = lex_.next();
      out.push_back(int32(t));
      lines.push_back(t.line);
      return;
    }
    const Token open = lex_.next();
    for (;;) {
      const Token t = lex_.next();
      if (t.kind == TokenKind::kCloseBracket) return;
      if (t.kind == TokenKind::kEnd) throw unclosed(open);
      out.push_back(int32(t));
      lines.push_back(t.line);
    }
  }

  /// MFVec3f: `[ x y z, ... ]` or a single value.
  void vec3_list(std::vector<Vec3>& out) {
    out.clear();
    if (lex_.peek().kind != TokenKind::kOpenBracket) {
      Vec3 p;
      numbers(p.data(), 3);
      out.push_back(p);
      return;
    }
    const Token open = lex_.next();
    for (;;) {
      const Token& t = lex_.peek();
      if (t.kind == TokenKind::kCloseBracket) {
        lex_.next();
        return;
      }
      if (t.kind == TokenKind::kEnd) throw unclosed(open);
      Vec3 p;
      for (int k = 0; k < 3; ++k) {
        if (k > 0 && lex_.peek().kind == TokenKind::kCloseBracket)
          throw lex_.error(lex_.peek().line, "point list length is not a multiple of 3");
        p[k] = number();
      }
      out.push_back(p);
    }
  }

  /// MFNode: `[ statements ]` or a single node statement. Null entries (NULL, skipped node
  /// types) are kept so that Switch's whichChoice counts them.
  void node_list(std::vector<NodePtr>& out) {
    out.clear();
    if (lex_.peek().kind != TokenKind::kOpenBracket) {
      out.push_back(statement());
      return;
    }
    const Token open = lex_.next();
    for (;;) {
      const Token& t = lex_.peek();
      if (t.kind == TokenKind::kCloseBracket) {
        lex_.next();
        return;
      }
      if (t.kind == TokenKind::kEnd) throw unclosed(open);
      const bool is_node = t.kind == TokenKind::kWord && t.text != "ROUTE" && t.text != "PROTO" &&
                           t.text != "EXTERNPROTO";
      NodePtr n = statement();
      if (is_node) out.push_back(std::move(n));
    }
  }

  /// Skips the value of a field this parser does not use, by its shape.
  void skip_value(const Token& field_name) {
    const Token& t = lex_.peek();
    switch (t.kind) {
      case TokenKind::kString:
        lex_.next();
        return;
      case TokenKind::kOpenBracket: {
        const Token open = lex_.next();
        for (;;) {
          const Token& u = lex_.peek();
          if (u.kind == TokenKind::kCloseBracket) {
            lex_.next();
            return;
          }
          if (u.kind == TokenKind::kEnd) throw unclosed(open);
          if (u.kind == TokenKind::kString || (u.kind == TokenKind::kWord && looks_numeric(u.text))) {
            lex_.next();
          } else if (u.kind == TokenKind::kWord) {
            statement();  // MFNode: DEF/USE/NULL/Type { }
          } else {
            throw lex_.error(u.line, "unexpected " + describe(u) + " in the value of " + quote(field_name.text));
          }
        }
      }
      case TokenKind::kWord: {
        if (looks_numeric(t.text)) {
          while (lex_.peek().kind == TokenKind::kWord && looks_numeric(lex_.peek().text)) lex_.next();
          return;
        }
        if (t.text == "TRUE" || t.text == "FALSE" || t.text == "NULL") {
          lex_.next();
          return;
        }
        if (t.text == "IS") {
          lex_.next();
          word("a field name after IS");
          return;
        }
        if (t.text == "DEF" || t.text == "USE" || lex_.peek(1).kind == TokenKind::kOpenBrace) {
          node_statement();  // SFNode
          return;
        }
        lex_.next();  // some other single-word value
        return;
      }
      default:
        throw lex_.error(t.line, "missing value for field " + quote(field_name.text) + ", found " + describe(t));
    }
  }

  // --- structural skipping -----------------------------------------------------------------

  FileError unclosed(const Token& open) const {
    return lex_.error(open.line, std::string(describe(open.kind)) + " opened here is never closed");
  }

  /// Skips to the bracket that closes `open` (just consumed), checking that brackets match and
  /// remembering DEF names on the way (as nodes without geometry).
  void skip_to_close(const Token& open) {
    std::vector<Token> stack{open};
    while (!stack.empty()) {
      const Token t = lex_.next();
      switch (t.kind) {
        case TokenKind::kEnd: throw unclosed(stack.back());
        case TokenKind::kOpenBrace:
        case TokenKind::kOpenBracket: stack.push_back(t); break;
        case TokenKind::kCloseBrace:
        case TokenKind::kCloseBracket: {
          const bool brace = t.kind == TokenKind::kCloseBrace;
          if ((stack.back().kind == TokenKind::kOpenBrace) != brace)
            throw lex_.error(t.line, std::string("mismatched ") + describe(t.kind) + ": " +
                                         describe(stack.back().kind) + " opened at line " +
                                         std::to_string(stack.back().line));
          stack.pop_back();
          break;
        }
        case TokenKind::kWord:
          if (t.text == "DEF" && lex_.peek().kind == TokenKind::kWord)
            defs_.emplace(std::string(lex_.peek().text), nullptr);
          break;
        case TokenKind::kString: break;
      }
    }
  }

  void expect_open(TokenKind kind, const char* context) {
    const Token t = lex_.next();
    if (t.kind != kind)
      throw lex_.error(t.line, std::string("expected ") + describe(kind) + " in " + context + ", found " + describe(t));
    skip_to_close(t);
  }

  void skip_proto() {
    lex_.next();  // PROTO
    word("a name after PROTO");
    expect_open(TokenKind::kOpenBracket, "PROTO interface");
    expect_open(TokenKind::kOpenBrace, "PROTO body");
  }

  void skip_externproto() {
    const Token kw = lex_.next();  // EXTERNPROTO
    word("a name after EXTERNPROTO");
    expect_open(TokenKind::kOpenBracket, "EXTERNPROTO interface");
    skip_value(kw);  // URL string(s)
  }

  void skip_route() {
    lex_.next();  // ROUTE
    word("a node.event after ROUTE");
    const Token to = word("TO");
    if (to.text != "TO") throw lex_.error(to.line, "expected TO in ROUTE, found " + quote(to.text));
    word("a node.event after TO");
  }

  // --- node post-processing ----------------------------------------------------------------

  /// VRML97 §6.52: P' = T·C·R·SR·S·SR⁻¹·C⁻¹·P.
  void finish_transform(Node& node, const TransformFields& tf) {
    auto rotation = [](const Eigen::Vector4d& r) {
      const Vec3 axis = r.head<3>();
      const double len = axis.norm();
      if (len == 0.0 || r[3] == 0.0) return Mat3::Identity().eval();
      return Eigen::AngleAxisd(r[3], axis / len).toRotationMatrix();
    };
    const Mat3 rot = rotation(tf.rotation);
    const Mat3 sr = rotation(tf.scale_orientation);
    Eigen::Affine3d m = Eigen::Affine3d::Identity();
    m.linear() = rot * sr * tf.scale.asDiagonal() * sr.transpose();
    m.translation() = tf.translation + tf.center - m.linear() * tf.center;
    node.transform = m;
    node.identity = m.matrix() == Eigen::Matrix4d::Identity();
    if (!m.matrix().allFinite()) throw lex_.error(node.line, "Transform is not finite");
  }

  void check_face_set(Node& node, const std::vector<std::uint64_t>& lines) {
    std::size_t n_points = 0;
    if (node.coord) {
      if (node.coord->kind != Node::Kind::kCoordinate)
        throw lex_.error(node.line, "IndexedFaceSet coord must be a Coordinate node");
      n_points = node.coord->points.size();
    }
    for (std::size_t i = 0; i < node.coord_index.size(); ++i) {
      const std::int32_t idx = node.coord_index[i];
      if (idx < -1) throw lex_.error(lines[i], "coordIndex " + std::to_string(idx) + " is below -1");
      if (node.coord && idx >= 0 && static_cast<std::size_t>(idx) >= n_points)
        throw lex_.error(lines[i], "coordIndex " + std::to_string(idx) + " out of range (" +
                                       std::to_string(n_points) + " points)");
    }
  }

  Lexer lex_;
  std::unordered_map<std::string, NodePtr> defs_;
  int depth_ = 0;
};

}  // namespace

std::vector<NodePtr> parse_scene(std::string_view bytes, const std::string& name) {
  Parser parser(bytes, name);
  return parser.parse();
}

}  // namespace trocar::vrml
