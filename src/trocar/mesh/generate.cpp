#include "trocar/mesh/generate.h"

#include "trocar/core/error.h"

namespace trocar {

TriMesh make_icosphere(Real, int) { throw Error("make_icosphere: not implemented yet"); }
TriMesh make_sheet(Real, Real, std::size_t, std::size_t, Real) { throw Error("make_sheet: not implemented yet"); }
TriMesh make_capsule(Real, Real, std::size_t, std::size_t) { throw Error("make_capsule: not implemented yet"); }
TriMesh make_cylinder(Real, Real, std::size_t, bool) { throw Error("make_cylinder: not implemented yet"); }
TriMesh make_box(Real, Real, Real) { throw Error("make_box: not implemented yet"); }

}  // namespace trocar
