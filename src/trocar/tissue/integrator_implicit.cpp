// Implicit (backward) Euler linearised once, solved by Jacobi-preconditioned conjugate
// gradients, matrix-free (Baraff & Witkin 1998, "Large steps in cloth simulation", §4–5).
//
// Derivation. Backward Euler for M ẍ = f(x, v):
//     Δx = h (v₀ + Δv),     M Δv = h f(x₀ + Δx, v₀ + Δv).
// One Newton step: f(x₀ + Δx, v₀ + Δv) ≈ f₀ + K Δx + D Δv with K = ∂f/∂x, D = ∂f/∂v, so
//     M Δv = h (f₀ + h K (v₀ + Δv) + D Δv)
//  ⇔ (M − h D − h² K) Δv = h (f₀ + h K v₀)                                     (A Δv = b)
// then v₁ = v₀ + Δv, x₁ = x₀ + h v₁. K and D are those of forces.h (negative semidefinite:
// springs with the compressed-spring transverse part clamped, Gauss–Newton area and volume
// terms, home springs; spring damping along the spring and −γ m), so A is symmetric positive
// definite and CG applies. f₀ is the step's one force evaluation (accumulate_forces plus
// loads.forces).
//
// Contacts. A penalty contact applies F = (k·depth + μ·approach speed)·n at the point
// Σ_b w_b x_b (the caller puts F into loads.forces; here only its Jacobian enters):
//     ∂f_a/∂x_b = −w_a w_b k n nᵀ,   ∂f_a/∂v_b = −w_a w_b μ n nᵀ,
// so (D + h K) p |_a = −(μ + h k) w_a n (Σ_b w_b n·p_b) and (K v₀)|_a = −k w_a n (Σ_b w_b n·v₀_b).
//
// Fixed vertices (Baraff–Witkin's filter S): b, the preconditioner and so every CG vector are
// zero there and A·p is filtered, so CG solves S A S Δv = S b and Δv = 0 on fixed vertices.
//
// What CG needs, computed once per step ("linearise"): K and D are constant during the solve,
// so rather than calling add_stiffness_product and add_damping_product (two passes over the
// springs, each with a square root per spring) every iteration, each spring's 3×3 block of
// D + h K is cached as a·u uᵀ + b·I: from forces.cpp, K_s = k [c I + (1 − c) u uᵀ] with
// c = max(0, 1 − l/|d|) (a degenerate spring: u = 0, c = 1, K_s = k I) and D_s = λ u uᵀ, so
//     (D_s + h K_s) δ = (λ + h k (1 − c)) (u·δ) u + h k c δ,   δ = p_j − p_i,
// added to i and subtracted from j. The volume term's Gauss–Newton stiffness is rank one,
// K_V = −κ_V ∇V ∇Vᵀ with κ_V = k_volume/V0 and ∇V_i = Σ_{t∋i} n_t/6, so its product is the
// scalar ∇V·p (accumulated in the pass that updates p) times the cached ∇V: O(V), no
// triangle pass. Home springs (−k_home I) and global damping (−γ m I) are diagonal. The area
// term alone goes through add_stiffness_product (only when k_area > 0).
// IntegratorImplicit.CachedProductsMatchForcesH checks all this against forces.h's products.
//
// Preconditioner: Jacobi, the exact diagonal of A per coordinate:
//     A_ii,c = m_i (1 + h γ) + h² k_home + h Σ_springs (a u_c² + b)
//              + h² κ_V (∇V_i,c)² + Σ_contacts (h μ + h² k) w_a² n_c²
// (the area term's diagonal is left out).
//
// Cost per step: one force evaluation, one pass over the springs (the cache, K v₀ and the
// diagonal together), one over the triangles (∇V, when the volume term is on); per CG
// iteration one pass over the cached springs and three fused passes over the vertices.
#include <algorithm>
#include <cmath>

#include "trocar/tissue/integrator.h"

namespace trocar {
namespace {

/// Same threshold as forces.cpp: below it a spring has no direction.
constexpr Real kTinyLength2 = 1e-30;

bool volume_on(const MassSpringSettings& s, const ForceTerms& t) {
  return t.volume && s.closed && s.k_volume > 0 && s.rest_volume > 0;
}
bool area_on(const MassSpringSettings& s, const ForceTerms& t) {
  return t.area && s.k_area > 0 && s.mean_rest_area > 0;
}
ForceTerms area_only() {
  ForceTerms t;
  t.springs = t.volume = t.home = t.global_damping = t.gravity = false;
  return t;
}

}  // namespace

void MassSpringIntegrator::linearise(const MassSpringState& state, Real h) {
  const Vec3* x = state.positions.data();
  const Vec3* v = state.velocities.data();
  Vec3* kv = product_.data();
  Vec3* diag = inverse_diagonal_.data();
  const std::size_t n = product_.size();

  // Diagonal terms: mass, global damping, home springs; K v₀ starts with the home springs.
  const Real gamma = terms_.global_damping ? settings_.damping : 0.0;
  const Real k_home = terms_.home ? settings_.k_home : 0.0;
  const Real* mass = settings_.masses.data();
  for (std::size_t i = 0; i < n; ++i) {
    diag[i].setConstant(mass[i] * (1 + h * gamma) + h * h * k_home);
    kv[i] = -k_home * v[i];
  }

  // Springs: cache (u, a, b), add K_s v₀ and h·(a u∘u + b) to the diagonal.
  CachedSpring* cache = spring_cache_.data();
  const std::size_t ns = terms_.springs ? settings_.springs.size() : 0;
  const Spring* springs = settings_.springs.data();
  for (std::size_t e = 0; e < ns; ++e) {
    const Spring& sp = springs[e];
    const Vec3 d = x[sp.j] - x[sp.i];
    const Real d2 = d.squaredNorm();
    const Real inv = d2 > kTinyLength2 ? 1.0 / std::sqrt(d2) : 0.0;
    const Vec3 u = d * inv;
    const Real c = std::max(Real{0}, 1.0 - sp.rest_length * inv);
    const Real hk = h * sp.stiffness;
    CachedSpring& cs = cache[e];
    cs.u = u;
    cs.a = sp.damping + hk * (1 - c);
    cs.b = hk * c;
    cs.i = sp.i;
    cs.j = sp.j;
    const Vec3 delta = v[sp.j] - v[sp.i];
    const Vec3 k_delta = sp.stiffness * (c * delta + ((1 - c) * u.dot(delta)) * u);
    kv[sp.i] += k_delta;
    kv[sp.j] -= k_delta;
    const Vec3 dd = h * (cs.a * u.cwiseProduct(u) + Vec3::Constant(cs.b));
    diag[sp.i] += dd;
    diag[sp.j] += dd;
  }

  // Volume: ∇V_i = Σ_{t∋i} n_t/6, K_V v₀ = −κ_V (∇V·v₀) ∇V, diagonal h² κ_V ∇V∘∇V.
  if (volume_on(settings_, terms_)) {
    Vec3* g = volume_gradient_.data();
    std::fill(volume_gradient_.begin(), volume_gradient_.end(), Vec3::Zero());
    for (const Triangle& t : settings_.triangles) {
      const Vec3 nt = (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]) / 6.0;
      g[t[0]] += nt;
      g[t[1]] += nt;
      g[t[2]] += nt;
    }
    const Real kappa = settings_.k_volume / settings_.rest_volume;
    Real slope = 0;
    for (std::size_t i = 0; i < n; ++i) slope += g[i].dot(v[i]);
    for (std::size_t i = 0; i < n; ++i) {
      kv[i] -= (kappa * slope) * g[i];
      diag[i] += (h * h * kappa) * g[i].cwiseProduct(g[i]);
    }
  }
  if (area_on(settings_, terms_)) add_stiffness_product(settings_, state.positions, state.velocities, product_, area_only());
}

Real MassSpringIntegrator::apply_system(const MassSpringState& state, const TissueLoads& loads, Real h,
                                        Real volume_slope) {
  const Vec3* p = direction_.data();
  Vec3* out = product_.data();  // zero on entry
  // Springs: out = (D + h K)_springs p.
  const CachedSpring* cache = spring_cache_.data();
  const std::size_t ns = terms_.springs ? spring_cache_.size() : 0;
  for (std::size_t e = 0; e < ns; ++e) {
    const CachedSpring& cs = cache[e];
    const Vec3 delta = p[cs.j] - p[cs.i];
    const Vec3 g = (cs.a * cs.u.dot(delta)) * cs.u + cs.b * delta;
    out[cs.i] += g;
    out[cs.j] -= g;
  }
  // Contacts: out_a += −(μ + h k) w_a n (Σ_b w_b n·p_b).
  for (const ContactJacobian& c : loads.contacts) {
    const Real s = c.weights[0] * c.normal.dot(p[c.vertices[0]]) + c.weights[1] * c.normal.dot(p[c.vertices[1]]) +
                   c.weights[2] * c.normal.dot(p[c.vertices[2]]);
    const Real g = -(c.damping + h * c.stiffness) * s;
    for (int k = 0; k < 3; ++k) out[c.vertices[k]] += (g * c.weights[k]) * c.normal;
  }
  const bool area = area_on(settings_, terms_);
  if (area) {
    std::fill(scratch_.begin(), scratch_.end(), Vec3::Zero());
    add_stiffness_product(settings_, state.positions, direction_, scratch_, area_only());
  }
  // A p = (m (1 + hγ) + h² k_home) p + h² κ_V (∇V·p) ∇V − h out − h² K_area p, filtered.
  const Real gamma = terms_.global_damping ? settings_.damping : 0.0;
  const Real c_home = terms_.home ? h * h * settings_.k_home : 0.0;
  const Real c_volume =
      volume_on(settings_, terms_) ? h * h * settings_.k_volume / settings_.rest_volume * volume_slope : 0.0;
  const Real* mass = settings_.masses.data();
  const Real* free = free_.data();
  const Vec3* gv = volume_gradient_.data();
  const Vec3* ka = scratch_.data();
  const std::size_t n = product_.size();
  Real pap = 0;
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 q = (mass[i] * (1 + h * gamma) + c_home) * p[i] + c_volume * gv[i] - h * out[i];
    if (area) q -= (h * h) * ka[i];
    q *= free[i];
    out[i] = q;
    pap += p[i].dot(q);
  }
  return pap;
}

StepStats MassSpringIntegrator::step_implicit(MassSpringState& state, const TissueLoads& loads, Real h) {
  begin_step(state, loads);
  const std::size_t n = forces_.size();
  Vec3* x = state.positions.data();
  Vec3* v = state.velocities.data();
  const Real* free = free_.data();
  Vec3* dv = dv_.data();
  Vec3* r = residual_.data();
  Vec3* p = direction_.data();
  Vec3* out = product_.data();
  Vec3* inverse_diagonal = inverse_diagonal_.data();
  const Vec3* gv = volume_gradient_.data();
  const bool volume = volume_on(settings_, terms_);

  // K v₀ into product_ and A's diagonal, then the contacts' share of both.
  linearise(state, h);
  for (const ContactJacobian& c : loads.contacts) {
    const Real s = c.weights[0] * c.normal.dot(v[c.vertices[0]]) + c.weights[1] * c.normal.dot(v[c.vertices[1]]) +
                   c.weights[2] * c.normal.dot(v[c.vertices[2]]);
    const Real g = -c.stiffness * s;
    const Vec3 nn = (h * c.damping + h * h * c.stiffness) * c.normal.cwiseProduct(c.normal);
    for (int k = 0; k < 3; ++k) {
      out[c.vertices[k]] += (g * c.weights[k]) * c.normal;
      inverse_diagonal[c.vertices[k]] += (c.weights[k] * c.weights[k]) * nn;
    }
  }

  // b = S h (f₀ + h K v₀) into r (Δv₀ = 0, so r₀ = b); z = P⁻¹ r, p = z, ρ = r·z; ∇V·p;
  // product_ zeroed for the first A p.
  const Vec3* f = forces_.data();
  Real bb = 0, rho = 0, slope = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 b = (free[i] * h) * (f[i] + h * out[i]);
    r[i] = b;
    bb += b.squaredNorm();
    dv[i].setZero();
    const Vec3 d = free[i] * inverse_diagonal[i].cwiseInverse();
    inverse_diagonal[i] = d;
    const Vec3 z = d.cwiseProduct(b);
    p[i] = z;
    rho += b.dot(z);
    out[i].setZero();
    if (volume) slope += gv[i].dot(z);
  }

  StepStats stats;
  const Real tolerance2 = options_.cg_tolerance * options_.cg_tolerance * bb;
  Real rr = bb;
  if (bb > 0 && std::isfinite(bb)) {
    while (stats.cg_iterations < options_.max_cg_iterations) {
      const Real pap = apply_system(state, loads, h, slope);
      if (!(pap > 0)) break;  // only with a non-finite (or, in error, indefinite) system
      const Real alpha = rho / pap;
      rr = 0;
      Real rho_next = 0;
      for (std::size_t i = 0; i < n; ++i) {
        dv[i] += alpha * p[i];
        r[i] -= alpha * out[i];
        rr += r[i].squaredNorm();
        rho_next += r[i].dot(inverse_diagonal[i].cwiseProduct(r[i]));
      }
      ++stats.cg_iterations;
      if (rr <= tolerance2) break;
      const Real beta = rho_next / rho;
      rho = rho_next;
      slope = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3 pi = inverse_diagonal[i].cwiseProduct(r[i]) + beta * p[i];
        p[i] = pi;
        out[i].setZero();
        if (volume) slope += gv[i].dot(pi);
      }
    }
  }
  stats.cg_residual = bb > 0 ? std::sqrt(rr / bb) : 0.0;

  // v₁ = v₀ + Δv, x₁ = x₀ + h v₁ (Δv = 0 at fixed vertices).
  Real check = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 vi = v[i] + dv[i];
    v[i] = vi;
    x[i] += h * vi;
    check += x[i].sum() + vi.sum();
  }
  end_step(state);
  stats.finite = std::isfinite(check) && std::isfinite(bb);
  return stats;
}

}  // namespace trocar
