// Placeholder: the vrml reader lands here. Replace this whole file.
#include "trocar/mesh/io/mesh_io.h"

namespace trocar {

TriMesh read_vrml(std::string_view, const std::string& name) {
  throw FileError(name, FileLocation::none(), "vrml reader not implemented yet");
}

}  // namespace trocar
