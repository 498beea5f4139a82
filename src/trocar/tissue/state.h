#pragma once
/// Per-instance state of a tissue and the loads the collision response puts on it.
#include <array>
#include <cstdint>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

struct MassSpringSettings;

/// Positions and velocities: everything that changes, cheap to copy into a snapshot.
struct MassSpringState {
  std::vector<Vec3> positions;   ///< x_i (m)
  std::vector<Vec3> velocities;  ///< v_i (m/s)

  /// The rest state of `settings`, at rest.
  static MassSpringState at_rest(const MassSpringSettings& settings);
};

/// One penalty contact's linearisation, for implicit integration. The response applies a
/// force F = (k·depth + μ·approach speed)·n at a point with barycentric weights w over three
/// tissue vertices, so ∂f_a/∂x_b = −w_a·w_b·k·n nᵀ and ∂f_a/∂v_b = −w_a·w_b·μ·n nᵀ.
struct ContactJacobian {
  std::array<std::uint32_t, 3> vertices{};  ///< tissue triangle's vertices
  std::array<Real, 3> weights{};            ///< barycentric weights of the contact point
  Vec3 normal = Vec3::UnitZ();              ///< unit direction of the penalty force
  Real stiffness = 0;                       ///< k (N/m)
  Real damping = 0;                         ///< μ (N·s/m)
};

/// External loads for one step: forces per vertex (the response's penalty forces) and the
/// contacts' Jacobians. Sized once (reserve) and cleared every step without freeing memory.
struct TissueLoads {
  std::vector<Vec3> forces;                 ///< N per vertex (size V)
  std::vector<ContactJacobian> contacts;    ///< capacity reserved up front

  /// Sizes the arrays for `vertex_count` vertices and up to `max_contacts` contacts.
  void reset(std::size_t vertex_count, std::size_t max_contacts = 1024);
  /// Zeroes the forces and empties the contacts (no deallocation).
  void clear();
};

}  // namespace trocar
