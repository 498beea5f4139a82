// Integrator selection, shared per-step bookkeeping, and the two explicit integrators.
// The implicit (backward Euler + conjugate gradients) integrator is in integrator_implicit.cpp.
// docs/tissue-integrators.md states each integrator's stability limit.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

#include "trocar/core/error.h"
#include "trocar/tissue/integrator.h"
#include "trocar/tissue/internal.h"

namespace trocar {

const char* integrator_name(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::kExplicitEuler: return "explicit-euler";
    case IntegratorKind::kSemiImplicitEuler: return "semi-implicit-euler";
    case IntegratorKind::kImplicitEuler: return "implicit-euler";
    case IntegratorKind::kXpbd: return "xpbd";
  }
  return "unknown";
}

IntegratorKind integrator_from_name(std::string_view name) {
  for (IntegratorKind kind : {IntegratorKind::kExplicitEuler, IntegratorKind::kSemiImplicitEuler,
                              IntegratorKind::kImplicitEuler, IntegratorKind::kXpbd})
    if (name == integrator_name(kind)) return kind;
  throw Error("unknown integrator \"" + std::string(name) +
              "\" (valid: explicit-euler, semi-implicit-euler, implicit-euler, xpbd)");
}

MassSpringIntegrator::MassSpringIntegrator(const MassSpringSettings& settings, IntegratorKind kind,
                                           ImplicitOptions options, XpbdOptions xpbd)
    : settings_(settings), kind_(kind), options_(options) {
  if (kind == IntegratorKind::kXpbd) {
    xpbd_ = std::make_unique<XpbdSolver>(settings, xpbd);
    return;
  }
  const std::size_t n = settings.vertex_count();
  free_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    free_[i] = settings.fixed[i] ? 0.0 : 1.0;
    if (settings.fixed[i]) fixed_indices_.push_back(static_cast<std::uint32_t>(i));
  }
  fixed_positions_.assign(fixed_indices_.size(), Vec3::Zero());
  use_avx2_ = cpu_has_avx2_fma();
  if (kind != IntegratorKind::kImplicitEuler) {
    set_explicit_sweep(tissue_detail::sweep_pays(settings));
    // The pass-by-pass step's arrays and layouts, unless only the sweep can run: it does while
    // the AVX2 passes and the sweep stay on and the area term cannot apply (k_area = 0); the
    // setters build them when they turn either off.
    if (!explicit_sweep() || settings.k_area > 0) build_passes();
    return;
  }

  if (use_avx2_) implicit_avx2_ = std::make_unique<tissue_detail::ImplicitAvx2>(settings);
  forces_.assign(n, Vec3::Zero());
  volume_gradient_.assign(n, Vec3::Zero());
  dv_.assign(n, Vec3::Zero());
  residual_.assign(n, Vec3::Zero());
  direction_.assign(n, Vec3::Zero());
  product_.assign(n, Vec3::Zero());
  scratch_.assign(n, Vec3::Zero());
  preconditioner_.resize(n);
  diagonal_mass_.assign(n, 0.0);
  spring_cache_.resize(settings.springs.size());
  triangle_cache_.resize(settings.triangles.size());
}

void MassSpringIntegrator::build_passes() {
  if (kind_ == IntegratorKind::kImplicitEuler || kind_ == IntegratorKind::kXpbd || passes_built_) return;
  const std::size_t n = settings_.vertex_count();
  padded_.allocate(n, 5);
  pair_forces_ = padded_[0];
  padded_volume_gradient_ = padded_[1];
  padded_positions_ = padded_[2];
  padded_velocities_ = padded_[3];
  padded_rest_ = padded_[4];
  tissue_detail::copy_padded(settings_.home_positions.data(), n, padded_rest_.data());
  spring_layout_ = tissue_detail::make_spring_layout(settings_.springs, n, &settings_.fixed);
  volume_layout_ = tissue_detail::make_volume_layout(settings_.triangles, n);
  passes_built_ = true;
}

void MassSpringIntegrator::home_moved() {
  if (passes_built_)
    tissue_detail::copy_padded(settings_.home_positions.data(), settings_.vertex_count(), padded_rest_.data());
  if (implicit_avx2_) implicit_avx2_->home_moved(settings_);
}

bool MassSpringIntegrator::springs_changed(std::span<const std::uint32_t> springs) {
  if (kind_ != IntegratorKind::kXpbd) return false;
  xpbd_->springs_changed(springs);
  return true;
}

void MassSpringIntegrator::set_simd(bool on) {
  use_avx2_ = on && cpu_has_avx2_fma();
  if (kind_ == IntegratorKind::kXpbd) return;
  if (!explicit_sweep()) build_passes();
}

void MassSpringIntegrator::set_explicit_sweep(bool on) {
  if (kind_ == IntegratorKind::kXpbd) return;
  sweep_on_ = on && kind_ != IntegratorKind::kImplicitEuler && cpu_has_avx2_fma();
  if (sweep_on_ && !sweep_) sweep_ = std::make_unique<tissue_detail::ExplicitSweep>(settings_);
  if (!explicit_sweep()) build_passes();
}

StepStats MassSpringIntegrator::step(MassSpringState& state, const TissueLoads& loads, Real dt) {
  assert(state.positions.size() == settings_.vertex_count());
  assert(state.velocities.size() == settings_.vertex_count());
  switch (kind_) {
    case IntegratorKind::kExplicitEuler: return step_explicit(state, loads, dt, false);
    case IntegratorKind::kSemiImplicitEuler: return step_explicit(state, loads, dt, true);
    case IntegratorKind::kImplicitEuler: {
      StepStats stats = step_implicit(state, loads, dt);
      stats.constraint_error = stats.cg_residual;
      return stats;
    }
    case IntegratorKind::kXpbd: {
      const XpbdStats x = xpbd_->step(state, loads, dt, contacts_);
      StepStats stats;
      stats.substeps = xpbd_->options().substeps;
      stats.constraint_error = x.max_strain;
      stats.finite = std::isfinite(x.max_strain);
      return stats;
    }
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
/// ignored. The forces are accumulate_forces', evaluated in three passes (explicit_kernels.h):
/// springs and area into a padded force array, and the external forces added to it at the
/// loaded vertices only; the volume term as one triangle pass (in fans) that sums V and
/// Σ_{t∋i} n_t per vertex; and the per-vertex terms (gravity, global damping, home springs, the
/// volume pressure) inside the update pass. The arithmetic order
/// differs from accumulate_forces' (and the AVX2 code uses FMA), so the two agree to rounding.
StepStats MassSpringIntegrator::step_explicit(MassSpringState& state, const TissueLoads& loads, Real dt,
                                              bool symplectic) {
  using namespace tissue_detail;
  const MassSpringSettings& s = settings_;
  for (std::size_t k = 0; k < fixed_indices_.size(); ++k) {
    fixed_positions_[k] = state.positions[fixed_indices_[k]];
    state.velocities[fixed_indices_[k]].setZero();
  }
  Vec3* x = state.positions.data();
  Vec3* v = state.velocities.data();
  StepStats stats;
  if (explicit_sweep() && !area_term_on(s, terms_)) {
    stats.finite = std::isfinite(sweep_->step(x, v, loads, terms_, dt, symplectic));
    end_step(state);
    return stats;
  }
  assert(passes_built_);
  const std::size_t n = s.vertex_count();
  copy_padded(x, n, padded_positions_.data());
  copy_padded(v, n, padded_velocities_.data());
  if (terms_.springs) add_spring_forces(spring_layout_, padded_positions_.data(), padded_velocities_.data(),
                                        pair_forces_.data(), use_avx2_);
  if (terms_.area) add_area_forces(s, x, pair_forces_.data());

  UpdateInputs in;
  in.x = padded_positions_.data();
  in.v = padded_velocities_.data();
  in.rest = padded_rest_.data();
  in.pair = pair_forces_.data();
  // External forces: only at the vertices the step loaded (TissueLoads), into the pair forces.
  add_external_forces(loads, pair_forces_.data(), n);
  // Volume: 6V = Σ (a − o)·n_t about o = the first triangle's first vertex (as forces.cpp), and
  // 6 ∂V/∂x_i = Σ_{t∋i} n_t; the pressure force is −κ_V (V − V0) ∂V/∂x_i.
  if (terms_.volume && s.closed && s.k_volume > 0 && s.rest_volume > 0 && !s.triangles.empty()) {
    const Real six_v =
        add_volume_gradient(volume_layout_, padded_positions_.data(), padded_volume_gradient_.data(), use_avx2_);
    in.gradient = padded_volume_gradient_.data();
    in.pressure6 = -s.k_volume / s.rest_volume * (six_v / 6.0 - s.rest_volume) / 6.0;
  }
  in.k_home = terms_.home ? s.k_home : 0.0;
  in.gamma = terms_.global_damping ? s.damping : 0.0;
  in.gravity = terms_.gravity ? s.gravity : Vec3::Zero();
  in.dt = dt;
  in.symplectic = symplectic;
  // Σ of every coordinate: NaN or ±inf there iff some coordinate is non-finite (or the sum of
  // finite ones overflows, beyond any physical scale), checked once per step.
  const Real check = explicit_update(s, x, v, in, use_avx2_);
  end_step(state);
  stats.finite = std::isfinite(check);
  return stats;
}

}  // namespace trocar
