#pragma once
/// Per-instance state of a tissue and the loads the collision response puts on it.
#include <array>
#include <cstdint>
#include <span>
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
/// contacts' Jacobians. Sized once (reset) and cleared every step without freeing memory.
///
/// Forces are added through add_force, which also records the vertex: a step usually loads a
/// few dozen of a tissue's thousands of vertices, so clear() zeroes only those and the explicit
/// integrators add only those (docs/tissue-integrators.md, "The AVX2 passes"); forces() is
/// still the dense array (zero where nothing was added).
class TissueLoads {
 public:
  std::vector<ContactJacobian> contacts;  ///< capacity reserved up front

  /// Sizes the arrays for `vertex_count` vertices and up to `max_contacts` contacts; all zero.
  void reset(std::size_t vertex_count, std::size_t max_contacts = 1024);
  /// Zeroes the forces added since the last clear and empties the contacts (no deallocation).
  void clear();
  /// forces()[vertex] += f (N). `vertex` < the size given to reset; never allocates.
  void add_force(std::uint32_t vertex, const Vec3& f);

  /// N per vertex: size V after reset (empty before: no external forces).
  std::span<const Vec3> forces() const { return forces_; }
  /// The vertices given to add_force since the last clear, each once, in the order first added.
  std::span<const std::uint32_t> loaded_vertices() const { return loaded_; }

 private:
  std::vector<Vec3> forces_;
  std::vector<std::uint32_t> loaded_;     ///< capacity V: push_back never reallocates
  std::vector<std::uint8_t> is_loaded_;   ///< 1 for the vertices in loaded_
};

/// Perfectly plastic home springs: every free vertex further than `settings.home_yield` from its
/// anchor drags the anchor along the line between them to that distance. Returns whether an
/// anchor moved (the integrator must then be told: MassSpringIntegrator::home_moved()). No-op
/// when the yield or k_home is 0.
bool yield_home(MassSpringSettings& settings, const MassSpringState& state);

}  // namespace trocar
