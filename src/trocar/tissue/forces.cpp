// Placeholder: the force terms land here. Replace this whole file.
#include "trocar/tissue/forces.h"

namespace trocar {

void accumulate_forces(const MassSpringSettings&, std::span<const Vec3>, std::span<const Vec3>, std::span<Vec3>,
                       const ForceTerms&) {}
Real potential_energy(const MassSpringSettings&, std::span<const Vec3>, const ForceTerms&) { return 0; }
Real kinetic_energy(const MassSpringSettings&, std::span<const Vec3>) { return 0; }
void add_stiffness_product(const MassSpringSettings&, std::span<const Vec3>, std::span<const Vec3>, std::span<Vec3>,
                           const ForceTerms&) {}
void add_damping_product(const MassSpringSettings&, std::span<const Vec3>, std::span<const Vec3>, std::span<Vec3>,
                         const ForceTerms&) {}

}  // namespace trocar
