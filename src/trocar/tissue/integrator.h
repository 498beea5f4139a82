#pragma once
/// Time integration of a mass-spring tissue.
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

  const MassSpringSettings& settings_;
  IntegratorKind kind_;
  ImplicitOptions options_;
  ForceTerms terms_;
  // Scratch, sized V at construction.
  std::vector<Vec3> forces_, rhs_, dv_, residual_, direction_, product_, scratch_;
};

}  // namespace trocar
