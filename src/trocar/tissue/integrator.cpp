// Integrator selection, shared per-step bookkeeping, and the two explicit integrators.
// The implicit (backward Euler + conjugate gradients) integrator is in integrator_implicit.cpp.
// docs/tissue-integrators.md states each integrator's stability limit.
#include <cassert>
#include <cmath>
#include <string>

#include "trocar/core/error.h"
#include "trocar/tissue/integrator.h"

namespace trocar {

const char* integrator_name(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::kExplicitEuler: return "explicit-euler";
    case IntegratorKind::kSemiImplicitEuler: return "semi-implicit-euler";
    case IntegratorKind::kImplicitEuler: return "implicit-euler";
  }
  return "unknown";
}

IntegratorKind integrator_from_name(std::string_view name) {
  for (IntegratorKind kind :
       {IntegratorKind::kExplicitEuler, IntegratorKind::kSemiImplicitEuler, IntegratorKind::kImplicitEuler})
    if (name == integrator_name(kind)) return kind;
  throw Error("unknown integrator \"" + std::string(name) +
              "\" (valid: explicit-euler, semi-implicit-euler, implicit-euler)");
}

MassSpringIntegrator::MassSpringIntegrator(const MassSpringSettings& settings, IntegratorKind kind,
                                           ImplicitOptions options)
    : settings_(settings), kind_(kind), options_(options) {
  const std::size_t n = settings.vertex_count();
  forces_.assign(n, Vec3::Zero());
  free_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    free_[i] = settings.fixed[i] ? 0.0 : 1.0;
    if (settings.fixed[i]) fixed_indices_.push_back(static_cast<std::uint32_t>(i));
  }
  fixed_positions_.assign(fixed_indices_.size(), Vec3::Zero());
  if (kind != IntegratorKind::kImplicitEuler) return;

  dv_.assign(n, Vec3::Zero());
  residual_.assign(n, Vec3::Zero());
  direction_.assign(n, Vec3::Zero());
  product_.assign(n, Vec3::Zero());
  scratch_.assign(n, Vec3::Zero());
  preconditioner_.resize(n);
  diagonal_mass_.assign(n, 0.0);
  volume_gradient_.assign(n, Vec3::Zero());
  spring_cache_.resize(settings.springs.size());
  triangle_cache_.resize(settings.triangles.size());
  spring_order_.resize(settings.springs.size());
  for (std::size_t e = 0; e < spring_order_.size(); ++e) spring_order_[e] = static_cast<std::uint32_t>(e);
}

StepStats MassSpringIntegrator::step(MassSpringState& state, const TissueLoads& loads, Real dt) {
  assert(state.positions.size() == settings_.vertex_count());
  assert(state.velocities.size() == settings_.vertex_count());
  switch (kind_) {
    case IntegratorKind::kExplicitEuler: return step_explicit(state, loads, dt, false);
    case IntegratorKind::kSemiImplicitEuler: return step_explicit(state, loads, dt, true);
    case IntegratorKind::kImplicitEuler: return step_implicit(state, loads, dt);
  }
  return {};
}

void MassSpringIntegrator::begin_step(MassSpringState& state, const TissueLoads& loads) {
  for (std::size_t k = 0; k < fixed_indices_.size(); ++k) {
    fixed_positions_[k] = state.positions[fixed_indices_[k]];
    state.velocities[fixed_indices_[k]].setZero();
  }
  // The external forces start the sum (or zero when the caller sized no force array).
  if (loads.forces.size() == forces_.size())
    std::copy(loads.forces.begin(), loads.forces.end(), forces_.begin());
  else
    std::fill(forces_.begin(), forces_.end(), Vec3::Zero());
  accumulate_forces(settings_, state.positions, state.velocities, forces_, terms_);
}

void MassSpringIntegrator::end_step(MassSpringState& state) const {
  // The update loops run over every vertex without a branch; fixed vertices have 1/m = 0 (or
  // Δv = 0), so they only lose the sign of a zero coordinate there, which this undoes.
  for (std::size_t k = 0; k < fixed_indices_.size(); ++k) {
    state.positions[fixed_indices_[k]] = fixed_positions_[k];
    state.velocities[fixed_indices_[k]].setZero();
  }
}

/// Explicit Euler (the seed's):       x₁ = x₀ + h v₀,  v₁ = v₀ + h M⁻¹ f(x₀, v₀).
/// Semi-implicit (symplectic) Euler:  v₁ = v₀ + h M⁻¹ f(x₀, v₀),  x₁ = x₀ + h v₁.
/// External forces (and contact penalties) enter f as plain forces; contact Jacobians are
/// ignored. One force evaluation and one fused pass over the vertices per step.
StepStats MassSpringIntegrator::step_explicit(MassSpringState& state, const TissueLoads& loads, Real dt,
                                              bool symplectic) {
  begin_step(state, loads);
  Vec3* x = state.positions.data();
  Vec3* v = state.velocities.data();
  const Vec3* f = forces_.data();
  const Real* inverse_mass = settings_.inverse_masses.data();
  const std::size_t n = forces_.size();
  // Σ of every coordinate: NaN or ±inf there iff some coordinate is non-finite (or the sum of
  // finite ones overflows, beyond any physical scale), checked once per step.
  Real check = 0;
  if (symplectic) {
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 vi = v[i] + (dt * inverse_mass[i]) * f[i];
      v[i] = vi;
      x[i] += dt * vi;
      check += x[i].sum() + vi.sum();
    }
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 vi = v[i];
      x[i] += dt * vi;
      v[i] = vi + (dt * inverse_mass[i]) * f[i];
      check += x[i].sum() + v[i].sum();
    }
  }
  end_step(state);
  StepStats stats;
  stats.finite = std::isfinite(check);
  return stats;
}

}  // namespace trocar
