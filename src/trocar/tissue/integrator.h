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
  /// One spring's linearisation for the current step (see integrator_implicit.cpp):
  /// (∂f/∂v + h·∂f/∂x) applied to δ = p_j − p_i is a·(u·δ)·u + b·δ on i and its negative on j.
  struct CachedSpring {
    Vec3 u;              ///< unit direction x_j − x_i (0 when degenerate)
    Real a = 0;          ///< λ + h·k·(1 − c) (N·s/m), c the clamped transverse factor
    Real b = 0;          ///< h·k·c (N·s/m)
    std::uint32_t i = 0, j = 0;
  };
  /// Builds spring_cache_, volume_gradient_ and the Jacobi diagonal for this step and adds
  /// ∂f/∂x·v (springs, volume, area, home; contacts separately) to product_.
  void linearise(const MassSpringState& state, Real h);
  /// product_ = A·p (direction_), filtered; returns p·A·p. `volume_slope` = ∇V·p.
  Real apply_system(const MassSpringState& state, const TissueLoads& loads, Real h, Real volume_slope);

  const MassSpringSettings& settings_;
  IntegratorKind kind_;
  ImplicitOptions options_;
  ForceTerms terms_;
  // Scratch, sized V at construction (the implicit solve's only for the implicit kind).
  // Implicit: dv_ is Δv, residual_ the CG residual r, direction_ the direction p, product_
  // A·p, scratch_ the area term's ∂f/∂x·p.
  std::vector<Vec3> forces_, dv_, residual_, direction_, product_, scratch_;
  std::vector<Vec3> inverse_diagonal_;   ///< Jacobi preconditioner 1/A_ii per coordinate (0 at fixed)
  std::vector<Vec3> volume_gradient_;    ///< ∇V at this step's positions (m²)
  std::vector<CachedSpring> spring_cache_;  ///< per spring, rebuilt once per implicit step
  std::vector<Real> free_;               ///< 1 for free vertices, 0 for fixed (the filter S)
  std::vector<std::uint32_t> fixed_indices_;  ///< the fixed vertices
  std::vector<Vec3> fixed_positions_;    ///< their positions at the start of a step
};

}  // namespace trocar
