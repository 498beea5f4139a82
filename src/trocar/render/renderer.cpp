#include "trocar/render/renderer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <string>
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

/// One indexed mesh on the GPU: positions and normals (dynamic for tissue), texture coordinates.
struct GpuMesh {
  GLuint vao = 0, positions = 0, normals = 0, texcoords = 0, indices = 0;
  GLsizei index_count = 0;
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
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(idx.size() * sizeof(std::uint32_t)), idx.data(), GL_STATIC_DRAW);
    index_count = static_cast<GLsizei>(idx.size());
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
  void draw() const {
    glBindVertexArray(vao);
    glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, nullptr);
  }
  void destroy() {
    const GLuint buffers[] = {positions, normals, texcoords, indices};
    glDeleteBuffers(4, buffers);
    glDeleteVertexArrays(1, &vao);
  }
};

/// A tissue drawn with the mesh's own UVs: UVs are per triangle corner, so the GPU gets one
/// vertex per corner, gathered from the deformed positions and smooth normals every frame.
struct TexturedMesh {
  GLuint vao = 0, positions = 0, normals = 0, texcoords = 0, texture = 0;
  std::vector<Triangle> triangles;
  std::vector<float> vertex_normals_xyz, corner_positions, corner_normals;

  void create(const std::vector<Vec3>& rest, const std::vector<Triangle>& tris, const std::vector<Vec2>& uv,
              const Image& image) {
    triangles = tris;
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
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8, image.width, image.height, 0, GL_RGB, GL_UNSIGNED_BYTE, image.rgb.data());
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    update(rest);
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
  void draw() const {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, texture);
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(3 * triangles.size()));
  }
  void destroy() {
    const GLuint buffers[] = {positions, normals, texcoords};
    glDeleteBuffers(3, buffers);
    glDeleteVertexArrays(1, &vao);
    glDeleteTextures(1, &texture);
  }
};

/// Rest positions in their best-fitting plane (the two principal axes of their spread), as xyz
/// floats with z = 0, in metres: the weave's domain, so it stays on the cloth as it deforms.
std::vector<float> plane_coordinates(const std::vector<Vec3>& rest) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : rest) mean += p;
  mean /= Real(std::max<std::size_t>(1, rest.size()));
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  for (const Vec3& p : rest) spread += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(spread);  // eigenvalues ascending
  const Vec3 u = axes.eigenvectors().col(2), v = axes.eigenvectors().col(1);
  std::vector<float> out(3 * rest.size(), 0.0f);
  for (std::size_t i = 0; i < rest.size(); ++i) {
    out[3 * i] = float((rest[i] - mean).dot(u));
    out[3 * i + 1] = float((rest[i] - mean).dot(v));
  }
  return out;
}

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

struct Renderer::Gpu {
  GLuint mesh_program = 0, overlay_program = 0;
  GLuint look_program = 0;    // the mesh program with TROCAR_LOOKS: plain, weave, opacity
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
  /// Clears the viewport and sets the mesh program's per-frame uniforms; returns the camera's
  /// view-projection matrix.
  Eigen::Matrix4f begin_frame(const CameraView& cam, const RenderOptions& o, int width, int height);
  /// The mesh program's material (shading mode, base and vessel colours); the id pass overrides it.
  /// Modes 4 and 5 and opacity < 1 use the look program, the rest the default one (shaders.h).
  void material(const RenderOptions& o, int mode, const Eigen::Vector3f& base, const Eigen::Vector3f& vessel,
                float vessel_strength = 1, float opacity = 1);
  /// Makes `p` the mesh program in use, with the current model matrix.
  void use(GLuint p);
  /// The mesh program's model and normal matrices.
  void model(const Eigen::Matrix4f& m);
  /// The material of tissue t or rigid r: its appearance's, else the default look.
  void tissue_material(const RenderOptions& o, std::size_t t, float opacity = 1);
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
};

Renderer::Renderer(const World& world, const SceneLook& look) : gpu_(std::make_unique<Gpu>()) {
  Gpu& g = *gpu_;
  const std::vector<std::filesystem::path>& textures = look.textures;
  g.tissue_looks = look.tissues;
  g.rigid_looks = look.rigids;
  g.mesh_program = link(shaders::kMeshVertex, shaders::kMeshFragment, "mesh");
  const std::string fragment(shaders::kMeshFragment);
  const std::string looks = fragment.substr(0, fragment.find('\n') + 1) + shaders::kLooksDefine +
                            fragment.substr(fragment.find('\n') + 1);
  g.look_program = link(shaders::kMeshVertex, looks.c_str(), "mesh (appearances)");
  g.overlay_program = link(shaders::kOverlayVertex, shaders::kOverlayFragment, "overlay");
  glGenVertexArrays(1, &g.overlay_vao);
  glBindVertexArray(g.overlay_vao);
  glGenBuffers(1, &g.overlay_vbo);
  glBindBuffer(GL_ARRAY_BUFFER, g.overlay_vbo);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glBindVertexArray(0);
  Vec3 lo = Vec3::Constant(1e30), hi = Vec3::Constant(-1e30);
  for (std::size_t i = 0; i < world.tissues.size(); ++i) {
    const TissueBody* t = world.tissues[i].get();
    const Appearance& a = look_of(g.tissue_looks, i);
    const bool weave = a.given && a.pattern == SurfacePattern::kWeave;
    const std::vector<float> plane = weave ? plane_coordinates(t->settings.rest_positions) : std::vector<float>{};
    g.tissues.emplace_back().create(t->settings.rest_positions, t->settings.triangles, GL_DYNAMIC_DRAW,
                                    weave ? &plane : nullptr);
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
  glDeleteProgram(g.mesh_program);
  glDeleteProgram(g.look_program);
  glDeleteProgram(g.overlay_program);
}

void Renderer::draw(const ViewSnapshot& snap, const CameraView& cam, const RenderOptions& o, int width, int height) {
  Gpu& g = *gpu_;
  const Eigen::Matrix4f view_projection = g.begin_frame(cam, o, width, height);
  g.draw_meshes(snap, cam, o);
  if (o.wireframe && !o.id_colors) g.draw_wireframe();
  if (!o.id_colors) g.draw_overlays(snap, cam, o, view_projection, height);
}

Eigen::Matrix4f Renderer::Gpu::begin_frame(const CameraView& cam, const RenderOptions& o, int width, int height) {
  glViewport(0, 0, width, height);
  if (o.id_colors) glClearColor(0, 0, 0, 1);
  else glClearColor(0.035f, 0.012f, 0.010f, 1);  // the unlit depth of the abdominal cavity
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);  // sheets are seen from both sides
  const Eigen::Matrix4f view_projection = cam.projection * cam.view;
  const Eigen::Vector3f eye = cam.eye.cast<float>();
  const float light_range = static_cast<float>(o.light_range > 0 ? o.light_range : 1.5 * scene_size);
  for (const GLuint p : {look_program, mesh_program}) {
    glUseProgram(p);
    glUniformMatrix4fv(loc(p, "u_view_projection"), 1, GL_FALSE, view_projection.data());
    glUniform3fv(loc(p, "u_eye"), 1, eye.data());
    glUniform1f(loc(p, "u_light_range"), light_range);
    glUniform1f(loc(p, "u_texture_scale"), static_cast<float>(12.0 / scene_size));
    glUniform1f(loc(p, "u_vignette"), o.id_colors ? 0.0f : static_cast<float>(o.vignette));
    glUniform2f(loc(p, "u_viewport"), float(width), float(height));
    if (p == look_program) glUniform1f(loc(p, "u_weave_period"), kWeavePeriod);
  }
  program = mesh_program;  // in use after the loop
  return view_projection;
}

void Renderer::Gpu::use(GLuint p) {
  if (program == p) return;
  program = p;
  glUseProgram(p);
  model(model_matrix);
}

void Renderer::Gpu::material(const RenderOptions& o, int mode, const Eigen::Vector3f& base,
                             const Eigen::Vector3f& vessel, float vessel_strength, float opacity) {
  const bool look = !o.id_colors && (mode >= 4 || opacity < 1);
  use(look ? look_program : mesh_program);
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

void Renderer::Gpu::tissue_material(const RenderOptions& o, std::size_t t, float opacity) {
  const Appearance& a = look_of(tissue_looks, t);
  const Eigen::Vector3f vessel(0.42f, 0.04f, 0.07f);
  if (o.id_colors || !a.given) {
    material(o, 0, o.id_colors ? Eigen::Vector3f(1, 0, 0) : Eigen::Vector3f(0.80f, 0.36f, 0.33f), vessel);
    return;
  }
  const int mode = a.pattern == SurfacePattern::kPlain ? 4 : a.pattern == SurfacePattern::kWeave ? 5 : 0;
  // The default pattern: the same texture, in the colour.
  material(o, mode, to_vector(a.colour), vessel, 0.6f, opacity);
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
             opacity);
    glUniform1i(loc(program, "u_texture"), 0);
  } else {
    tissue_material(o, t, opacity);
  }
  if (use_texture) textured[t]->draw();
  else tissues[t].draw();
}

void Renderer::Gpu::draw_meshes(const ViewSnapshot& snap, const CameraView& cam, const RenderOptions& o) {
  deferred.clear();
  model(Eigen::Matrix4f::Identity());
  for (std::size_t t = 0; t < tissues.size() && t < snap.tissues.size(); ++t) {
    if (snap.tissues[t].size() * 3 != tissues[t].scratch_positions.size()) continue;
    const Appearance& a = look_of(tissue_looks, t);
    const bool use_texture = textured[t] && default_pattern(a);
    if (use_texture) textured[t]->update(snap.tissues[t]);
    if (!use_texture || o.wireframe) tissues[t].update(snap.tissues[t]);  // the textured: for the wireframe only
    if (invisible(o, a)) continue;
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
