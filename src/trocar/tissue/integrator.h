#pragma once
/// Time integration of a mass-spring tissue.
#include <cstdint>
#include <string_view>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/tissue/forces.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"

namespace trocar {

/// The integrators a scene can choose per tissue (DESIGN.md §5 "integrator").
enum class IntegratorKind {
  kExplicitEuler,      ///< x += h v; v += h a(x, v)           (the seed's)
  kSemiImplicitEuler,  ///< v += h a(x, v); x += h v          (symplectic)
  kImplicitEuler,      ///< backward Euler, one Newton step, CG (Baraff & Witkin 1998)
};

/// "explicit-euler", "semi-implicit-euler", "implicit-euler".
const char* integrator_name(IntegratorKind kind);
/// Parses the names above; throws trocar::Error listing the valid names.
IntegratorKind integrator_from_name(std::string_view name);

/// Options of the implicit solve.
struct ImplicitOptions {
  int max_cg_iterations = 100;   ///< conjugate-gradient iteration cap
  Real cg_tolerance = 1e-6;      ///< relative residual |r|/|b| to stop at
};

/// What one step did (for metrics and tests).
struct StepStats {
  int cg_iterations = 0;         ///< implicit only
  Real cg_residual = 0;          ///< implicit only: final relative residual
  bool finite = true;            ///< false when a position or velocity became non-finite
};

/// Steps one tissue. Holds scratch buffers sized at construction, so step() never allocates.
class MassSpringIntegrator {
 public:
  MassSpringIntegrator(const MassSpringSettings& settings, IntegratorKind kind, ImplicitOptions options = {});

  /// Advances `state` by dt seconds under the internal forces and `loads` (external forces,
  /// and for the implicit integrator also the contacts' Jacobians). Fixed vertices keep
  /// their position bit for bit and zero velocity.
  StepStats step(MassSpringState& state, const TissueLoads& loads, Real dt);

  IntegratorKind kind() const { return kind_; }
  const MassSpringSettings& settings() const { return settings_; }
  ForceTerms& terms() { return terms_; }  ///< which force terms are on (all by default)

 private:
  StepStats step_explicit(MassSpringState& state, const TissueLoads& loads, Real dt, bool symplectic);
  StepStats step_implicit(MassSpringState& state, const TissueLoads& loads, Real dt);
  /// Saves the fixed vertices' positions, zeroes their velocities, and evaluates
  /// forces_ = loads.forces + f(x, v) (the step's one force evaluation).
  void begin_step(MassSpringState& state, const TissueLoads& loads);
  /// Restores the fixed vertices' positions bit for bit and zeroes their velocities.
  void end_step(MassSpringState& state) const;
  /// out = A·p with A = M − h·∂f/∂v − h²·∂f/∂x (contacts included), filtered (0 at fixed
  /// vertices); needs scratch_ = h·p and product_ = 0 on entry. Returns p·A·p.
  Real apply_system(const MassSpringState& state, const TissueLoads& loads, Real h);

  const MassSpringSettings& settings_;
  IntegratorKind kind_;
  ImplicitOptions options_;
  ForceTerms terms_;
  // Scratch, sized V at construction (none for the implicit solve unless kind_ is implicit).
  // Implicit: dv_ is Δv, residual_ the CG residual r, direction_ the direction p, scratch_
  // h·p, product_ first ∂f/∂x·v then A·p.
  std::vector<Vec3> forces_, dv_, residual_, direction_, product_, scratch_;
  std::vector<Real> inverse_diagonal_;   ///< Jacobi preconditioner 1/A_ii (0 at fixed vertices)
  std::vector<Real> free_;               ///< 1 for free vertices, 0 for fixed (the filter S)
  std::vector<Real> spring_damping_sum_; ///< Σ λ over the springs at each vertex (N·s/m)
  std::vector<Real> spring_stiffness_sum_;  ///< Σ k over the springs at each vertex (N/m)
  std::vector<std::uint32_t> fixed_indices_;  ///< the fixed vertices
  std::vector<Vec3> fixed_positions_;    ///< their positions at the start of a step
};

}  // namespace trocar
