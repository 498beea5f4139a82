// Placeholder: the obj reader lands here. Replace this whole file.
#include "trocar/mesh/io/mesh_io.h"

namespace trocar {

TriMesh read_obj(std::string_view, const std::string& name) {
  throw FileError(name, FileLocation::none(), "obj reader not implemented yet");
}

}  // namespace trocar
