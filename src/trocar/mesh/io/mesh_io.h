#pragma once
/// Reading and writing triangle meshes. Every reader takes the file's bytes and the name to
/// report in errors, so it can be tested and fuzzed from memory; load_mesh() reads a file and
/// picks the reader by extension, then checks the content agrees (e.g. a binary STL named
/// .obj is an error that says so). Malformed input throws FileError naming the file and the
/// line (text) or byte offset (binary) and the reason; no reader crashes, hangs or allocates
/// more than the input can justify. See docs/mesh-io.md for what each format supports.
#include <filesystem>
#include <string>
#include <string_view>

#include "trocar/core/error.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// The file formats trocar reads (and, for OBJ and STL, writes).
enum class MeshFormat { kObj, kStl, kPly, kVrml, kVtk };

/// Lower-case name ("obj", "stl", "ply", "vrml", "vtk").
const char* format_name(MeshFormat format);
/// The format for a path's extension (.obj .stl .ply .wrl/.vrml .vtk, any case); throws
/// FileError for an unknown extension.
MeshFormat format_from_path(const std::filesystem::path& path);

/// Wavefront OBJ: v/vt/vn, f in all index forms (v, v/t, v//n, v/t/n, negative = relative),
/// polygons fan-triangulated, CRLF, g/o/s/usemtl/mtllib accepted (no .mtl is read).
/// Vertex order and indices are the file's `v` order (unused vertices are kept). Normals are
/// kept when every corner has a `vn`: each vertex takes the first referencing corner's normal
/// (zero if unused); texcoords when every corner has a `vt`. No faces is an error.
TriMesh read_obj(std::string_view bytes, const std::string& name);
/// STL, ASCII or binary (detected by content, not by the word "solid"); attribute words are
/// ignored; corners with bit-identical coordinates (-0 = +0) are welded into one vertex, in
/// order of first appearance; degenerate facets are kept.
TriMesh read_stl(std::string_view bytes, const std::string& name);
/// PLY 1.0: ascii, binary_little_endian, binary_big_endian; `vertex` (x, y, z, optional
/// nx ny nz) and `face` (vertex_indices / vertex_index list), any other elements skipped.
TriMesh read_ply(std::string_view bytes, const std::string& name);
/// VRML97: every IndexedFaceSet reached through Group/Transform/Shape/Anchor/Collision/
/// Billboard/Switch(choice) nesting, DEF/USE, comments, optional commas, -1-separated
/// polygons (fan-triangulated), Transform nodes applied; all sets merged into one mesh.
TriMesh read_vrml(std::string_view bytes, const std::string& name);
/// Legacy VTK (version 2.0–5.1) DATASET POLYDATA, ASCII or BINARY (big-endian), POINTS and
/// POLYGONS (and TRIANGLE_STRIPS), polygons fan-triangulated.
TriMesh read_vtk(std::string_view bytes, const std::string& name);

/// Reads a mesh in the given format from memory.
TriMesh read_mesh(std::string_view bytes, MeshFormat format, const std::string& name);
/// Reads a mesh file, choosing the reader by extension. Throws FileError on any problem.
TriMesh load_mesh(const std::filesystem::path& path);

/// Appends `value` in the shortest form that reads back as the same double (std::to_chars):
/// what every text writer here prints numbers with.
void append_real(std::string& out, double value);

/// Writes OBJ text (v, optional vn, f with 1-based indices); positions printed with 17
/// significant digits so a reload gives the same doubles.
std::string write_obj(const TriMesh& mesh);
/// Writes binary STL (float32, as the format demands; one facet normal per triangle).
std::string write_stl_binary(const TriMesh& mesh);
/// Writes the mesh to a file, format from the extension (.obj or .stl); throws FileError.
void save_mesh(const TriMesh& mesh, const std::filesystem::path& path);

}  // namespace trocar
