#include "trocar/render/renderer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_set>

#include <Eigen/Geometry>

#include "trocar/core/error.h"
#include "trocar/render/offscreen.h"
#include "trocar/render/shaders.h"

namespace trocar {
namespace {

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

  void create(const std::vector<Vec3>& positions_m, const std::vector<Triangle>& tris, GLenum usage) {
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
    buffer(texcoords, 2, scratch_positions, GL_STATIC_DRAW);  // rest positions: the solid texture's domain
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
  GLuint overlay_vao = 0, overlay_vbo = 0;
  std::vector<GpuMesh> tissues, instruments, rigids;
  std::vector<std::unique_ptr<TexturedMesh>> textured;  // per tissue: null = procedural texture
  std::vector<float> lines;  // overlay scratch
  Real scene_size = 0.1;

  GLint loc(GLuint program, const char* name) const { return glGetUniformLocation(program, name); }

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
  void material(const RenderOptions& o, int mode, const Eigen::Vector3f& base, const Eigen::Vector3f& vessel,
                float vessel_strength = 1);
  /// The mesh program's model and normal matrices.
  void model(const Eigen::Matrix4f& m);
  /// Tissues (deformed this frame), rigids and instruments (at their poses).
  void draw_meshes(const ViewSnapshot& snap, const RenderOptions& o);
  /// Tissue edges over the shading.
  void draw_wireframe();
  /// Contacts, force arrows, boxes, cells and gauges, over everything.
  void draw_overlays(const ViewSnapshot& snap, const CameraView& cam, const RenderOptions& o,
                     const Eigen::Matrix4f& view_projection, int height);
};

Renderer::Renderer(const World& world, const std::vector<std::filesystem::path>& textures)
    : gpu_(std::make_unique<Gpu>()) {
  Gpu& g = *gpu_;
  g.mesh_program = link(shaders::kMeshVertex, shaders::kMeshFragment, "mesh");
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
    g.tissues.emplace_back().create(t->settings.rest_positions, t->settings.triangles, GL_DYNAMIC_DRAW);
    g.textured.emplace_back();
    if (i < textures.size() && !textures[i].empty() && !t->texcoords.empty()) {
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
  for (const RigidBody& r : world.rigids) g.rigids.emplace_back().create(r.mesh.positions, r.mesh.triangles, GL_STATIC_DRAW);
}

Renderer::~Renderer() {
  Gpu& g = *gpu_;
  for (auto* list : {&g.tissues, &g.instruments, &g.rigids})
    for (GpuMesh& m : *list) m.destroy();
  for (auto& m : g.textured)
    if (m) m->destroy();
  glDeleteBuffers(1, &g.overlay_vbo);
  glDeleteVertexArrays(1, &g.overlay_vao);
  glDeleteProgram(g.mesh_program);
  glDeleteProgram(g.overlay_program);
}

void Renderer::draw(const ViewSnapshot& snap, const CameraView& cam, const RenderOptions& o, int width, int height) {
  Gpu& g = *gpu_;
  const Eigen::Matrix4f view_projection = g.begin_frame(cam, o, width, height);
  g.draw_meshes(snap, o);
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
  const GLuint p = mesh_program;
  glUseProgram(p);
  glUniformMatrix4fv(loc(p, "u_view_projection"), 1, GL_FALSE, view_projection.data());
  const Eigen::Vector3f eye = cam.eye.cast<float>();
  glUniform3fv(loc(p, "u_eye"), 1, eye.data());
  const float light_range = static_cast<float>(o.light_range > 0 ? o.light_range : 1.5 * scene_size);
  glUniform1f(loc(p, "u_light_range"), light_range);
  glUniform1f(loc(p, "u_texture_scale"), static_cast<float>(12.0 / scene_size));
  glUniform1f(loc(p, "u_vignette"), o.id_colors ? 0.0f : static_cast<float>(o.vignette));
  glUniform2f(loc(p, "u_viewport"), float(width), float(height));
  return view_projection;
}

void Renderer::Gpu::material(const RenderOptions& o, int mode, const Eigen::Vector3f& base,
                             const Eigen::Vector3f& vessel, float vessel_strength) {
  const GLuint p = mesh_program;
  glUniform1i(loc(p, "u_mode"), o.id_colors ? 2 : mode);
  glUniform1f(loc(p, "u_vessel_strength"), vessel_strength);
  glUniform3fv(loc(p, "u_base"), 1, base.data());
  glUniform3fv(loc(p, "u_vessel"), 1, vessel.data());
}

void Renderer::Gpu::model(const Eigen::Matrix4f& m) {
  const GLuint p = mesh_program;
  glUniformMatrix4fv(loc(p, "u_model"), 1, GL_FALSE, m.data());
  const Eigen::Matrix3f normal = m.block<3, 3>(0, 0).inverse().transpose();
  glUniformMatrix3fv(loc(p, "u_normal_matrix"), 1, GL_FALSE, normal.data());
}

void Renderer::Gpu::draw_meshes(const ViewSnapshot& snap, const RenderOptions& o) {
  model(Eigen::Matrix4f::Identity());
  for (std::size_t t = 0; t < tissues.size() && t < snap.tissues.size(); ++t) {
    if (snap.tissues[t].size() * 3 != tissues[t].scratch_positions.size()) continue;
    if (textured[t]) {
      textured[t]->update(snap.tissues[t]);
      material(o, 3, o.id_colors ? Eigen::Vector3f(1, 0, 0) : Eigen::Vector3f(1, 1, 1), Eigen::Vector3f::Zero());
      glUniform1i(loc(mesh_program, "u_texture"), 0);
      textured[t]->draw();
      if (!o.wireframe) continue;
    }
    tissues[t].update(snap.tissues[t]);
    if (textured[t]) continue;  // updated for the wireframe pass only
    material(o, 0, o.id_colors ? Eigen::Vector3f(1, 0, 0) : Eigen::Vector3f(0.80f, 0.36f, 0.33f),
             Eigen::Vector3f(0.42f, 0.04f, 0.07f));
    tissues[t].draw();
  }
  for (GpuMesh& r : rigids) {
    material(o, 0, o.id_colors ? Eigen::Vector3f(0, 0, 1) : Eigen::Vector3f(0.62f, 0.22f, 0.20f),
             Eigen::Vector3f(0.78f, 0.62f, 0.55f), 0.35f);  // muscle with faint fascia strands
    r.draw();
  }
  for (std::size_t i = 0; i < instruments.size() && i < snap.instruments.size(); ++i) {
    model(pose_matrix(snap.instruments[i].pose));
    material(o, 1, o.id_colors ? Eigen::Vector3f(0, 1, 0) : Eigen::Vector3f(0.62f, 0.64f, 0.68f),
             Eigen::Vector3f::Zero());
    instruments[i].draw();
  }
}

void Renderer::Gpu::draw_wireframe() {
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
