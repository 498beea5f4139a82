#include "trocar/mesh/repair.h"

#include "trocar/core/error.h"

namespace trocar {

bool RepairReport::changed() const { return false; }
std::vector<std::string> RepairReport::summary() const { return {}; }
RepairReport repair(TriMesh&, const RepairOptions&) { throw Error("repair: not implemented yet"); }
std::vector<std::uint32_t> vertex_representatives(const std::vector<Vec3>&, Real) {
  throw Error("vertex_representatives: not implemented yet");
}

}  // namespace trocar
