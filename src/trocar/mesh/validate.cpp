#include "trocar/mesh/validate.h"

#include "trocar/core/error.h"

namespace trocar {

const char* orientation_name(Orientation orientation) {
  switch (orientation) {
    case Orientation::kOutward: return "outward";
    case Orientation::kInward: return "inward";
    case Orientation::kUndefined: break;
  }
  return "undefined";
}

std::vector<std::string> MeshReport::defects() const { return {}; }
bool MeshReport::is_clean() const { return false; }
bool MeshReport::is_clean_open() const { return false; }

MeshReport validate(const TriMesh&, const ValidateOptions&) { throw Error("validate: not implemented yet"); }

}  // namespace trocar
