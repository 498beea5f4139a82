#pragma once
/// Writing a built organ with its texture: OBJ + MTL (+ the PNG beside them) and VRML97, the
/// original system's format.
#include <filesystem>
#include <string>

#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// Writes `obj_path` (positions, per-corner vt when the mesh has texcoords, `mtllib`/`usemtl`)
/// and the .mtl of the same stem beside it, whose material names `texture_file` (relative to
/// the OBJ, empty for none) as map_Kd and `diffuse` (RGB in [0, 1]) as Kd. Throws FileError.
void write_textured_obj(const TriMesh& mesh, const std::filesystem::path& obj_path, const std::string& texture_file,
                        const Vec3& diffuse);

/// VRML97 text: one Shape with a Material (`diffuse`), an ImageTexture (`texture_file`, when
/// given) and an IndexedFaceSet (coord, coordIndex, and texCoord/texCoordIndex when the mesh
/// has texcoords; solid TRUE, ccw TRUE: outward counter-clockwise triangles).
std::string write_vrml(const TriMesh& mesh, const std::string& texture_file, const Vec3& diffuse, const std::string& name);

/// Writes write_vrml() to a file. Throws FileError.
void save_vrml(const TriMesh& mesh, const std::filesystem::path& path, const std::string& texture_file,
               const Vec3& diffuse, const std::string& name);

}  // namespace trocar
