#include "trocar/render/renderer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"
#include "trocar/render/offscreen.h"
#include "trocar/render/shaders.h"

namespace trocar {
namespace {

/// The weave's repeat (m): a large-pore lightweight polypropylene mesh, pores ~ 2 mm between
/// filaments (docs/render.md, "Appearance").
constexpr float kWeavePeriod = 3e-3f;
/// Titanium, as the tacks are.
const Eigen::Vector3f kTitanium(0.56f, 0.56f, 0.58f);

GLuint compile(GLenum type, const char* source, const char* name) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    throw Error(std::string("render: shader ") + name + " does not compile: " + log);
  }
  return s;
}

GLuint link(const char* vertex, const char* fragment, const char* name) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex, name);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment, name);
  const GLuint p = glCreateProgram();
  glAttachShader(p, vs);
  glAttachShader(p, fs);
  glLinkProgram(p);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    glDeleteProgram(p);
    throw Error(std::string("render: program ") + name + " does not link: " + log);
  }
  return p;
}

void to_floats(const std::vector<Vec3>& in, std::vector<float>& out) {
  out.resize(3 * in.size());
  for (std::size_t i = 0; i < in.size(); ++i)
    for (int k = 0; k < 3; ++k) out[3 * i + k] = static_cast<float>(in[i][k]);
}

/// A new array buffer of `bytes` (from `data`, or uninitialised when null) bound to the bound
/// vertex array's attribute `location` as three floats per vertex; returns its id.
GLuint attribute_buffer(GLuint location, GLsizeiptr bytes, const void* data, GLenum usage) {
  GLuint id = 0;
  glGenBuffers(1, &id);
  glBindBuffer(GL_ARRAY_BUFFER, id);
  glBufferData(GL_ARRAY_BUFFER, bytes, data, usage);
  glEnableVertexAttribArray(location);
  glVertexAttribPointer(location, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  return id;
}

/// Uploads 4 floats per vertex to the bound vertex array's attribute 3 (what electrosurgery and
/// bleeding did: shaders.h), making its buffer on first use.
void upload_effects(GLuint vao, GLuint& buffer, const std::vector<float>& values) {
  glBindVertexArray(vao);
  if (!buffer) glGenBuffers(1, &buffer);
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(values.size() * sizeof(float)), values.data(), GL_STREAM_DRAW);
  glEnableVertexAttribArray(3);
  glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
  glBindVertexArray(0);
}


/// One indexed mesh on the GPU: positions and normals (dynamic for tissue), texture coordinates,
/// and for a tissue something burnt or bled on, its effects (attribute 3, made on first use).
/// Then its triangles are ordered with those untouched first (plain_count indices), drawn by the
/// default program as ever, and the touched ones after them, drawn by an effects variant: a burn
/// costs only its own pixels, and the rest of the tissue is drawn exactly as before.
struct GpuMesh {
  GLuint vao = 0, positions = 0, normals = 0, texcoords = 0, indices = 0, effects = 0;
  GLsizei index_count = 0;
  GLsizei plain_count = 0;              // the first plain_count indices: triangles without effects
  std::vector<std::uint8_t> touched;    // per triangle, as the index buffer is ordered now
  std::vector<std::uint32_t> order;     // scratch
  std::vector<Triangle> triangles;
  std::vector<Vec3> local_positions;  // instruments and rigids: fixed
  std::vector<float> scratch_positions, scratch_normals;

  /// `texcoords_xyz`: three floats per vertex for the texture coordinate (null: the positions).
  void create(const std::vector<Vec3>& positions_m, const std::vector<Triangle>& tris, GLenum usage,
              const std::vector<float>* texcoords_xyz = nullptr) {
    triangles = tris;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    const auto buffer = [](GLuint& id, GLuint location, const std::vector<float>& data, GLenum use) {
      id = attribute_buffer(location, GLsizeiptr(data.size() * sizeof(float)), data.data(), use);
    };
    to_floats(positions_m, scratch_positions);
    vertex_normals(positions_m, tris, scratch_normals);
    buffer(this->positions, 0, scratch_positions, usage);
    buffer(normals, 1, scratch_normals, usage);
    // Rest positions: the solid texture's domain (or the weave's plane coordinates).
    buffer(texcoords, 2, texcoords_xyz ? *texcoords_xyz : scratch_positions, GL_STATIC_DRAW);
    std::vector<std::uint32_t> idx(3 * tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t)
      for (int k = 0; k < 3; ++k) idx[3 * t + k] = tris[t][k];
    glGenBuffers(1, &indices);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(idx.size() * sizeof(std::uint32_t)), idx.data(), GL_DYNAMIC_DRAW);
    index_count = plain_count = static_cast<GLsizei>(idx.size());
    touched.assign(tris.size(), 0);
    glBindVertexArray(0);
  }
  void update(const std::vector<Vec3>& positions_m) {
    to_floats(positions_m, scratch_positions);
    vertex_normals(positions_m, triangles, scratch_normals);
    glBindBuffer(GL_ARRAY_BUFFER, positions);
    glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(scratch_positions.size() * sizeof(float)), scratch_positions.data());
    glBindBuffer(GL_ARRAY_BUFFER, normals);
    glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(scratch_normals.size() * sizeof(float)), scratch_normals.data());
  }
  /// Uploads the effects (4 floats per vertex) and orders the triangles: untouched (all three
  /// corners zero), then touched.
  void set_effects(const std::vector<float>& per_vertex) {
    upload_effects(vao, effects, per_vertex);
    bool changed = false;
    GLsizei plain = 0;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      bool any = false;
      for (const std::uint32_t v : triangles[t])
        for (int k = 0; k < 4; ++k) any = any || per_vertex[4 * v + std::size_t(k)] != 0.0f;
      changed = changed || (touched[t] != 0) != any;
      touched[t] = any ? 1 : 0;
      plain += any ? 0 : 3;
    }
    if (changed) reorder(plain);
  }
  /// Back to the original order, all triangles plain.
  void clear_effects() {
    if (plain_count == index_count) return;
    std::fill(touched.begin(), touched.end(), std::uint8_t(0));
    reorder(index_count);
  }
  void reorder(GLsizei plain) {
    order.clear();
    for (const int pass : {0, 1})
      for (std::size_t t = 0; t < triangles.size(); ++t)
        if (touched[t] == pass) order.insert(order.end(), triangles[t].begin(), triangles[t].end());
    glBindVertexArray(vao);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices);
    glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, GLsizeiptr(order.size() * sizeof(std::uint32_t)), order.data());
    glBindVertexArray(0);
    plain_count = plain;
  }
  void draw() const {
    glBindVertexArray(vao);
    glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);
  }
  /// The plain triangles, or the touched ones.
  void draw_part(bool touched_part) const {
    const GLsizei first = touched_part ? plain_count : 0, count = touched_part ? index_count - plain_count : plain_count;
    if (count <= 0) return;
    glBindVertexArray(vao);
    glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT,
                   reinterpret_cast<const void*>(std::uintptr_t(first) * sizeof(std::uint32_t)));
  }
  void destroy() {
    const GLuint buffers[] = {positions, normals, texcoords, indices, effects};
    glDeleteBuffers(5, buffers);
    glDeleteVertexArrays(1, &vao);
    *this = GpuMesh{};
  }
};

/// A rest position's bits (−0 as +0), for matching positions a cut copied exactly.
std::array<std::uint64_t, 3> position_bits(const Vec3& p) {
  std::array<std::uint64_t, 3> bits{};
  for (int k = 0; k < 3; ++k) {
    const double x = p[k] + 0.0;
    std::memcpy(&bits[std::size_t(k)], &x, sizeof x);
  }
  return bits;
}

/// A triangle's three corners' rest positions, in its corner order.
struct CornerKey {
  std::array<std::uint64_t, 9> bits;
  bool operator==(const CornerKey&) const = default;
};
struct CornerKeyHash {
  std::size_t operator()(const CornerKey& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (const std::uint64_t w : k.bits) h = (h ^ w) * 1099511628211ull;
    return std::size_t(h ^ (h >> 31));
  }
};
CornerKey corner_key(const std::vector<Vec3>& rest, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  CornerKey k{};
  const std::uint32_t corners[] = {a, b, c};
  for (int i = 0; i < 3; ++i) {
    const auto bits = position_bits(rest[corners[i]]);
    for (int d = 0; d < 3; ++d) k.bits[std::size_t(3 * i + d)] = bits[std::size_t(d)];
  }
  return k;
}

/// A tissue drawn with the mesh's own UVs: UVs are per triangle corner, so the GPU gets one
/// vertex per corner, gathered from the deformed positions and smooth normals every frame.
struct TexturedMesh {
  GLuint vao = 0, positions = 0, normals = 0, texcoords = 0, texture = 0, effects = 0;
  std::vector<Triangle> triangles;
  std::vector<Vec2> uv;  // per corner
  std::vector<float> vertex_normals_xyz, corner_positions, corner_normals, corner_effects;

  void create(const std::vector<Vec3>& rest, const std::vector<Triangle>& tris, const std::vector<Vec2>& corner_uv,
              const Image& image) {
    create_buffers(tris, corner_uv);
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8, image.width, image.height, 0, GL_RGB, GL_UNSIGNED_BYTE, image.rgb.data());
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    update(rest);
  }
  void create_buffers(const std::vector<Triangle>& tris, const std::vector<Vec2>& corner_uv) {
    triangles = tris;
    uv = corner_uv;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    const std::size_t n = 3 * tris.size();
    std::vector<float> st(3 * n);
    for (std::size_t c = 0; c < n; ++c) {
      st[3 * c] = float(uv[c].x());
      st[3 * c + 1] = float(1.0 - uv[c].y());  // image rows go top to bottom, v goes up
      st[3 * c + 2] = 0;
    }
    positions = attribute_buffer(0, GLsizeiptr(3 * n * sizeof(float)), nullptr, GL_DYNAMIC_DRAW);
    normals = attribute_buffer(1, GLsizeiptr(3 * n * sizeof(float)), nullptr, GL_DYNAMIC_DRAW);
    texcoords = attribute_buffer(2, GLsizeiptr(st.size() * sizeof(float)), st.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);
  }
  void destroy_buffers() {
    const GLuint buffers[] = {positions, normals, texcoords, effects};
    glDeleteBuffers(4, buffers);
    glDeleteVertexArrays(1, &vao);
    vao = positions = normals = texcoords = effects = 0;
  }
  /// After a cut: each remaining triangle takes the UVs of the triangle it was, found by its
  /// corners' rest positions (a cut removes triangles and copies the rest positions of the
  /// vertices it splits). Returns false when a triangle is not one of `before`'s (the caller
  /// then draws the tissue with the default solid texture).
  bool remodel(const std::vector<Vec3>& before_rest, const std::vector<Vec3>& rest, const std::vector<Triangle>& tris) {
    if (uv.size() != 3 * triangles.size()) return false;
    std::unordered_map<CornerKey, std::uint32_t, CornerKeyHash> was;  // rotation r in the top bits
    was.reserve(3 * triangles.size());
    for (std::size_t o = 0; o < triangles.size(); ++o) {
      const Triangle& f = triangles[o];
      if (f[0] >= before_rest.size() || f[1] >= before_rest.size() || f[2] >= before_rest.size()) return false;
      for (std::uint32_t r = 0; r < 3; ++r)
        was.try_emplace(corner_key(before_rest, f[r], f[(r + 1) % 3], f[(r + 2) % 3]), std::uint32_t(o) | (r << 30));
    }
    std::vector<Vec2> corner_uv(3 * tris.size());
    for (std::size_t t = 0; t < tris.size(); ++t) {
      const auto it = was.find(corner_key(rest, tris[t][0], tris[t][1], tris[t][2]));
      if (it == was.end()) return false;
      const std::uint32_t o = it->second & 0x3fffffffu, r = it->second >> 30;
      for (std::uint32_t k = 0; k < 3; ++k) corner_uv[3 * t + k] = uv[3 * o + (r + k) % 3];
    }
    destroy_buffers();
    create_buffers(tris, corner_uv);
    return true;
  }
  void update(const std::vector<Vec3>& x) {
    vertex_normals(x, triangles, vertex_normals_xyz);
    corner_positions.resize(9 * triangles.size());
    corner_normals.resize(9 * triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = triangles[t][k];
        for (int d = 0; d < 3; ++d) {
          corner_positions[9 * t + 3 * k + d] = float(x[v][d]);
          corner_normals[9 * t + 3 * k + d] = vertex_normals_xyz[3 * v + d];
        }
      }
    glBindBuffer(GL_ARRAY_BUFFER, positions);
    glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(corner_positions.size() * sizeof(float)), corner_positions.data());
    glBindBuffer(GL_ARRAY_BUFFER, normals);
    glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(corner_normals.size() * sizeof(float)), corner_normals.data());
  }
  /// Per-vertex effects gathered to the corners.
  void set_effects(const std::vector<float>& per_vertex) {
    corner_effects.resize(12 * triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t)
      for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 4; ++d) corner_effects[12 * t + 4 * k + d] = per_vertex[4 * triangles[t][k] + d];
    upload_effects(vao, effects, corner_effects);
  }
  void draw() const {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, texture);
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(3 * triangles.size()));
  }
  void destroy() {
    destroy_buffers();
    glDeleteTextures(1, &texture);
  }
};

/// The best-fitting plane of a set of rest positions: their mean and the two principal axes of
/// their spread.
struct PlaneFrame {
  Vec3 mean = Vec3::Zero(), u = Vec3::UnitX(), v = Vec3::UnitY();
};
PlaneFrame plane_frame(const std::vector<Vec3>& rest) {
  PlaneFrame f;
  for (const Vec3& p : rest) f.mean += p;
  f.mean /= Real(std::max<std::size_t>(1, rest.size()));
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  for (const Vec3& p : rest) spread += (p - f.mean) * (p - f.mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(spread);  // eigenvalues ascending
  f.u = axes.eigenvectors().col(2);
  f.v = axes.eigenvectors().col(1);
  return f;
}

/// Rest positions in a plane (by default their best-fitting one), as xyz floats with z = 0, in
/// metres: the weave's domain, so it stays on the cloth as it deforms. A cut tissue keeps the
/// plane it had, so the weave does not shift.
std::vector<float> plane_coordinates(const std::vector<Vec3>& rest, const PlaneFrame& f) {
  std::vector<float> out(3 * rest.size(), 0.0f);
  for (std::size_t i = 0; i < rest.size(); ++i) {
    out[3 * i] = float((rest[i] - f.mean).dot(f.u));
    out[3 * i + 1] = float((rest[i] - f.mean).dot(f.v));
  }
  return out;
}
std::vector<float> plane_coordinates(const std::vector<Vec3>& rest) { return plane_coordinates(rest, plane_frame(rest)); }

const Appearance& look_of(const std::vector<Appearance>& looks, std::size_t i) {
  static const Appearance kDefaultLook;
  return i < looks.size() ? looks[i] : kDefaultLook;
}

Eigen::Vector3f to_vector(const std::array<float, 3>& c) { return {c[0], c[1], c[2]}; }

/// Drawn in the translucent pass (the id pass draws everything opaque).
bool translucent(const RenderOptions& o, const Appearance& a) { return !o.id_colors && a.given && a.opacity < 1; }
/// Not drawn at all.
bool invisible(const RenderOptions& o, const Appearance& a) { return !o.id_colors && a.given && a.opacity <= 0; }
/// The mesh's own texture image is used.
bool default_pattern(const Appearance& a) { return !a.given || a.pattern == SurfacePattern::kDefault; }

/// Appends a closed tube of `sides` around the polyline `centre` (with `across`, per point, a
/// unit vector normal to the line there), capped at both ends.
void append_tube(TriMesh& m, const std::vector<Vec3>& centre, const std::vector<Vec3>& across, Real radius, int sides) {
  const auto base = static_cast<std::uint32_t>(m.positions.size());
  const std::size_t n = centre.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 t = (centre[std::min(i + 1, n - 1)] - centre[i > 0 ? i - 1 : 0]).normalized();
    const Vec3 a = across[i], b = t.cross(a);
    for (int k = 0; k < sides; ++k) {
      const Real phi = 2 * 3.14159265358979323846 * k / sides;
      m.positions.push_back(centre[i] + radius * (std::cos(phi) * a + std::sin(phi) * b));
    }
  }
  const auto at = [&](std::size_t i, int k) { return base + std::uint32_t(i * std::size_t(sides) + std::size_t(k % sides)); };
  for (std::size_t i = 0; i + 1 < n; ++i)
    for (int k = 0; k < sides; ++k) {
      m.triangles.push_back({at(i, k), at(i, k + 1), at(i + 1, k + 1)});
      m.triangles.push_back({at(i, k), at(i + 1, k + 1), at(i + 1, k)});
    }
  const auto cap_first = static_cast<std::uint32_t>(m.positions.size());
  m.positions.push_back(centre.front());
  m.positions.push_back(centre.back());
  for (int k = 0; k < sides; ++k) {
    m.triangles.push_back({cap_first, at(0, k + 1), at(0, k)});
    m.triangles.push_back({cap_first + 1, at(n - 1, k), at(n - 1, k + 1)});
  }
}

Eigen::Matrix4f pose_matrix(const Pose& pose) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<3, 3>(0, 0) = pose.rotation_matrix();
  m.block<3, 1>(0, 3) = pose.translation;
  return m.cast<float>();
}

// Overlay geometry, as xyz floats appended to a line (or point) list.
void push_point(std::vector<float>& v, const Vec3& a) {
  v.push_back(float(a.x()));
  v.push_back(float(a.y()));
  v.push_back(float(a.z()));
}

// The twelve edges of a box whose corner i (bit 0: +x, bit 1: +y, bit 2: +z) is corner(i).
template <class Corner>
void push_box_edges(std::vector<float>& v, const Corner& corner) {
  for (int i = 0; i < 8; ++i)
    for (int bit : {1, 2, 4})
      if (!(i & bit)) {
        push_point(v, corner(i));
        push_point(v, corner(i | bit));
      }
}

// Per instrument in contact, an arrow of the force on the tissue (minus the instrument's) from the
// contact centre, its two barbs in the plane facing the camera.
void push_force_arrows(std::vector<float>& v, const ViewSnapshot& snap, const CameraView& cam, Real force_scale) {
  for (const InstrumentView& iv : snap.instruments) {
    if (iv.contacts == 0 || iv.force.norm() < 1e-6) continue;
    const Vec3 a = iv.contact_centre;
    const Vec3 f = -iv.force * force_scale;
    const Vec3 b = a + f;
    push_point(v, a);
    push_point(v, b);
    const Vec3 dir = f.normalized();
    Vec3 side = dir.cross(cam.forward);
    if (side.norm() < 1e-6) side = dir.cross(cam.up);
    side = side.normalized() * 0.25 * f.norm();
    for (const Vec3& tip : {Vec3(b - 0.35 * f + side), Vec3(b - 0.35 * f - side)}) {
      push_point(v, b);
      push_point(v, tip);
    }
  }
}

// Cells of edge snap.cell_size holding vertices of an instrument and of a tissue: where the OHC
// grid finds potential collisions (by vertex occupancy; the detector hashes triangles' boxes).
void push_shared_cells(std::vector<float>& v, const ViewSnapshot& snap, const std::vector<GpuMesh>& instruments) {
  const Real h = snap.cell_size;
  const auto key = [h](const Vec3& x) {
    const auto c = [h](Real q) { return std::int64_t(std::floor(q / h)) & 0x1fffff; };
    return (c(x.x()) << 42) | (c(x.y()) << 21) | c(x.z());
  };
  std::unordered_set<std::int64_t> instrument_cells, shown;
  for (std::size_t i = 0; i < snap.instruments.size() && i < instruments.size(); ++i)
    for (const Vec3& x : instruments[i].local_positions) instrument_cells.insert(key(snap.instruments[i].pose.apply(x)));
  for (const auto& tissue : snap.tissues)
    for (const Vec3& x : tissue) {
      const std::int64_t k = key(x);
      if (!instrument_cells.count(k) || !shown.insert(k).second) continue;
      const Vec3 lo(std::floor(x.x() / h) * h, std::floor(x.y() / h) * h, std::floor(x.z() / h) * h);
      push_box_edges(v, [&](int j) { return Vec3(lo + h * Vec3((j & 1) ? 1 : 0, (j & 2) ? 1 : 0, (j & 4) ? 1 : 0)); });
    }
}

/// The smoke field's sums (optical depth τ and τ × light, distance, distance²; renderer's
/// prepare_smoke) at several resolutions: level l has pixels 2^l times as wide as level 0's. A
/// puff is splatted at the finest level where its radius is at most kSplatRadius pixels, so each
/// costs at most about π kSplatRadius² pixels (a puff near the scope would otherwise cost the
/// whole field). collapse() then adds every level into level 0: the sums are per pixel (an optical
/// depth along its ray), so a coarse level is interpolated bilinearly, not divided.
class SplatLevels {
 public:
  static constexpr float kSplatRadius = 3.0f;
  static constexpr int kLevels = 4;

  void reset(int width, int height) {
    levels_.resize(kLevels);
    for (int l = 0; l < kLevels; ++l) {
      Level& level = levels_[std::size_t(l)];
      level.width = std::max(1, (width + (1 << l) - 1) >> l);
      level.height = std::max(1, (height + (1 << l) - 1) >> l);
      level.sums.assign(4 * std::size_t(level.width) * std::size_t(level.height), 0.0f);
    }
  }

  /// A puff at (x, y) of radius r (level-0 pixels) and centre alpha α: α (1 − ρ²)² over
  /// its disc, as τ = −ln(1 − alpha), with its light and distance.
  void splat(float x, float y, float r, float alpha, float light, float distance) {
    int l = 0;
    while (l + 1 < kLevels && r > kSplatRadius * float(1 << l)) ++l;
    Level& level = levels_[std::size_t(l)];
    const float s = 1.0f / float(1 << l);
    const float cx = x * s, cy = y * s, radius = std::max(r * s, 0.5f);
    // Splatted at least half a pixel wide, its cover (α r²) kept.
    alpha = std::min(alpha * (r * s) * (r * s) / (radius * radius), 0.999f);
    const std::size_t texels = std::size_t(level.width) * std::size_t(level.height);
    float* const tau_plane = level.sums.data();
    const float inv_r2 = 1.0f / (radius * radius);
    const int j0 = std::max(0, int(std::floor(cy - radius))), j1 = std::min(level.height - 1, int(std::ceil(cy + radius)));
    for (int j = j0; j <= j1; ++j) {
      const float dy = float(j) + 0.5f - cy;
      const float chord2 = radius * radius - dy * dy;
      if (chord2 <= 0) continue;
      const float chord = std::sqrt(chord2);
      const int i0 = std::max(0, int(std::floor(cx - chord))), i1 = std::min(level.width - 1, int(std::ceil(cx + chord)));
      float* const tau_row = tau_plane + std::size_t(j) * std::size_t(level.width);
      float* const light_row = tau_row + texels;
      float* const distance_row = light_row + texels;
      float* const square_row = distance_row + texels;
      const float dy2 = dy * dy, square = distance * distance;
      if (alpha < 0.3f) {
        // −ln(1 − a) to the third order: within 0.6 % below 0.3 (and a ≤ α; this loop vectorises).
        for (int i = i0; i <= i1; ++i) {
          const float dx = float(i) + 0.5f - cx;
          const float q = std::max(0.0f, 1.0f - (dx * dx + dy2) * inv_r2);
          const float a = alpha * q * q;
          const float tau = a * (1.0f + a * (0.5f + a * (1.0f / 3)));
          tau_row[i] += tau;
          light_row[i] += tau * light;
          distance_row[i] += tau * distance;
          square_row[i] += tau * square;
        }
      } else {
        for (int i = i0; i <= i1; ++i) {
          const float dx = float(i) + 0.5f - cx;
          const float q = std::max(0.0f, 1.0f - (dx * dx + dy2) * inv_r2);
          const float tau = -std::log(1.0f - alpha * q * q);
          tau_row[i] += tau;
          light_row[i] += tau * light;
          distance_row[i] += tau * distance;
          square_row[i] += tau * square;
        }
      }
    }
  }

  /// Adds each coarser level into the next finer one, down to level 0; returns level 0's sums
  /// (4 planes of width × height).
  const std::vector<float>& collapse() {
    for (int l = kLevels - 1; l > 0; --l) {
      const Level& coarse = levels_[std::size_t(l)];
      Level& fine = levels_[std::size_t(l - 1)];
      const std::size_t coarse_texels = std::size_t(coarse.width) * std::size_t(coarse.height);
      const std::size_t fine_texels = std::size_t(fine.width) * std::size_t(fine.height);
      bool empty = true;
      for (std::size_t k = 0; k < coarse_texels && empty; ++k) empty = !(coarse.sums[k] > 0);
      if (empty) continue;
      for (int j = 0; j < fine.height; ++j) {
        const float v = std::clamp((float(j) + 0.5f) * 0.5f - 0.5f, 0.0f, float(coarse.height - 1));
        const int v0 = int(v), v1 = std::min(v0 + 1, coarse.height - 1);
        const float fv = v - float(v0);
        for (int i = 0; i < fine.width; ++i) {
          const float u = std::clamp((float(i) + 0.5f) * 0.5f - 0.5f, 0.0f, float(coarse.width - 1));
          const int u0 = int(u), u1 = std::min(u0 + 1, coarse.width - 1);
          const float fu = u - float(u0);
          const std::size_t a = std::size_t(v0) * std::size_t(coarse.width), b = std::size_t(v1) * std::size_t(coarse.width);
          for (int c = 0; c < 4; ++c) {
            const float* plane = &coarse.sums[std::size_t(c) * coarse_texels];
            const float value = (1 - fv) * ((1 - fu) * plane[a + std::size_t(u0)] + fu * plane[a + std::size_t(u1)]) +
                                fv * ((1 - fu) * plane[b + std::size_t(u0)] + fu * plane[b + std::size_t(u1)]);
            fine.sums[std::size_t(c) * fine_texels + std::size_t(j) * std::size_t(fine.width) + std::size_t(i)] += value;
          }
        }
      }
    }
    return levels_[0].sums;
  }

 private:
  struct Level {
    int width = 0, height = 0;
    std::vector<float> sums;  // 4 planes
  };
  std::vector<Level> levels_;
};

}  // namespace

TriMesh make_tack_mesh() {
  // A ProTack-like tack: a coil 4 mm long, 3.5 mm centreline diameter plus a 0.5 mm wire (4 mm
  // across), three turns down into the tissue and a flat head turn with a cross-bar above it.
  constexpr Real kCoil = 1.75e-3, kWire = 0.25e-3, kHead = 0.5e-3, kDepth = 3.5e-3;
  constexpr int kPerTurn = 24, kTurns = 3;
  std::vector<Vec3> centre, across;
  for (int i = 0; i <= (kTurns + 1) * kPerTurn; ++i) {
    const Real turns = Real(i) / kPerTurn;
    const Real angle = 2 * 3.14159265358979323846 * turns;
    const Real z = turns < kTurns ? -kDepth + (kDepth + kHead) * turns / kTurns : kHead;
    const Vec3 radial(std::cos(angle), std::sin(angle), 0);
    centre.push_back(kCoil * radial + Vec3(0, 0, z));
    across.push_back(radial);  // a helix's radial direction is normal to its tangent
  }
  TriMesh m;
  append_tube(m, centre, across, kWire, 8);
  TriMesh bar = make_box(2 * kCoil, 2 * kWire, 2 * kWire);
  for (Vec3& p : bar.positions) p.z() += kHead;
  const auto base = static_cast<std::uint32_t>(m.positions.size());
  m.positions.insert(m.positions.end(), bar.positions.begin(), bar.positions.end());
  for (const Triangle& t : bar.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  return m;
}

void vertex_normals(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                    std::vector<float>& normals_xyz) {
  normals_xyz.assign(3 * positions.size(), 0.0f);
  for (const Triangle& t : triangles) {
    // The cross product's length is twice the area: summing it weights each face by area.
    const Vec3 n = (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]);
    for (std::uint32_t v : t)
      for (int k = 0; k < 3; ++k) normals_xyz[3 * v + k] += static_cast<float>(n[k]);
  }
  for (std::size_t v = 0; v < positions.size(); ++v) {
    float* n = &normals_xyz[3 * v];
    const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len > 0)
      for (int k = 0; k < 3; ++k) n[k] /= len;
  }
}

/// The smoke's puffs are added up (on the CPU) in a field of about this many rows (an integer
/// fraction of the frame's), which the surfaces read: soft puffs need no more, and the splats'
/// pixels are the field's cost (bench_render).
constexpr int kSmokeRows = 72;
/// Smoke's albedo (grey-white, linear); the cavity's darkness (the clear colour, as stored) and
/// its linear value.
const Eigen::Vector3f kSmokeColour(0.64f, 0.64f, 0.62f);
const Eigen::Vector3f kBackground(0.035f, 0.012f, 0.010f);
const Eigen::Vector3f kBackgroundLinear(6.27e-4f, 5.87e-5f, 3.98e-5f);

/// The mesh program's variants (shaders.h): bit 0 TROCAR_LOOKS, bit 1 TROCAR_EFFECTS, bit 2
/// TROCAR_SMOKE.
enum : unsigned { kLooks = 1, kEffects = 2, kSmoke = 4 };
/// Frames the smoke's backdrop waits after a frame where it drew nothing (Gpu::backdrop_query).
constexpr int kBackdropRecheck = 8;

struct Renderer::Gpu {
  /// The mesh program's variants by their bits (kLooks, kEffects, kSmoke), each made when first
  /// needed: the default one (0) and the looks one (kLooks) at construction. Each object is drawn
  /// by the smallest that it needs (under llvmpipe a shader costs all of its code on every
  /// pixel, whichever branch it takes), so a frame where nothing burns, bleeds or smokes is drawn
  /// exactly as before those existed.
  std::array<GLuint, 8> programs{};
  GLuint mesh_program = 0, look_program = 0;  // programs[0], programs[kLooks]
  GLuint overlay_program = 0;
  GLuint backdrop_program = 0;  // the smoke where no surface was drawn (made with the first smoke)
  /// Whether the backdrop drew anything (GL_ANY_SAMPLES_PASSED, read a frame later): where the
  /// scene covers the smoke's part of the frame, it is skipped for kBackdropRecheck frames (under
  /// llvmpipe even the depth test of a pass over the frame costs a few ms).
  GLuint backdrop_query = 0;
  bool backdrop_pending = false;
  int backdrop_skip = 0;
  bool smoke_frame = false;   // this frame has smoke on screen
  GLuint program = 0;         // the mesh program in use this object
  Eigen::Matrix4f model_matrix = Eigen::Matrix4f::Identity();
  GLuint overlay_vao = 0, overlay_vbo = 0;
  std::vector<GpuMesh> tissues, instruments, rigids;
  std::vector<std::unique_ptr<TexturedMesh>> textured;  // per tissue: null = procedural texture
  std::vector<Appearance> tissue_looks, rigid_looks;
  std::vector<Vec3> rigid_centres;
  GpuMesh tack;
  /// The translucent pass's objects this frame: distance from the eye, rigid or tissue, index.
  struct Deferred {
    Real distance;
    bool rigid;
    std::size_t index;
    bool texture;  // a tissue drawn with its texture image
  };
  std::vector<Deferred> deferred;
  std::vector<float> lines;  // overlay scratch
  Real scene_size = 0.1;

  // Cuts, burns, blood, smoke.
  std::vector<TissueModel> models;                   // per tissue: what its buffers were built from
  std::vector<std::optional<PlaneFrame>> weave_frames;  // per tissue with the weave: its plane
  std::vector<std::uint8_t> with_effects;            // per tissue, this frame: drawn with its effects
  std::vector<std::uint8_t> reported;                // per tissue: a mismatch was reported
  std::vector<float> effects_scratch;
  std::unique_ptr<EffectsView> effects;
  /// The frame's uniforms of the mesh programs (a program made mid-frame gets them too).
  struct FrameUniforms {
    Eigen::Matrix4f view_projection = Eigen::Matrix4f::Identity();
    Eigen::Vector3f eye = Eigen::Vector3f::Zero();
    float light_range = 1, texture_scale = 1, vignette = 0, width = 1, height = 1;
  } frame;
  bool frame_set = false;  // frame_values has run
  /// The smoke's low-resolution field (shaders.h, TROCAR_SMOKE): per texel optical depth (× log2 e),
  /// light, mean distance and the inverse of its spread; 32-bit floats, texture unit 1.
  GLuint smoke_field = 0;
  /// The smoke over the cavity's darkness, per field texel: its colour as drawn (gamma-encoded,
  /// vignetted), RGBA8 on texture unit 2.
  GLuint smoke_backdrop = 0;
  std::vector<std::uint8_t> backdrop;
  int field_width = 0, field_height = 0;
  std::vector<float> field;       // field_width × field_height × 4, rows bottom to top
  SplatLevels splat;              // scratch: the field's sums
  std::array<float, 4> smoke_box{};  // pixels the puffs cover: x0, y0, x1, y1 (GL's y up)
  std::array<float, 2> smoke_scale{};  // the field's texture coordinates per frame pixel

  GLint loc(GLuint p, const char* name) const { return glGetUniformLocation(p, name); }

  void overlay(const Eigen::Matrix4f& matrix, GLenum mode, const std::vector<float>& xyz, const Eigen::Vector4f& rgba,
               float point_size = 1) {
    if (xyz.empty()) return;
    glUseProgram(overlay_program);
    glUniformMatrix4fv(loc(overlay_program, "u_matrix"), 1, GL_FALSE, matrix.data());
    glUniform4fv(loc(overlay_program, "u_color"), 1, rgba.data());
    glUniform1f(loc(overlay_program, "u_point_size"), point_size);
    glBindVertexArray(overlay_vao);
    glBindBuffer(GL_ARRAY_BUFFER, overlay_vbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(xyz.size() * sizeof(float)), xyz.data(), GL_STREAM_DRAW);
    glDrawArrays(mode, 0, GLsizei(xyz.size() / 3));
  }

  // Renderer::draw's phases, in order.
  /// Clears the viewport and sets the mesh programs' per-frame uniforms (frame_values first);
  /// returns the camera's view-projection matrix.
  Eigen::Matrix4f begin_frame(const RenderOptions& o, int width, int height);
  /// The mesh program's material (shading mode, base and vessel colours); the id pass overrides it.
  /// The variant: kLooks for modes 4 and 5 and opacity < 1; kEffects `with_effect` in a tissue
  /// mode (0, 3, 4: the mesh's attribute 3 set); kSmoke in a frame with smoke (shaders.h).
  void material(const RenderOptions& o, int mode, const Eigen::Vector3f& base, const Eigen::Vector3f& vessel,
                float vessel_strength = 1, float opacity = 1, bool with_effect = false);
  /// Makes `p` the mesh program in use, with the current model matrix.
  void use(GLuint p);
  /// The mesh program's model and normal matrices.
  void model(const Eigen::Matrix4f& m);
  /// The material of tissue t or rigid r: its appearance's, else the default look.
  void tissue_material(const RenderOptions& o, std::size_t t, float opacity = 1, bool burnt = false);
  void rigid_material(const RenderOptions& o, std::size_t r, float opacity = 1);
  /// Tissues (deformed this frame), rigids and instruments (at their poses), the tacks, then the
  /// translucent objects.
  void draw_meshes(const ViewSnapshot& snap, const CameraView& cam, const RenderOptions& o);
  /// One tissue (its texture image where it has one and keeps the default pattern).
  void draw_tissue(const RenderOptions& o, std::size_t t, bool use_texture, float opacity = 1);
  /// A helical tack per holding attachment, its head towards the eye.
  void draw_tacks(const ViewSnapshot& snap, const CameraView& cam, const RenderOptions& o);
  /// The deferred objects far to near, blended, depth writes off; back faces then front faces.
  void draw_translucent(const RenderOptions& o);
  /// Tissue edges over the shading.
  void draw_wireframe();
  /// Contacts, force arrows, boxes, cells and gauges, over everything.
  void draw_overlays(const ViewSnapshot& snap, const CameraView& cam, const RenderOptions& o,
                     const Eigen::Matrix4f& view_projection, int height);

  /// Sets the frame's uniforms of mesh program p (leaves `program` in use).
  void frame_uniforms(GLuint p);
  /// Rebuilds the buffers of each tissue whose model changed (a cut) from the snapshot.
  void sync_models(const ViewSnapshot& snap);
  void rebuild_tissue(std::size_t t, std::uint32_t version, const std::vector<Triangle>& triangles,
                      const std::vector<Vec3>& rest);
  /// The mesh program variant with these bits (made on first use, its frame uniforms set).
  GLuint program_for(unsigned bits);
  /// The frame's uniforms' values (no GL).
  void frame_values(const CameraView& cam, const RenderOptions& o, int width, int height);
  /// Before the frame: adds up the smoke's puffs (EffectsView's SmokeField) into its field and
  /// binds it on texture unit 1. False (nothing done) without puffs on screen.
  bool prepare_smoke(const CameraView& cam, int width, int height);
  /// After the opaque objects: the smoke where no surface was drawn.
  void draw_smoke_backdrop();
};

Renderer::Renderer(const World& world, const SceneLook& look) : gpu_(std::make_unique<Gpu>()) {
  Gpu& g = *gpu_;
  const std::vector<std::filesystem::path>& textures = look.textures;
  g.tissue_looks = look.tissues;
  g.rigid_looks = look.rigids;
  g.mesh_program = g.program_for(0);
  g.look_program = g.program_for(kLooks);
  g.overlay_program = link(shaders::kOverlayVertex, shaders::kOverlayFragment, "overlay");
  glGenVertexArrays(1, &g.overlay_vao);
  glBindVertexArray(g.overlay_vao);
  glGenBuffers(1, &g.overlay_vbo);
  glBindBuffer(GL_ARRAY_BUFFER, g.overlay_vbo);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glBindVertexArray(0);
  Vec3 lo = Vec3::Constant(1e30), hi = Vec3::Constant(-1e30);
  std::vector<Vec3> gravity;
  for (std::size_t i = 0; i < world.tissues.size(); ++i) {
    const TissueBody* t = world.tissues[i].get();
    const Appearance& a = look_of(g.tissue_looks, i);
    const bool weave = a.given && a.pattern == SurfacePattern::kWeave;
    g.weave_frames.push_back(weave ? std::optional<PlaneFrame>(plane_frame(t->settings.rest_positions)) : std::nullopt);
    const std::vector<float> plane =
        weave ? plane_coordinates(t->settings.rest_positions, *g.weave_frames.back()) : std::vector<float>{};
    g.tissues.emplace_back().create(t->settings.rest_positions, t->settings.triangles, GL_DYNAMIC_DRAW,
                                    weave ? &plane : nullptr);
    g.models.push_back({t->model_version, t->settings.triangles, t->settings.rest_positions});
    gravity.push_back(t->settings.gravity);
    g.textured.emplace_back();
    if (i < textures.size() && !textures[i].empty() && !t->texcoords.empty() && default_pattern(a)) {
      g.textured.back() = std::make_unique<TexturedMesh>();
      g.textured.back()->create(t->settings.rest_positions, t->settings.triangles, t->texcoords,
                                read_png(textures[i].c_str()));
    }
    for (const Vec3& p : t->settings.rest_positions) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  if (!world.tissues.empty()) g.scene_size = std::max(1e-3, (hi - lo).norm());
  g.with_effects.assign(world.tissues.size(), 0);
  g.reported.assign(world.tissues.size(), 0);
  g.effects = std::make_unique<EffectsView>(std::move(gravity));
  for (const InstrumentBody& b : world.instruments) {
    const TriMesh& m = b.instrument.local_mesh();
    GpuMesh& gm = g.instruments.emplace_back();
    gm.create(m.positions, m.triangles, GL_STATIC_DRAW);
    gm.local_positions = m.positions;
  }
  for (std::size_t i = 0; i < world.rigids.size(); ++i) {
    const TriMesh& m = world.rigids[i].mesh;
    const Appearance& a = look_of(g.rigid_looks, i);
    const bool weave = a.given && a.pattern == SurfacePattern::kWeave;
    const std::vector<float> plane = weave ? plane_coordinates(m.positions) : std::vector<float>{};
    g.rigids.emplace_back().create(m.positions, m.triangles, GL_STATIC_DRAW, weave ? &plane : nullptr);
    Vec3 centre = Vec3::Zero();
    for (const Vec3& p : m.positions) centre += p;
    g.rigid_centres.push_back(m.positions.empty() ? centre : Vec3(centre / Real(m.positions.size())));
  }
  const TriMesh tack = make_tack_mesh();
  g.tack.create(tack.positions, tack.triangles, GL_STATIC_DRAW);
  g.deferred.reserve(world.tissues.size() + world.rigids.size());
}

Renderer::~Renderer() {
  Gpu& g = *gpu_;
  for (auto* list : {&g.tissues, &g.instruments, &g.rigids})
    for (GpuMesh& m : *list) m.destroy();
  g.tack.destroy();
  for (auto& m : g.textured)
    if (m) m->destroy();
  glDeleteBuffers(1, &g.overlay_vbo);
  glDeleteVertexArrays(1, &g.overlay_vao);
  for (const GLuint p : g.programs) glDeleteProgram(p);  // 0s are ignored
  glDeleteProgram(g.overlay_program);
  glDeleteProgram(g.backdrop_program);
  glDeleteTextures(1, &g.smoke_field);
  glDeleteTextures(1, &g.smoke_backdrop);
  glDeleteQueries(1, &g.backdrop_query);
}

const EffectsView& Renderer::effects() const { return *gpu_->effects; }

void Renderer::draw(const ViewSnapshot& snap, const CameraView& cam, const RenderOptions& o, int width, int height) {
  Gpu& g = *gpu_;
  g.sync_models(snap);
  EffectsSwitches on;
  on.blood = o.effects;
  on.smoke = o.effects && o.smoke;
  on.venting = o.venting;
  g.effects->update(snap, g.models, on);
  g.frame_values(cam, o, width, height);
  g.smoke_frame = on.smoke && !o.id_colors && g.prepare_smoke(cam, width, height);
  const Eigen::Matrix4f view_projection = g.begin_frame(o, width, height);
  g.draw_meshes(snap, cam, o);
  if (o.wireframe && !o.id_colors) g.draw_wireframe();
  if (!o.id_colors) g.draw_overlays(snap, cam, o, view_projection, height);
}

Eigen::Matrix4f Renderer::Gpu::begin_frame(const RenderOptions& o, int width, int height) {
  glViewport(0, 0, width, height);
  if (o.id_colors) glClearColor(0, 0, 0, 1);
  else glClearColor(kBackground.x(), kBackground.y(), kBackground.z(), 1);  // the unlit depth of the abdominal cavity
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);  // sheets are seen from both sides
  for (std::size_t bits = programs.size(); bits-- > 0;)
    if (programs[bits]) frame_uniforms(programs[bits]);
  program = mesh_program;  // in use after the loop
  return frame.view_projection;
}

void Renderer::Gpu::frame_values(const CameraView& cam, const RenderOptions& o, int width, int height) {
  frame.view_projection = cam.projection * cam.view;
  frame.eye = cam.eye.cast<float>();
  frame.light_range = static_cast<float>(o.light_range > 0 ? o.light_range : 1.5 * scene_size);
  frame.texture_scale = static_cast<float>(12.0 / scene_size);
  frame.vignette = o.id_colors ? 0.0f : static_cast<float>(o.vignette);
  frame.width = float(width);
  frame.height = float(height);
  frame_set = true;
}

void Renderer::Gpu::frame_uniforms(GLuint p) {
  glUseProgram(p);
  program = p;
  glUniformMatrix4fv(loc(p, "u_view_projection"), 1, GL_FALSE, frame.view_projection.data());
  glUniform3fv(loc(p, "u_eye"), 1, frame.eye.data());
  glUniform1f(loc(p, "u_light_range"), frame.light_range);
  glUniform1f(loc(p, "u_texture_scale"), frame.texture_scale);
  glUniform1f(loc(p, "u_vignette"), frame.vignette);
  glUniform2f(loc(p, "u_viewport"), frame.width, frame.height);
  glUniform1f(loc(p, "u_weave_period"), kWeavePeriod);  // (−1: not in this variant, ignored)
  glUniform1i(loc(p, "u_smoke_field"), 1);
  glUniform2fv(loc(p, "u_smoke_scale"), 1, smoke_scale.data());
  glUniform3fv(loc(p, "u_smoke_colour"), 1, kSmokeColour.data());
}

GLuint Renderer::Gpu::program_for(unsigned bits) {
  if (programs[bits]) return programs[bits];
  // The defines after each source's first line (#version); the default program's sources as
  // they are.
  const auto with = [](const char* source, const std::string& defines) {
    const std::string text(source);
    return text.substr(0, text.find('\n') + 1) + defines + text.substr(text.find('\n') + 1);
  };
  std::string defines, name = "mesh";
  if (bits & kLooks) defines += shaders::kLooksDefine, name += " (appearances)";
  if (bits & kEffects) defines += shaders::kEffectsDefine, name += " (effects)";
  if (bits & kSmoke) defines += shaders::kSmokeDefine, name += " (smoke)";
  const std::string vertex = with(shaders::kMeshVertex, std::string(bits & kEffects ? shaders::kEffectsDefine : "") +
                                                            (bits & kSmoke ? shaders::kSmokeDefine : ""));
  const std::string fragment = with(shaders::kMeshFragment, defines);
  programs[bits] = link(vertex.c_str(), fragment.c_str(), name.c_str());
  if (frame_set) {  // mid-frame: the frame's uniforms now, the program in use kept
    const GLuint in_use = program;
    frame_uniforms(programs[bits]);
    if (in_use) use(in_use);
  }
  return programs[bits];
}

void Renderer::Gpu::sync_models(const ViewSnapshot& snap) {
  for (std::size_t t = 0; t < tissues.size() && t < snap.tissues.size(); ++t) {
    if (t >= snap.tissue_versions.size() || snap.tissue_versions[t] == models[t].version) continue;
    if (t >= snap.tissue_triangles.size() || t >= snap.tissue_rest.size() ||
        snap.tissue_rest[t].size() != snap.tissues[t].size())
      continue;  // not a model to draw these positions with (reported when drawn)
    const std::vector<Triangle>& triangles = snap.tissue_triangles[t];
    const std::vector<Vec3>& rest = snap.tissue_rest[t];
    if (triangles == models[t].triangles && rest == models[t].rest) {
      models[t].version = snap.tissue_versions[t];  // coagulation stiffened springs: the same surface
      continue;
    }
    rebuild_tissue(t, snap.tissue_versions[t], triangles, rest);
  }
}

void Renderer::Gpu::rebuild_tissue(std::size_t t, std::uint32_t version, const std::vector<Triangle>& triangles,
                                   const std::vector<Vec3>& rest) {
  // Only triangles of this model's vertices (a tissue may be left with none: drawn as nothing).
  std::vector<Triangle> valid;
  valid.reserve(triangles.size());
  for (const Triangle& f : triangles)
    if (f[0] < rest.size() && f[1] < rest.size() && f[2] < rest.size()) valid.push_back(f);
  TissueModel before = std::move(models[t]);
  models[t] = {version, std::move(valid), rest};
  tissues[t].destroy();
  const std::vector<float> plane = weave_frames[t] ? plane_coordinates(rest, *weave_frames[t]) : std::vector<float>{};
  tissues[t].create(rest, models[t].triangles, GL_DYNAMIC_DRAW, weave_frames[t] ? &plane : nullptr);
  // A tissue drawn with its image and the mesh's UVs keeps them on the triangles a cut left;
  // should a triangle not be one it had (a model not made by cutting), it falls back to the
  // default solid texture on its rest positions.
  if (textured[t] && !textured[t]->remodel(before.rest, models[t].rest, models[t].triangles)) {
    textured[t]->destroy();
    textured[t].reset();
  }
}

void Renderer::Gpu::use(GLuint p) {
  if (program == p) return;
  program = p;
  glUseProgram(p);
  model(model_matrix);
}

void Renderer::Gpu::material(const RenderOptions& o, int mode, const Eigen::Vector3f& base,
                             const Eigen::Vector3f& vessel, float vessel_strength, float opacity, bool with_effect) {
  const bool look = !o.id_colors && (mode >= 4 || opacity < 1);
  const bool burnt = with_effect && !o.id_colors && (mode == 0 || mode == 3 || mode == 4);
  const bool smoky = smoke_frame && !o.id_colors;
  use(program_for((look ? kLooks : 0u) | (burnt ? kEffects : 0u) | (smoky ? kSmoke : 0u)));
  const GLuint p = program;
  glUniform1i(loc(p, "u_mode"), o.id_colors ? 2 : mode);
  if (look) glUniform1f(loc(p, "u_opacity"), opacity);
  glUniform1f(loc(p, "u_vessel_strength"), vessel_strength);
  glUniform3fv(loc(p, "u_base"), 1, base.data());
  glUniform3fv(loc(p, "u_vessel"), 1, vessel.data());
}

void Renderer::Gpu::model(const Eigen::Matrix4f& m) {
  model_matrix = m;
  const GLuint p = program;
  glUniformMatrix4fv(loc(p, "u_model"), 1, GL_FALSE, m.data());
  const Eigen::Matrix3f normal = m.block<3, 3>(0, 0).inverse().transpose();
  glUniformMatrix3fv(loc(p, "u_normal_matrix"), 1, GL_FALSE, normal.data());
}

void Renderer::Gpu::tissue_material(const RenderOptions& o, std::size_t t, float opacity, bool burnt) {
  const Appearance& a = look_of(tissue_looks, t);
  const Eigen::Vector3f vessel(0.42f, 0.04f, 0.07f);
  if (o.id_colors || !a.given) {
    material(o, 0, o.id_colors ? Eigen::Vector3f(1, 0, 0) : Eigen::Vector3f(0.80f, 0.36f, 0.33f), vessel, 1, 1,
             burnt);
    return;
  }
  const int mode = a.pattern == SurfacePattern::kPlain ? 4 : a.pattern == SurfacePattern::kWeave ? 5 : 0;
  // The default pattern: the same texture, in the colour.
  material(o, mode, to_vector(a.colour), vessel, 0.6f, opacity, burnt);
}

void Renderer::Gpu::rigid_material(const RenderOptions& o, std::size_t r, float opacity) {
  const Appearance& a = look_of(rigid_looks, r);
  const Eigen::Vector3f fascia(0.78f, 0.62f, 0.55f);  // muscle with faint fascia strands
  if (o.id_colors || !a.given) {
    material(o, 0, o.id_colors ? Eigen::Vector3f(0, 0, 1) : Eigen::Vector3f(0.62f, 0.22f, 0.20f), fascia, 0.35f);
    return;
  }
  const int mode = a.pattern == SurfacePattern::kPlain ? 4 : a.pattern == SurfacePattern::kWeave ? 5 : 0;
  material(o, mode, to_vector(a.colour), fascia, 0.35f, opacity);
}

void Renderer::Gpu::draw_tissue(const RenderOptions& o, std::size_t t, bool use_texture, float opacity) {
  if (use_texture) {
    material(o, 3, o.id_colors ? Eigen::Vector3f(1, 0, 0) : Eigen::Vector3f(1, 1, 1), Eigen::Vector3f::Zero(), 1,
             opacity, with_effects[t] != 0);
    glUniform1i(loc(program, "u_texture"), 0);
    textured[t]->draw();
    return;
  }
  tissue_material(o, t, opacity);
  tissues[t].draw_part(false);
  if (!with_effects[t]) return;
  tissue_material(o, t, opacity, true);
  tissues[t].draw_part(true);
}

void Renderer::Gpu::draw_meshes(const ViewSnapshot& snap, const CameraView& cam, const RenderOptions& o) {
  deferred.clear();
  model(Eigen::Matrix4f::Identity());
  for (std::size_t t = 0; t < tissues.size() && t < snap.tissues.size(); ++t) {
    with_effects[t] = 0;
    if (snap.tissues[t].size() != models[t].rest.size()) {
      // Positions for a model this renderer was not given (a snapshot made without capture_view's
      // triangles): it cannot be drawn; say so once.
      if (!reported[t])
        std::fprintf(stderr, "render: tissue %zu has %zu vertices, its model %zu (no triangles for them): not drawn\n", t,
                     snap.tissues[t].size(), models[t].rest.size());
      reported[t] = 1;
      continue;
    }
    const Appearance& a = look_of(tissue_looks, t);
    const bool use_texture = textured[t] && default_pattern(a);
    if (use_texture) textured[t]->update(snap.tissues[t]);
    if (!use_texture || o.wireframe) tissues[t].update(snap.tissues[t]);  // the textured: for the wireframe only
    if (invisible(o, a)) continue;
    // Burns and blood: drawn by an effects variant, only where a tissue has any.
    if (o.effects && !o.id_colors && effects->fill(snap, t, snap.tissues[t].size(), true, effects_scratch)) {
      with_effects[t] = 1;
      if (use_texture) textured[t]->set_effects(effects_scratch);
      else tissues[t].set_effects(effects_scratch);
    } else if (!use_texture) {
      tissues[t].clear_effects();
    }
    if (translucent(o, a)) {
      Vec3 centre = Vec3::Zero();
      for (const Vec3& x : snap.tissues[t]) centre += x;
      centre /= Real(std::max<std::size_t>(1, snap.tissues[t].size()));
      deferred.push_back({(centre - cam.eye).norm(), false, t, use_texture});
      continue;
    }
    draw_tissue(o, t, use_texture);
  }
  for (std::size_t r = 0; r < rigids.size(); ++r) {
    const Appearance& a = look_of(rigid_looks, r);
    if (invisible(o, a)) continue;
    if (translucent(o, a)) {
      deferred.push_back({(rigid_centres[r] - cam.eye).norm(), true, r, false});
      continue;
    }
    rigid_material(o, r);
    rigids[r].draw();
  }
  for (std::size_t i = 0; i < instruments.size() && i < snap.instruments.size(); ++i) {
    model(pose_matrix(snap.instruments[i].pose));
    material(o, 1, o.id_colors ? Eigen::Vector3f(0, 1, 0) : Eigen::Vector3f(0.62f, 0.64f, 0.68f),
             Eigen::Vector3f::Zero());
    instruments[i].draw();
  }
  if (!o.id_colors) draw_tacks(snap, cam, o);
  model(Eigen::Matrix4f::Identity());
  if (smoke_frame) draw_smoke_backdrop();
  if (!deferred.empty()) draw_translucent(o);
}

void Renderer::Gpu::draw_tacks(const ViewSnapshot& snap, const CameraView& cam, const RenderOptions& o) {
  if (snap.tacks.empty()) return;
  material(o, 1, kTitanium, Eigen::Vector3f::Zero());
  for (const TackView& tack_view : snap.tacks) {
    Vec3 n = tack_view.normal.norm() > 0 ? Vec3(tack_view.normal.normalized()) : Vec3::UnitZ();
    if (n.dot(cam.eye - tack_view.point) < 0) n = -n;  // the head faces the cavity, where the scope is
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<3, 3>(0, 0) = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), n).toRotationMatrix();
    m.block<3, 1>(0, 3) = tack_view.point;
    model(m.cast<float>());
    tack.draw();
  }
}

void Renderer::Gpu::draw_translucent(const RenderOptions& o) {
  std::sort(deferred.begin(), deferred.end(), [](const Deferred& a, const Deferred& b) { return a.distance > b.distance; });
  glEnable(GL_BLEND);
  // Colour blends by the object's opacity; the target's alpha stays opaque (a window's too).
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
  glDepthMask(GL_FALSE);
  glEnable(GL_CULL_FACE);
  for (const Deferred& d : deferred)
    for (GLenum culled : {GL_FRONT, GL_BACK}) {  // a closed body's far side first, then its near side
      glCullFace(culled);
      if (d.rigid) {
        rigid_material(o, d.index, look_of(rigid_looks, d.index).opacity);
        rigids[d.index].draw();
      } else {
        draw_tissue(o, d.index, d.texture, look_of(tissue_looks, d.index).opacity);
      }
    }
  glDisable(GL_CULL_FACE);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
}

bool Renderer::Gpu::prepare_smoke(const CameraView& cam, int width, int height) {
  const SmokeField* smoke = effects->smoke();
  if (!smoke || smoke->size() == 0) return false;
  // The field: an integer fraction of the frame, about kSmokeRows rows; GL's rows (bottom up).
  const int factor = std::max(1, (height + kSmokeRows / 2) / kSmokeRows);
  const int fw = (width + factor - 1) / factor, fh = (height + factor - 1) / factor;
  const float scale = 1.0f / float(factor);  // field pixels per frame pixel
  const std::size_t texels = std::size_t(fw) * std::size_t(fh);
  splat.reset(fw, fh);
  const Eigen::Matrix4f& vp = frame.view_projection;
  const float p11 = cam.projection(1, 1);
  const float range2 = frame.light_range * frame.light_range;
  float x0 = float(width), y0 = float(height), x1 = 0, y1 = 0;
  bool any = false;
  for (const SmokeParticle& p : smoke->particles()) {
    const Eigen::Vector3f at = p.position.cast<float>();
    const Eigen::Vector4f clip = vp * Eigen::Vector4f(at.x(), at.y(), at.z(), 1);
    if (!(clip.w() > float(cam.near_clip))) continue;  // behind the scope's lens
    const float cx = (0.5f * clip.x() / clip.w() + 0.5f) * float(width) * scale;
    const float cy = (0.5f * clip.y() / clip.w() + 0.5f) * float(height) * scale;
    const float radius = std::min(float(p.radius) * 0.5f * float(height) * scale * p11 / clip.w(), float(fh));
    const float r = std::max(radius, 0.5f);  // as splatted
    if (cx + r < 0 || cx - r > float(fw) || cy + r < 0 || cy - r > float(fh)) continue;
    const float distance = (at - frame.eye).norm();
    const float light = 1.0f / (1.0f + distance * distance / range2);  // the headlight's falloff
    splat.splat(cx, cy, radius, float(p.opacity), light, distance);
    any = true;
    x0 = std::min(x0, (cx - r) / scale), x1 = std::max(x1, (cx + r) / scale);
    y0 = std::min(y0, (cy - r) / scale), y1 = std::max(y1, (cy + r) / scale);
  }
  if (!any) return false;
  const std::vector<float>& sums = splat.collapse();
  const float* const depth_plane = sums.data();
  const float* const light_plane = depth_plane + texels;
  const float* const distance_plane = light_plane + texels;
  const float* const square_plane = distance_plane + texels;
  smoke_box = {std::max(0.0f, std::floor(x0)), std::max(0.0f, std::floor(y0)), std::min(float(width), std::ceil(x1)),
               std::min(float(height), std::ceil(y1))};
  // Per texel: τ log2 e (the shader's exp2), the light, the mean distance and 1 / (2√3 σ) (the
  // distances taken as uniform over mean ± √3 σ; σ plus 1 mm, so a single puff has a depth).
  // The backdrop: the smoke over the clear colour, vignetted as the mesh shader does, encoded.
  field.resize(4 * texels);
  backdrop.resize(4 * texels);
  static const std::array<std::uint8_t, 1024> gamma = [] {  // √linear in 1024 steps → 8 bits
    std::array<std::uint8_t, 1024> table{};
    for (std::size_t k = 0; k < table.size(); ++k) {
      const double root = double(k) / double(table.size() - 1);
      table[k] = std::uint8_t(std::lround(255 * std::pow(root * root, 1 / 2.2)));
    }
    return table;
  }();
  const auto encode = [](float linear) {
    return gamma[std::size_t(std::sqrt(std::clamp(linear, 0.0f, 1.0f)) * float(gamma.size() - 1) + 0.5f)];
  };
  const std::uint8_t clear[3] = {std::uint8_t(std::lround(255 * kBackground.x())), std::uint8_t(std::lround(255 * kBackground.y())),
                                 std::uint8_t(std::lround(255 * kBackground.z()))};
  for (std::size_t k = 0; k < texels; ++k) {
    float* f = &field[4 * k];
    std::uint8_t* b = &backdrop[4 * k];
    const float tau = depth_plane[k];
    if (!(tau > 1e-6f)) {
      f[0] = f[1] = f[2] = f[3] = 0;
      b[0] = clear[0], b[1] = clear[1], b[2] = clear[2], b[3] = 255;
      continue;
    }
    const float mean = distance_plane[k] / tau;
    const float sigma = std::sqrt(std::max(0.0f, square_plane[k] / tau - mean * mean)) + 1e-3f;
    f[0] = tau * 1.4426950f;
    f[1] = light_plane[k] / tau;
    f[2] = mean;
    f[3] = 1.0f / (3.4641016f * sigma);
    float vignette = 1;
    if (frame.vignette > 0) {
      const float px = (float(k % std::size_t(fw)) + 0.5f) / scale, py = (float(k / std::size_t(fw)) + 0.5f) / scale;
      const float c = std::hypot(px - 0.5f * frame.width, py - 0.5f * frame.height) / (0.5f * frame.height);
      const float t = std::clamp((c - frame.vignette) / 0.6f, 0.0f, 1.0f);
      vignette = 1 - t * t * (3 - 2 * t);
    }
    const float a = 1 - std::exp(-tau);
    for (int c = 0; c < 3; ++c)
      b[c] = encode(kBackgroundLinear[c] + (kSmokeColour[c] * f[1] * vignette - kBackgroundLinear[c]) * a);
    b[3] = 255;
  }
  if (!backdrop_program) backdrop_program = link(shaders::kSmokeBackdropVertex, shaders::kSmokeBackdropFragment, "smoke backdrop");
  // Units 1 and 2 hold them for the frame (unit 0: a tissue's image).
  const bool resized = fw != field_width || fh != field_height;
  const auto upload = [&](GLenum unit, GLuint& texture, GLint format, GLenum type, const void* data) {
    glActiveTexture(unit);
    if (!texture) {
      glGenTextures(1, &texture);
      glBindTexture(GL_TEXTURE_2D, texture);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    glBindTexture(GL_TEXTURE_2D, texture);
    if (resized) glTexImage2D(GL_TEXTURE_2D, 0, format, fw, fh, 0, GL_RGBA, type, data);
    else glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, fw, fh, GL_RGBA, type, data);
  };
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  upload(GL_TEXTURE1, smoke_field, GL_RGBA32F, GL_FLOAT, field.data());
  upload(GL_TEXTURE2, smoke_backdrop, GL_RGBA8, GL_UNSIGNED_BYTE, backdrop.data());
  glActiveTexture(GL_TEXTURE0);
  field_width = fw;
  field_height = fh;
  smoke_scale = {1.0f / float(fw * factor), 1.0f / float(fh * factor)};
  return true;
}

void Renderer::Gpu::draw_smoke_backdrop() {
  // Where nothing was drawn (the depth still cleared), the smoke over the cavity's darkness: a
  // quad on the far plane over the puffs' box, passing the depth test only there.
  if (!backdrop_query) glGenQueries(1, &backdrop_query);
  if (backdrop_pending) {
    GLuint available = 0;
    glGetQueryObjectuiv(backdrop_query, GL_QUERY_RESULT_AVAILABLE, &available);
    if (available) {
      GLuint drawn = 1;
      glGetQueryObjectuiv(backdrop_query, GL_QUERY_RESULT, &drawn);
      backdrop_pending = false;
      if (!drawn) backdrop_skip = kBackdropRecheck;
    }
  }
  if (backdrop_skip > 0) {
    --backdrop_skip;
    return;
  }
  glUseProgram(backdrop_program);
  program = 0;
  const GLuint bp = backdrop_program;
  glUniform1i(loc(bp, "u_backdrop"), 2);
  glUniform2fv(loc(bp, "u_scale"), 1, smoke_scale.data());
  const float nx0 = 2 * smoke_box[0] / frame.width - 1, nx1 = 2 * smoke_box[2] / frame.width - 1;
  const float ny0 = 2 * smoke_box[1] / frame.height - 1, ny1 = 2 * smoke_box[3] / frame.height - 1;
  lines = {nx0, ny0, 1, nx1, ny0, 1, nx1, ny1, 1, nx0, ny0, 1, nx1, ny1, 1, nx0, ny1, 1};
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_FALSE);
  glBindVertexArray(overlay_vao);
  glBindBuffer(GL_ARRAY_BUFFER, overlay_vbo);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(lines.size() * sizeof(float)), lines.data(), GL_STREAM_DRAW);
  const bool ask = !backdrop_pending;
  if (ask) glBeginQuery(GL_ANY_SAMPLES_PASSED, backdrop_query);
  glDrawArrays(GL_TRIANGLES, 0, 6);
  if (ask) glEndQuery(GL_ANY_SAMPLES_PASSED);
  backdrop_pending = true;
  glBindVertexArray(0);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
}

void Renderer::Gpu::draw_wireframe() {
  use(mesh_program);
  model(Eigen::Matrix4f::Identity());
  glUniform1i(loc(mesh_program, "u_mode"), 2);
  const Eigen::Vector3f edge(0.15f, 0.05f, 0.05f);
  glUniform3fv(loc(mesh_program, "u_base"), 1, edge.data());
  glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
  glEnable(GL_POLYGON_OFFSET_LINE);
  glPolygonOffset(-1, -1);
  for (GpuMesh& m : tissues) m.draw();
  glDisable(GL_POLYGON_OFFSET_LINE);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
}

void Renderer::Gpu::draw_overlays(const ViewSnapshot& snap, const CameraView& cam, const RenderOptions& o,
                                  const Eigen::Matrix4f& view_projection, int height) {
  // Drawn over everything so they stay visible inside the tissue.
  glDisable(GL_DEPTH_TEST);
  glEnable(GL_PROGRAM_POINT_SIZE);
  std::vector<float>& v = lines;
  if (o.contacts) {
    v.clear();
    for (const ContactView& c : snap.contacts) push_point(v, c.point);
    overlay(view_projection, GL_POINTS, v, {1.0f, 0.9f, 0.1f, 1}, std::max(3.0f, float(height) / 160));
  }
  if (o.forces) {
    v.clear();
    push_force_arrows(v, snap, cam, o.force_scale);
    glLineWidth(2);
    overlay(view_projection, GL_LINES, v, {0.2f, 1.0f, 0.4f, 1});
  }
  if (o.obb) {
    v.clear();
    for (const InstrumentView& iv : snap.instruments) {
      const Obb& b = iv.obb;
      push_box_edges(v, [&b](int i) {
        const Vec3 s((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
        return Vec3(b.center + b.axes * s.cwiseProduct(b.half_extents));
      });
    }
    overlay(view_projection, GL_LINES, v, {0.3f, 0.7f, 1.0f, 1});
  }
  if (o.cells && snap.cell_size > 0) {
    v.clear();
    push_shared_cells(v, snap, instruments);
    overlay(view_projection, GL_LINES, v, {1.0f, 0.5f, 0.1f, 0.8f});
  }
  if (o.gauge) {
    // One bar per instrument, bottom left, in normalised device coordinates.
    for (std::size_t i = 0; i < snap.instruments.size(); ++i) {
      const float x0 = -0.95f, x1 = -0.55f, y0 = -0.93f + 0.07f * float(i), y1 = y0 + 0.04f;
      const float f = static_cast<float>(std::min(1.0, snap.instruments[i].force.norm() / std::max(1e-9, o.gauge_max)));
      const auto quad = [&](float a, float b) {
        v = {a, y0, 0, b, y0, 0, b, y1, 0, a, y0, 0, b, y1, 0, a, y1, 0};
      };
      quad(x0, x1);
      overlay(Eigen::Matrix4f::Identity(), GL_TRIANGLES, v, {0.15f, 0.15f, 0.15f, 1});
      quad(x0, x0 + f * (x1 - x0));
      overlay(Eigen::Matrix4f::Identity(), GL_TRIANGLES, v, {0.2f + 0.8f * f, 0.9f * (1 - f) + 0.1f, 0.2f, 1});
    }
  }
  glEnable(GL_DEPTH_TEST);
  glBindVertexArray(0);
}

}  // namespace trocar
