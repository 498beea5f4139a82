#include "trocar/modelling/organ_writers.h"

#include <fstream>

#include "trocar/core/error.h"
#include "trocar/mesh/io/mesh_io.h"

namespace trocar {
namespace {

void write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw FileError(path.string(), FileLocation::none(), "cannot write the file");
}

/// "a b c" (or "a b") with the shortest round-trip digits.
template <typename Vector>
std::string numbers_text(const Vector& v) {
  std::string s;
  for (int k = 0; k < static_cast<int>(v.size()); ++k) {
    if (k > 0) s += ' ';
    append_real(s, v[k]);
  }
  return s;
}

}  // namespace

void write_textured_obj(const TriMesh& mesh, const std::filesystem::path& obj_path, const std::string& texture_file,
                        const Vec3& diffuse) {
  const std::filesystem::path mtl_path = std::filesystem::path(obj_path).replace_extension(".mtl");
  std::string mtl = "# written by trocar\nnewmtl organ\nKa 0 0 0\nKd " + numbers_text(diffuse) +
                    "\nKs 0.3 0.3 0.3\nNs 40\nd 1\nillum 2\n";
  if (!texture_file.empty()) mtl += "map_Kd " + texture_file + "\n";
  std::string obj = write_obj(mesh);
  // The material lines go before the first face (usemtl applies to the faces after it).
  const std::string header = "mtllib " + mtl_path.filename().string() + "\nusemtl organ\n";
  const std::size_t first_face = obj.find("\nf ");
  obj.insert(first_face == std::string::npos ? obj.size() : first_face + 1, header);
  write_file(mtl_path, mtl);
  write_file(obj_path, obj);
}

std::string write_vrml(const TriMesh& mesh, const std::string& texture_file, const Vec3& diffuse, const std::string& name) {
  std::string out = "#VRML V2.0 utf8\n# written by trocar: " + name + "\n";
  out += "Shape {\n  appearance Appearance {\n    material Material { diffuseColor " + numbers_text(diffuse) +
         " specularColor 0.3 0.3 0.3 shininess 0.3 }\n";
  if (!texture_file.empty()) out += "    texture ImageTexture { url \"" + texture_file + "\" }\n";
  out += "  }\n  geometry IndexedFaceSet {\n    solid TRUE\n    ccw TRUE\n    coord Coordinate { point [\n";
  for (const Vec3& p : mesh.positions) out += "      " + numbers_text(p) + ",\n";
  out += "    ] }\n    coordIndex [\n";
  for (const Triangle& t : mesh.triangles) {
    out += "      " + std::to_string(t[0]) + ' ' + std::to_string(t[1]) + ' ' + std::to_string(t[2]) + " -1,\n";
  }
  out += "    ]\n";
  if (!mesh.texcoords.empty()) {
    out += "    texCoord TextureCoordinate { point [\n";
    for (const Vec2& uv : mesh.texcoords) out += "      " + numbers_text(uv) + ",\n";
    out += "    ] }\n    texCoordIndex [\n";
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      out += "      " + std::to_string(3 * t) + ' ' + std::to_string(3 * t + 1) + ' ' + std::to_string(3 * t + 2) + " -1,\n";
    }
    out += "    ]\n";
  }
  out += "  }\n}\n";
  return out;
}

void save_vrml(const TriMesh& mesh, const std::filesystem::path& path, const std::string& texture_file,
               const Vec3& diffuse, const std::string& name) {
  write_file(path, write_vrml(mesh, texture_file, diffuse, name));
}

}  // namespace trocar
