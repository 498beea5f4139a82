// OBJ and binary STL writers.
//
// OBJ: numbers are printed with std::to_chars in the shortest form that reads back as the same
// double (at most 17 significant digits), so read_obj(write_obj(m)) reproduces the positions,
// normals and texture coordinates bit for bit. Normals (per vertex) become `vn` lines indexed
// like the vertices; texture coordinates (per corner) become one `vt` per corner.
// Binary STL: an 80-byte header starting "trocar" (never "solid"), float32 little-endian facet
// normal (unit, or zero for a degenerate triangle) and corners, attribute word 0.
// Both throw trocar::Error for a mesh with invalid indices or non-finite positions, rather than
// write a file no reader accepts.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "trocar/mesh/io/mesh_io.h"

namespace trocar {
namespace {

void check_writable(const TriMesh& mesh, const char* what) {
  if (!mesh.indices_valid()) {
    throw Error(std::string(what) + ": the mesh has out-of-range indices or attribute sizes");
  }
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!mesh.positions[i].allFinite()) {
      throw Error(std::string(what) + ": vertex " + std::to_string(i) + " is not finite");
    }
  }
}

void append_index(std::string& out, std::uint64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void append_u32_le(std::string& out, std::uint32_t v) {
  const char bytes[4] = {static_cast<char>(v & 0xFF), static_cast<char>((v >> 8) & 0xFF),
                         static_cast<char>((v >> 16) & 0xFF), static_cast<char>((v >> 24) & 0xFF)};
  out.append(bytes, 4);
}

void append_f32_le(std::string& out, float f) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &f, 4);
  append_u32_le(out, bits);
}

}  // namespace

void append_real(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

std::string write_obj(const TriMesh& mesh) {
  check_writable(mesh, "write_obj");
  const bool has_normals = !mesh.normals.empty();
  const bool has_texcoords = !mesh.texcoords.empty();
  std::string out;
  out.reserve(mesh.positions.size() * 40 * (has_normals ? 2 : 1) + mesh.triangles.size() * 30);
  out += "# written by trocar\n";
  for (const Vec3& p : mesh.positions) {
    out += "v ";
    append_real(out, p.x());
    out += ' ';
    append_real(out, p.y());
    out += ' ';
    append_real(out, p.z());
    out += '\n';
  }
  if (has_normals) {
    for (const Vec3& n : mesh.normals) {
      out += "vn ";
      append_real(out, n.x());
      out += ' ';
      append_real(out, n.y());
      out += ' ';
      append_real(out, n.z());
      out += '\n';
    }
  }
  if (has_texcoords) {
    for (const Vec2& uv : mesh.texcoords) {
      out += "vt ";
      append_real(out, uv.x());
      out += ' ';
      append_real(out, uv.y());
      out += '\n';
    }
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    out += 'f';
    for (int c = 0; c < 3; ++c) {
      const std::uint64_t v = std::uint64_t{mesh.triangles[t][c]} + 1;
      out += ' ';
      append_index(out, v);
      if (has_texcoords || has_normals) out += '/';
      if (has_texcoords) append_index(out, 3 * t + c + 1);
      if (has_normals) {
        out += '/';
        append_index(out, v);
      }
    }
    out += '\n';
  }
  return out;
}

std::string write_stl_binary(const TriMesh& mesh) {
  check_writable(mesh, "write_stl_binary");
  if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw Error("write_stl_binary: more than 2^32 - 1 triangles");
  }
  std::string out;
  out.reserve(84 + 50 * mesh.triangles.size());
  std::string header = "trocar";
  header.resize(80, '\0');
  out += header;
  append_u32_le(out, static_cast<std::uint32_t>(mesh.triangles.size()));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto corners = mesh.corners(t);
    float f[3][3];
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < 3; ++k) {
        f[c][k] = static_cast<float>(corners[c][k]);
        if (!std::isfinite(f[c][k])) {
          throw Error("write_stl_binary: vertex " + std::to_string(mesh.triangles[t][c]) +
                      " does not fit in float32");
        }
      }
    }
    // The normal of the triangle as stored (float32 corners), computed in double.
    const Vec3 a(f[0][0], f[0][1], f[0][2]);
    const Vec3 b(f[1][0], f[1][1], f[1][2]);
    const Vec3 c(f[2][0], f[2][1], f[2][2]);
    Vec3 n = (b - a).cross(c - a);
    const double len = n.norm();
    n = len > 0 && std::isfinite(len) ? Vec3(n / len) : Vec3::Zero();
    for (int k = 0; k < 3; ++k) append_f32_le(out, static_cast<float>(n[k]));
    for (int cc = 0; cc < 3; ++cc)
      for (int k = 0; k < 3; ++k) append_f32_le(out, f[cc][k]);
    out.append(2, '\0');  // attribute byte count
  }
  return out;
}

}  // namespace trocar
