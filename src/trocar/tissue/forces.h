#pragma once
/// Internal forces, energies and force Jacobian products of the mass-spring model.
/// Each term is a function over the whole arrays, so integrators compose them; none allocates.
#include <span>

#include "trocar/core/types.h"
#include "trocar/tissue/settings.h"

namespace trocar {

/// Which terms to include (tests switch terms on one at a time).
struct ForceTerms {
  bool springs = true;          ///< structural + bending springs, eq. 3.2 (elastic + damping)
  bool area = true;             ///< area constraint
  bool volume = true;           ///< volume constraint (closed meshes)
  bool home = true;             ///< home springs
  bool global_damping = true;   ///< −γ m v (eq. 3.1)
  bool gravity = true;          ///< m g
};

/// Adds the internal forces (N) at positions x, velocities v to `forces` (size V; the caller
/// zeroes it). Fixed vertices receive forces too; integrators ignore them.
void accumulate_forces(const MassSpringSettings& s, std::span<const Vec3> x, std::span<const Vec3> v,
                       std::span<Vec3> forces, const ForceTerms& terms = {});

/// Potential energy (J) of the elastic terms (springs, area, volume, home) and of gravity
/// (−Σ m g·x), so that accumulate_forces' conservative part is −∇ of it.
Real potential_energy(const MassSpringSettings& s, std::span<const Vec3> x, const ForceTerms& terms = {});
/// Kinetic energy ½ Σ m v² (J).
Real kinetic_energy(const MassSpringSettings& s, std::span<const Vec3> v);

/// out += (∂f/∂x)·dx at positions x (the stiffness matrix times a vector, matrix-free), for the
/// terms selected. Springs use the positive-semidefinite-projected Hessian (the transverse part
/// is clamped when a spring is compressed) so that conjugate gradients stay applicable.
void add_stiffness_product(const MassSpringSettings& s, std::span<const Vec3> x, std::span<const Vec3> dx,
                           std::span<Vec3> out, const ForceTerms& terms = {});
/// out += (∂f/∂v)·dv (the damping matrix times a vector): spring damping along each spring
/// and global damping −γ m.
void add_damping_product(const MassSpringSettings& s, std::span<const Vec3> x, std::span<const Vec3> dv,
                         std::span<Vec3> out, const ForceTerms& terms = {});

}  // namespace trocar
