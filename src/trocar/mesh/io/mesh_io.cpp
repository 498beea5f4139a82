#include "trocar/mesh/io/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

namespace trocar {

const char* format_name(MeshFormat format) {
  switch (format) {
    case MeshFormat::kObj: return "obj";
    case MeshFormat::kStl: return "stl";
    case MeshFormat::kPly: return "ply";
    case MeshFormat::kVrml: return "vrml";
    case MeshFormat::kVtk: return "vtk";
  }
  return "unknown";
}

MeshFormat format_from_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".obj") return MeshFormat::kObj;
  if (ext == ".stl") return MeshFormat::kStl;
  if (ext == ".ply") return MeshFormat::kPly;
  if (ext == ".wrl" || ext == ".vrml") return MeshFormat::kVrml;
  if (ext == ".vtk") return MeshFormat::kVtk;
  throw FileError(path.string(), FileLocation::none(),
                  "unknown mesh extension '" + ext + "' (expected .obj .stl .ply .wrl .vtk)");
}

TriMesh read_mesh(std::string_view bytes, MeshFormat format, const std::string& name) {
  switch (format) {
    case MeshFormat::kObj: return read_obj(bytes, name);
    case MeshFormat::kStl: return read_stl(bytes, name);
    case MeshFormat::kPly: return read_ply(bytes, name);
    case MeshFormat::kVrml: return read_vrml(bytes, name);
    case MeshFormat::kVtk: return read_vtk(bytes, name);
  }
  throw FileError(name, FileLocation::none(), "unknown mesh format");
}

TriMesh load_mesh(const std::filesystem::path& path) {
  const MeshFormat format = format_from_path(path);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw FileError(path.string(), FileLocation::none(), "no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path.string(), FileLocation::none(), "cannot open for reading");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw FileError(path.string(), FileLocation::none(), "read error");
  return read_mesh(buffer.str(), format, path.string());
}

void save_mesh(const TriMesh& mesh, const std::filesystem::path& path) {
  const MeshFormat format = format_from_path(path);
  std::string bytes;
  if (format == MeshFormat::kObj) {
    bytes = write_obj(mesh);
  } else if (format == MeshFormat::kStl) {
    bytes = write_stl_binary(mesh);
  } else {
    throw FileError(path.string(), FileLocation::none(),
                    std::string("writing ") + format_name(format) + " is not supported (use .obj or .stl)");
  }
  std::ofstream out(path, std::ios::binary);
  if (!out) throw FileError(path.string(), FileLocation::none(), "cannot open for writing");
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw FileError(path.string(), FileLocation::none(), "write failed");
}

}  // namespace trocar
