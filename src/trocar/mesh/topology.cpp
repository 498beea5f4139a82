#include "trocar/mesh/topology.h"

#include "trocar/core/error.h"

namespace trocar {

MeshTopology::MeshTopology(const TriMesh&) { throw Error("MeshTopology: not implemented yet"); }
bool MeshTopology::traverses_forward(const TriMesh&, std::size_t, std::size_t) const { return false; }

}  // namespace trocar
