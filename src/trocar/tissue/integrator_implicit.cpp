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
// What CG needs, computed once per step ("linearise", one pass over the springs and one over
// the triangles, which also evaluate the forces f₀ and h K v₀ — the same formulas as forces.cpp,
// so the spring and triangle geometry is computed once per step): K and D are constant during
// the solve, so each spring's block of A is cached as −(a u uᵀ + b I): from forces.cpp,
// K_s = k [c I + (1 − c) u uᵀ] with c = max(0, 1 − l/|d|) (a degenerate spring: u = 0, c = 1,
// K_s = k I) and D_s = λ u uᵀ, so with a = h (λ + h k (1 − c)), b = h² k c and δ = p_j − p_i,
//     g = a (u·δ) u + b δ   is subtracted from (A p)_i and added to (A p)_j.
// The area term's Gauss–Newton stiffness is rank one per triangle: each triangle caches
// g_c = h √κ ∂A/∂x_c and adds (Σ_c g_c·p_c) g_c to (A p)_c. The volume term's is rank one over
// the mesh, K_V = −κ_V ∇V ∇Vᵀ with κ_V = k_volume/V0 and ∇V_i = Σ_{t∋i} n_t/6, so its product
// is the scalar ∇V·p (accumulated in the pass that updates p) times the cached ∇V. Home
// springs (−k_home I) and global damping (−γ m I) are diagonal. pᵀ A p is accumulated term by
// term inside these passes (δ·g per spring, (g·p)² per triangle, h² κ_V (∇V·p)², m|p|²), so
// a CG iteration is one pass over the cached springs, one over the cached triangles (only when
// k_area > 0) and two over the vertices.
// Integrator.ImplicitStepSolvesTheBackwardEulerSystemOfForcesH checks the whole solve against
// forces.h's products, so a change in forces.cpp that is not mirrored here fails it.
//
// Preconditioner: block Jacobi, the exact 3×3 diagonal blocks of A, inverted once per step:
//     A_ii = (m_i (1 + h γ) + h² k_home) I + Σ_springs (a u uᵀ + b I) + Σ_triangles g_c g_cᵀ
//            + h² κ_V ∇V_i ∇V_iᵀ + Σ_contacts (h μ + h² k) w_a² n nᵀ.
// (On the liver it takes 6.7 iterations per step where the per-coordinate diagonal takes 8.6.)
//
// Warm start: CG starts from the previous step's Δv (kept in dv_), at the cost of one extra
// product. On the liver bench (state reset every 64 steps) it saves 1.2–1.5 iterations per step
// (7.98 → 6.73 at cg_tolerance 1e-4, 13.78 → 12.27 at 1e-6), 3.5 % of the step net.
// Stopping: |r| ≤ cg_tolerance |b|, or the block-Jacobi estimate of the remaining error in Δv,
// max_i |A_ii⁻¹ r_i|, ≤ cg_tolerance × 0.1 m/s (near equilibrium |b| → 0 and a purely relative
// test would polish noise); at least one iteration always runs.
#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "trocar/tissue/integrator.h"
#include "trocar/tissue/internal.h"

namespace trocar {
namespace {

using namespace tissue_detail;

/// The absolute stopping floor, per unit of cg_tolerance: CG also stops when the block-Jacobi
/// estimate of the remaining velocity error, max_i |(A_ii)⁻¹ r_i|, is below
/// kVelocityFloorPerTolerance · cg_tolerance (1e-5 m/s at the default 1e-4).
constexpr Real kVelocityFloorPerTolerance = 0.1;  // m/s

/// A symmetric 3×3 block (xx, yy, zz, xy, xz, yz) += scale · a aᵀ.
inline void add_outer(Real* m, Real scale, const P3& a) {
  m[0] += scale * a.x * a.x;
  m[1] += scale * a.y * a.y;
  m[2] += scale * a.z * a.z;
  m[3] += scale * a.x * a.y;
  m[4] += scale * a.x * a.z;
  m[5] += scale * a.y * a.z;
}
/// inv[k] = len2[k] > kTinyLength2 ? 1/√len2[k] : 0 for k < m; bit for bit the scalar
/// expression (IEEE square root and division are correctly rounded in every lane).
inline void safe_inverse_sqrts(const Real* len2, Real* inv, std::size_t m) {
  std::size_t k = 0;
#if defined(__SSE2__)
  const __m128d tiny = _mm_set1_pd(kTinyLength2);
  const __m128d one = _mm_set1_pd(1.0);
  for (; k + 2 <= m; k += 2) {
    const __m128d l = _mm_loadu_pd(len2 + k);
    const __m128d r = _mm_div_pd(one, _mm_sqrt_pd(_mm_max_pd(l, tiny)));
    _mm_storeu_pd(inv + k, _mm_and_pd(_mm_cmpgt_pd(l, tiny), r));  // 0 where not > tiny (or NaN)
  }
#endif
  for (; k < m; ++k) inv[k] = len2[k] > kTinyLength2 ? 1.0 / std::sqrt(len2[k]) : 0.0;
}

}  // namespace

void MassSpringIntegrator::linearise(const MassSpringState& state, const TissueLoads& loads, Real h) {
  const MassSpringSettings& s = settings_;
  const Vec3* x = state.positions.data();
  const Vec3* v = state.velocities.data();
  Vec3* f = forces_.data();  // external forces on entry; f₀ + h K v₀ on exit
  Sym3* diag = preconditioner_.data();
  Real* dm = diagonal_mass_.data();
  const std::size_t n = forces_.size();

  // Per-vertex terms: gravity m g, global damping −γ m v (D = −γ m I), home springs
  // −k_home (x − x0) (K = −k_home I, so h K v₀ = −h k_home v₀); A_ii starts at m (1 + hγ) + h² k_home.
  {
    const Real gamma = terms_.global_damping ? s.damping : 0.0;
    const Real k_home = terms_.home ? s.k_home : 0.0;
    const P3 g = terms_.gravity ? load(s.gravity) : P3{0, 0, 0};
    const Real* mass = s.masses.data();
    const Vec3* x0 = s.home_positions.data();
    for (std::size_t i = 0; i < n; ++i) {
      const P3 vi = load(v[i]);
      add_to(f[i], mass[i] * (g - gamma * vi) - k_home * (load(x[i]) - load(x0[i]) + h * vi));
      const Real d = mass[i] * (1 + h * gamma) + h * h * k_home;
      dm[i] = d;
      diag[i] = {{d, d, d, 0, 0, 0}};
    }
  }

  // Springs, one pass: the force (as forces.cpp), h K_s v₀, the cached block of A, and A_ii.
  // K_s = k [c I + (1 − c) u uᵀ], c = max(0, 1 − l/|d|), D_s = λ u uᵀ; A's off-diagonal block
  // is −h (D_s + h K_s) = −(a u uᵀ + b I) with a = h (λ + h k (1 − c)), b = h² k c.
  if (terms_.springs) {
    const Spring* springs = s.springs.data();
    CachedSpring* cache = spring_cache_.data();
    const std::size_t ns = s.springs.size();
    // In chunks: the lengths first, then every 1/|d| of the chunk in one SIMD loop (so the
    // square roots and divisions pipeline instead of heading one long chain per spring).
    constexpr std::size_t kChunk = 64;
    alignas(16) Real chunk_len2[kChunk], chunk_inv[kChunk];
    for (std::size_t e = 0; e < ns; ++e) {
      const std::size_t slot = e % kChunk;
      if (slot == 0) {
        const std::size_t m = std::min(kChunk, ns - e);
        for (std::size_t q = 0; q < m; ++q) {
          const Spring& sq = springs[e + q];
          const P3 dq = load(x[sq.j]) - load(x[sq.i]);
          chunk_len2[q] = dot(dq, dq);
        }
        safe_inverse_sqrts(chunk_len2, chunk_inv, m);
      }
      const Spring& sp = springs[e];
      const P3 d = load(x[sp.j]) - load(x[sp.i]);
      const P3 dvel = load(v[sp.j]) - load(v[sp.i]);
      const Real len2 = chunk_len2[slot];
      const Real inv = chunk_inv[slot];
      const Real len = len2 * inv;
      const Real sigma = sp.stiffness * (len - sp.rest_length) * inv + sp.damping * dot(dvel, d) * inv * inv;
      const P3 u = inv * d;
      const Real c = std::max(Real{0}, 1.0 - sp.rest_length * inv);
      const Real hk = h * sp.stiffness;
      const Real a = h * (sp.damping + hk * (1 - c));
      const Real b = h * hk * c;
      CachedSpring& cs = cache[e];
      cs.u[0] = u.x;
      cs.u[1] = u.y;
      cs.u[2] = u.z;
      cs.b = b;
      cs.a = a;
      cs.i = sp.i;
      cs.j = sp.j;
      // f_i += σ d + h k (c δv + (1 − c)(u·δv) u), f_j −= the same.
      const P3 t = sigma * d + hk * (c * dvel + ((1 - c) * dot(u, dvel)) * u);
      add_to(f[sp.i], t);
      subtract_from(f[sp.j], t);
      const Real blk[6] = {a * u.x * u.x + b, a * u.y * u.y + b, a * u.z * u.z + b,
                           a * u.x * u.y,     a * u.x * u.z,     a * u.y * u.z};
      for (int k = 0; k < 6; ++k) {
        diag[sp.i].m[k] += blk[k];
        diag[sp.j].m[k] += blk[k];
      }
    }
  }

  // Triangles, one pass: area force, h K_A v₀ and the cached g_c = h √κ ∂A/∂x_c (forces.cpp's
  // formulas), and ∇V_i = Σ_{t∋i} n_t/6 with 6V = Σ (a − o)·n_t.
  const bool area = area_term_on(s, terms_);
  const bool volume = volume_term_on(s, terms_);
  if (area || volume) {
    const Triangle* tris = s.triangles.data();
    const Real* rest = s.rest_areas.data();
    const std::size_t nt = s.triangles.size();
    const Real kappa = area ? s.k_area / s.mean_rest_area : 0.0;
    const Real h_sqrt_kappa = h * std::sqrt(kappa);
    CachedTriangle* cache = triangle_cache_.data();
    Vec3* gv = volume_gradient_.data();
    if (volume) std::fill(volume_gradient_.begin(), volume_gradient_.end(), Vec3::Zero());
    const P3 origin = load(x[tris[0][0]]);
    Real six_v = 0;
    for (std::size_t t = 0; t < nt; ++t) {
      const Triangle& tri = tris[t];
      const P3 pa = load(x[tri[0]]), pb = load(x[tri[1]]), pc = load(x[tri[2]]);
      const P3 nrm = cross(pb - pa, pc - pa);
      if (volume) {
        six_v += dot(pa - origin, nrm);
        const P3 g6 = (1.0 / 6.0) * nrm;
        add_to(gv[tri[0]], g6);
        add_to(gv[tri[1]], g6);
        add_to(gv[tri[2]], g6);
      }
      if (!area) continue;
      const Real n2 = dot(nrm, nrm);
      const Real inv = n2 > kTinyNormal2 ? 1.0 / std::sqrt(n2) : 0.0;
      const Real half_inv = 0.5 * inv;
      const P3 ga = half_inv * cross(nrm, pc - pb);  // ∂A/∂x_a
      const P3 gb = half_inv * cross(nrm, pa - pc);
      const P3 gc = half_inv * cross(nrm, pb - pa);
      // f_c = −κ (A − A0) ∂A/∂x_c − h κ (∇A·v₀) ∂A/∂x_c.
      const Real slope = dot(ga, load(v[tri[0]])) + dot(gb, load(v[tri[1]])) + dot(gc, load(v[tri[2]]));
      const Real coef = -kappa * (0.5 * n2 * inv - rest[t] + h * slope);
      add_to(f[tri[0]], coef * ga);
      add_to(f[tri[1]], coef * gb);
      add_to(f[tri[2]], coef * gc);
      CachedTriangle& ct = cache[t];
      const P3 g[3] = {h_sqrt_kappa * ga, h_sqrt_kappa * gb, h_sqrt_kappa * gc};
      for (int k = 0; k < 3; ++k) {
        store(ct.g[k], g[k]);
        ct.v[k] = tri[k];
        add_outer(diag[tri[k]].m, 1.0, g[k]);
      }
    }
    if (volume) {
      // f += (−κ_V (V − V0) − h κ_V (∇V·v₀)) ∇V;  A_ii += h² κ_V ∇V_i ∇V_iᵀ.
      const Real kappa_v = s.k_volume / s.rest_volume;
      Real slope = 0;
      for (std::size_t i = 0; i < n; ++i) slope += gv[i].dot(v[i]);
      const Real coef = -kappa_v * (six_v / 6.0 - s.rest_volume + h * slope);
      const Real c2 = h * h * kappa_v;
      for (std::size_t i = 0; i < n; ++i) {
        const P3 g = load(gv[i]);
        add_to(f[i], coef * g);
        add_outer(diag[i].m, c2, g);
      }
    }
  }

  // Contacts: h K v₀ at a = −h k w_a n (Σ_b w_b n·v₀_b); A_aa += (h μ + h² k) w_a² n nᵀ.
  for (const ContactJacobian& c : loads.contacts) {
    const P3 nn = load(c.normal);
    const Real sv = c.weights[0] * dot(nn, load(v[c.vertices[0]])) + c.weights[1] * dot(nn, load(v[c.vertices[1]])) +
                    c.weights[2] * dot(nn, load(v[c.vertices[2]]));
    const Real g = -h * c.stiffness * sv;
    const Real w = h * c.damping + h * h * c.stiffness;
    for (int k = 0; k < 3; ++k) {
      add_to(f[c.vertices[k]], (g * c.weights[k]) * nn);
      add_outer(diag[c.vertices[k]].m, w * c.weights[k] * c.weights[k], nn);
    }
  }
}

Real MassSpringIntegrator::apply_system(const TissueLoads& loads, Real h, Real volume_slope) {
  const Vec3* p = direction_.data();
  Vec3* out = product_.data();  // diagonal_mass_ · p on entry
  Real pap_springs = 0, pap_triangles = 0, pap_contacts = 0;
  // Springs: g = a (u·δ) u + b δ, δ = p_j − p_i; (A p)_i −= g, (A p)_j += g; pᵀ A p gains δ·g.
  if (terms_.springs) {
    const CachedSpring* cache = spring_cache_.data();
    const std::size_t ns = spring_cache_.size();
    Real acc0 = 0, acc1 = 0;
    std::size_t e = 0;
    const auto one = [&](const CachedSpring& cs) {
      const P3 u = load(cs.u);
      const P3 delta = load(p[cs.j]) - load(p[cs.i]);
      const Real ud = dot(u, delta);
      const P3 g = (cs.a * ud) * u + cs.b * delta;
      subtract_from(out[cs.i], g);
      add_to(out[cs.j], g);
      return cs.a * ud * ud + cs.b * dot(delta, delta);
    };
    for (; e + 1 < ns; e += 2) {
      acc0 += one(cache[e]);
      acc1 += one(cache[e + 1]);
    }
    if (e < ns) acc0 += one(cache[e]);
    pap_springs = acc0 + acc1;
  }
  // Area (Gauss–Newton, rank one per triangle): (A p)_c += (Σ g·p) g_c.
  if (area_term_on(settings_, terms_)) {
    const CachedTriangle* cache = triangle_cache_.data();
    const std::size_t nt = triangle_cache_.size();
    for (std::size_t t = 0; t < nt; ++t) {
      const CachedTriangle& ct = cache[t];
      const P3 g0 = load(ct.g[0]), g1 = load(ct.g[1]), g2 = load(ct.g[2]);
      const Real sl = dot(g0, load(p[ct.v[0]])) + dot(g1, load(p[ct.v[1]])) + dot(g2, load(p[ct.v[2]]));
      add_to(out[ct.v[0]], sl * g0);
      add_to(out[ct.v[1]], sl * g1);
      add_to(out[ct.v[2]], sl * g2);
      pap_triangles += sl * sl;
    }
  }
  // Contacts: (A p)_a += (h μ + h² k) w_a n (Σ_b w_b n·p_b).
  for (const ContactJacobian& c : loads.contacts) {
    const P3 nn = load(c.normal);
    const Real sl = c.weights[0] * dot(nn, load(p[c.vertices[0]])) + c.weights[1] * dot(nn, load(p[c.vertices[1]])) +
                    c.weights[2] * dot(nn, load(p[c.vertices[2]]));
    const Real g = (h * c.damping + h * h * c.stiffness) * sl;
    for (int k = 0; k < 3; ++k) add_to(out[c.vertices[k]], (g * c.weights[k]) * nn);
    pap_contacts += g * sl;
  }
  // Volume: h² κ_V (∇V·p) ∇V is added in the vertex pass; its share of pᵀ A p is h² κ_V (∇V·p)².
  const Real pap_volume =
      volume_term_on(settings_, terms_) ? h * h * settings_.k_volume / settings_.rest_volume * volume_slope * volume_slope : 0.0;
  return pap_springs + pap_triangles + pap_contacts + pap_volume;
}

namespace {
/// The inverse of a symmetric positive definite 3×3 block (xx, yy, zz, xy, xz, yz) by cofactors.
inline void invert_sym3(const Real* a, Real* inv) {
  const Real c00 = a[1] * a[2] - a[5] * a[5];
  const Real c11 = a[0] * a[2] - a[4] * a[4];
  const Real c22 = a[0] * a[1] - a[3] * a[3];
  const Real c01 = a[4] * a[5] - a[3] * a[2];
  const Real c02 = a[3] * a[5] - a[4] * a[1];
  const Real c12 = a[3] * a[4] - a[0] * a[5];
  const Real det = a[0] * c00 + a[3] * c01 + a[4] * c02;
  const Real r = 1.0 / det;
  inv[0] = c00 * r;
  inv[1] = c11 * r;
  inv[2] = c22 * r;
  inv[3] = c01 * r;
  inv[4] = c02 * r;
  inv[5] = c12 * r;
}
inline P3 sym3_times(const Real* m, const P3& r) {
  return {m[0] * r.x + m[3] * r.y + m[4] * r.z, m[3] * r.x + m[1] * r.y + m[5] * r.z,
          m[4] * r.x + m[5] * r.y + m[2] * r.z};
}
inline Real max_abs(const P3& a) { return std::max(std::abs(a.x), std::max(std::abs(a.y), std::abs(a.z))); }
}  // namespace

StepStats MassSpringIntegrator::step_implicit(MassSpringState& state, const TissueLoads& loads, Real h) {
  for (std::size_t k = 0; k < fixed_indices_.size(); ++k) {
    fixed_positions_[k] = state.positions[fixed_indices_[k]];
    state.velocities[fixed_indices_[k]].setZero();
  }
  if (use_avx2_ && implicit_avx2_ && tissue_detail::ImplicitAvx2::supports(settings_, terms_)) {
    const StepStats stats = implicit_avx2_->step(state, loads, h, terms_, options_);
    end_step(state);
    return stats;
  }
  if (loads.forces().size() == forces_.size())
    std::copy(loads.forces().begin(), loads.forces().end(), forces_.begin());
  else
    std::fill(forces_.begin(), forces_.end(), Vec3::Zero());
  linearise(state, loads, h);

  const std::size_t n = forces_.size();
  Vec3* x = state.positions.data();
  Vec3* v = state.velocities.data();
  const Real* free = free_.data();
  const Real* dm = diagonal_mass_.data();
  Vec3* dv = dv_.data();
  Vec3* r = residual_.data();
  Vec3* p = direction_.data();
  Vec3* z = scratch_.data();
  Vec3* out = product_.data();
  Sym3* pre = preconditioner_.data();
  const Vec3* gv = volume_gradient_.data();
  const bool volume = volume_term_on(settings_, terms_);
  const Real c_volume = volume ? h * h * settings_.k_volume / settings_.rest_volume : 0.0;
  const Vec3* f = forces_.data();

  // b = S h (f₀ + h K v₀); the preconditioner inverted (0 at fixed vertices); the warm start
  // Δv (the previous step's, 0 at fixed vertices) as p for the first product.
  Real bb = 0, slope = 0;
  bool warm = false;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 b = (free[i] * h) * f[i];
    r[i] = b;
    bb += b.squaredNorm();
    Sym3& m = pre[i];
    if (free[i] != 0) {
      Real inv[6];
      invert_sym3(m.m, inv);
      std::copy(inv, inv + 6, m.m);
    } else {
      m = {{0, 0, 0, 0, 0, 0}};
    }
    const Vec3 d = free[i] * dv[i];
    p[i] = d;
    warm = warm || !d.isZero(0);
    out[i] = dm[i] * d;
    if (volume) slope += gv[i].dot(d);
  }

  StepStats stats;
  if (!(bb > 0 && std::isfinite(bb)) || !warm) {
    for (std::size_t i = 0; i < n; ++i) dv[i].setZero();
    warm = false;
  }
  // r₀ = b − A Δv₀ (warm start), z₀ = P⁻¹ r₀, p₀ = z₀; the next product's diagonal part.
  if (warm) apply_system(loads, h, slope);
  const Real warm_volume = c_volume * slope;
  Real rho = 0, rr = 0, mpp = 0;  // mpp = Σ diagonal_mass |p|², the diagonal's share of pᵀ A p
  slope = 0;
  for (std::size_t i = 0; i < n; ++i) {
    P3 ri = load(r[i]);
    if (warm) {
      ri = ri - free[i] * (load(out[i]) + warm_volume * load(gv[i]));
      r[i] = Vec3(ri.x, ri.y, ri.z);
    }
    rr += dot(ri, ri);
    const P3 zi = sym3_times(pre[i].m, ri);
    rho += dot(ri, zi);
    p[i] = Vec3(zi.x, zi.y, zi.z);
    out[i] = dm[i] * p[i];
    mpp += dm[i] * dot(zi, zi);
    if (volume) slope += gv[i].dot(p[i]);
  }
  const Real tolerance2 = options_.cg_tolerance * options_.cg_tolerance * bb;
  const Real floor = kVelocityFloorPerTolerance * options_.cg_tolerance;
  if (bb > 0 && std::isfinite(bb) && rr > 0) {
    while (stats.cg_iterations < options_.max_cg_iterations) {
      const Real pap = mpp + apply_system(loads, h, slope);
      if (!(pap > 0)) break;  // only with a non-finite (or, in error, indefinite) system
      const Real alpha = rho / pap;
      const Real cv = c_volume * slope;
      rr = 0;
      Real rho_next = 0, zmax = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const P3 q = free[i] * (load(out[i]) + cv * load(gv[i]));
        const P3 pi = load(p[i]);
        const P3 ri = load(r[i]) - alpha * q;
        add_to(dv[i], alpha * pi);
        r[i] = Vec3(ri.x, ri.y, ri.z);
        rr += dot(ri, ri);
        const P3 zi = sym3_times(pre[i].m, ri);
        z[i] = Vec3(zi.x, zi.y, zi.z);
        rho_next += dot(ri, zi);
        zmax = std::max(zmax, max_abs(zi));
      }
      ++stats.cg_iterations;
      if (rr <= tolerance2 || zmax <= floor) break;
      const Real beta = rho_next / rho;
      rho = rho_next;
      slope = 0;
      mpp = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3 pi = z[i] + beta * p[i];
        p[i] = pi;
        out[i] = dm[i] * pi;
        mpp += dm[i] * pi.squaredNorm();
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
  if (!stats.finite) std::fill(dv_.begin(), dv_.end(), Vec3::Zero());  // no warm start from garbage
  return stats;
}

}  // namespace trocar
