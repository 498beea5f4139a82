// Integrator selection, shared per-step bookkeeping, and the two explicit integrators.
// The implicit (backward Euler + conjugate gradients) integrator is in integrator_implicit.cpp.
// docs/tissue-integrators.md states each integrator's stability limit.
#include <algorithm>
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
  volume_gradient_.assign(n, Vec3::Zero());
  if (kind != IntegratorKind::kImplicitEuler) return;

  dv_.assign(n, Vec3::Zero());
  residual_.assign(n, Vec3::Zero());
  direction_.assign(n, Vec3::Zero());
  product_.assign(n, Vec3::Zero());
  scratch_.assign(n, Vec3::Zero());
  preconditioner_.resize(n);
  diagonal_mass_.assign(n, 0.0);
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
/// ignored. The forces are those of accumulate_forces, evaluated in fewer passes: the springs
/// and the area term through accumulate_forces; the volume term as one triangle pass that sums
/// V and Σ_{t∋i} n_t per vertex; and the per-vertex terms (gravity, global damping, home
/// springs, the volume pressure) inside the update pass itself. Without the volume term the
/// forces are bit for bit accumulate_forces' (the same additions in the same order).
StepStats MassSpringIntegrator::step_explicit(MassSpringState& state, const TissueLoads& loads, Real dt,
                                              bool symplectic) {
  const MassSpringSettings& s = settings_;
  for (std::size_t k = 0; k < fixed_indices_.size(); ++k) {
    fixed_positions_[k] = state.positions[fixed_indices_[k]];
    state.velocities[fixed_indices_[k]].setZero();
  }
  // The external forces start the sum (or zero when the caller sized no force array), in the
  // order accumulate_forces would add the rest, so that the rounding is the same.
  if (loads.forces.size() == forces_.size())
    std::copy(loads.forces.begin(), loads.forces.end(), forces_.begin());
  else
    std::fill(forces_.begin(), forces_.end(), Vec3::Zero());
  ForceTerms pair_terms = terms_;  // springs and area only
  pair_terms.volume = pair_terms.home = pair_terms.global_damping = pair_terms.gravity = false;
  accumulate_forces(s, state.positions, state.velocities, forces_, pair_terms);

  Vec3* x = state.positions.data();
  Vec3* v = state.velocities.data();
  const std::size_t n = forces_.size();
  // Volume: 6V = Σ (a − o)·n_t about o = the first triangle's first vertex (as forces.cpp), and
  // 6 ∂V/∂x_i = Σ_{t∋i} n_t; the pressure force is −κ_V (V − V0) ∂V/∂x_i.
  const bool volume = terms_.volume && s.closed && s.k_volume > 0 && s.rest_volume > 0 && !s.triangles.empty();
  Real pressure6 = 0;  // −κ_V (V − V0)/6
  if (volume) {
    Vec3* g = volume_gradient_.data();
    std::fill(volume_gradient_.begin(), volume_gradient_.end(), Vec3::Zero());
    const Vec3 origin = x[s.triangles.front()[0]];
    Real six_v = 0;
    for (const Triangle& t : s.triangles) {
      const Real a0 = x[t[0]][0], a1 = x[t[0]][1], a2 = x[t[0]][2];
      const Real e0 = x[t[1]][0] - a0, e1 = x[t[1]][1] - a1, e2 = x[t[1]][2] - a2;
      const Real f0 = x[t[2]][0] - a0, f1 = x[t[2]][1] - a1, f2 = x[t[2]][2] - a2;
      const Real n0 = e1 * f2 - e2 * f1, n1 = e2 * f0 - e0 * f2, n2 = e0 * f1 - e1 * f0;
      six_v += (a0 - origin[0]) * n0 + (a1 - origin[1]) * n1 + (a2 - origin[2]) * n2;
      for (int k = 0; k < 3; ++k) {
        Vec3& gk = g[t[k]];
        gk[0] += n0;
        gk[1] += n1;
        gk[2] += n2;
      }
    }
    pressure6 = -s.k_volume / s.rest_volume * (six_v / 6.0 - s.rest_volume) / 6.0;
  }

  const Real k_home = terms_.home ? s.k_home : 0.0;
  const Real gamma = terms_.global_damping ? s.damping : 0.0;
  const Vec3 gravity = terms_.gravity ? s.gravity : Vec3::Zero();
  const Vec3* x0 = s.rest_positions.data();
  const Real* mass = s.masses.data();
  const Real* inverse_mass = s.inverse_masses.data();
  const Vec3* gv = volume ? volume_gradient_.data() : nullptr;
  const Vec3* fp = forces_.data();
  // Σ of every coordinate: NaN or ±inf there iff some coordinate is non-finite (or the sum of
  // finite ones overflows, beyond any physical scale), checked once per step.
  Real check = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 xi = x[i], vi = v[i];
    Vec3 f = fp[i];
    if (gv != nullptr) f += pressure6 * gv[i];
    f += mass[i] * (gravity - gamma * vi) - k_home * (xi - x0[i]);
    const Vec3 v1 = vi + (dt * inverse_mass[i]) * f;
    const Vec3 x1 = xi + dt * (symplectic ? v1 : vi);
    v[i] = v1;
    x[i] = x1;
    check += x1.sum() + v1.sum();
  }
  end_step(state);
  StepStats stats;
  stats.finite = std::isfinite(check);
  return stats;
}

}  // namespace trocar
