// Internal forces of the mass-spring tissue, their energies and their Jacobian products.
//
// Conventions used throughout this file:
//  * A spring joins x_i and x_j; d = x_j − x_i, |d| its length, u = d/|d| its unit direction.
//  * A triangle (a, b, c) is counter-clockwise seen from outside; n = (b − a) × (c − a) is
//    twice its area vector, so A = ½|n| and n̂ = n/|n|.
//  * "∂f/∂x" is the Jacobian of the force (not of the energy): for conservative terms it is
//    −∇²E, so every product below applies a negative-semidefinite matrix.
//  * Degenerate geometry (a spring shorter than kTinyLength, a triangle with |n|² below
//    kTinyNormal2) contributes no direction-dependent force: the direction is undefined there,
//    and taking it as zero keeps every result finite (no 0/0).
// Every loop reads the flat arrays once and writes through raw pointers; none allocates.
#include "trocar/tissue/forces.h"

#include "trocar/tissue/explicit_kernels.h"
#include "trocar/tissue/internal.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace trocar {
namespace {

using namespace tissue_detail;

// The same into the explicit integrators' padded force layout.
inline void add_to(Padded3& f, const P3& a) {
  f.x += a.x;
  f.y += a.y;
  f.z += a.z;
}


// ---------------------------------------------------------------------------------------------
// Springs (eq. 3.2)
//
// Elastic: E = ½ k (|d| − l)², f_i = −∂E/∂x_i = k (|d| − l) u, f_j = −f_i.
// Damping: f_i = λ ((v_j − v_i)·u) u, f_j = −f_i; along the spring only, so a rigid motion
// (v_j − v_i = ω × d ⟂ d) is not damped.
// Both share the direction, so f_i = σ d with σ = k(|d| − l)/|d| + λ (Δv·d)/|d|²: one sqrt and
// one division per spring.
[[gnu::noinline]] void spring_forces(const MassSpringSettings& s, const Vec3* x, const Vec3* v, Vec3* f) {
  const Spring* sp = s.springs.data();
  const std::size_t n = s.springs.size();
  for (std::size_t e = 0; e < n; ++e) {
    const Spring& p = sp[e];
    const P3 d = load(x[p.j]) - load(x[p.i]);
    const P3 dv = load(v[p.j]) - load(v[p.i]);
    const Real len2 = dot(d, d);
    const Real inv = safe_inverse_sqrt(len2, kTinyLength2);
    const Real len = len2 * inv;  // |d| (0 when degenerate)
    const Real sigma = p.stiffness * (len - p.rest_length) * inv + p.damping * dot(dv, d) * inv * inv;
    const P3 fi = sigma * d;
    add_to(f[p.i], fi);
    subtract_from(f[p.j], fi);
  }
}

Real spring_energy(const MassSpringSettings& s, const Vec3* x) {
  Real e = 0;
  for (const Spring& p : s.springs) {
    const Real stretch = (x[p.j] - x[p.i]).norm() - p.rest_length;
    e += 0.5 * p.stiffness * stretch * stretch;
  }
  return e;
}

// Stiffness: with d = x_j − x_i, ∂f_i/∂x_j = K, ∂f_i/∂x_i = −K, and f_j = −f_i, where
//   K = ∂(k(|d| − l) u)/∂d = k [ u uᵀ + (1 − l/|d|)(I − u uᵀ) ]
// (∂|d|/∂d = uᵀ, ∂u/∂d = (I − u uᵀ)/|d|). So out_i += K (dx_j − dx_i), out_j −= the same.
// PSD projection: when the spring is compressed (|d| < l) the transverse factor 1 − l/|d| is
// negative and the spring buckles (K indefinite); we clamp it to max(0, 1 − l/|d|) so K ⪰ 0 and
// the assembled ∂f/∂x = −[K −K; −K K] ⪯ 0, as conjugate gradients on (M − h²∂f/∂x) requires.
// Stretched springs (|d| ≥ l) are exact. A degenerate spring (inv = 0) gets K = k I, which is
// exact for a zero-rest-length spring (f = k d). The x-derivative of the damping force
// (through u) is left out, as in Baraff & Witkin 1998.
[[gnu::noinline]] void spring_stiffness_product(const MassSpringSettings& s, const Vec3* x, const Vec3* dx, Vec3* out) {
  const Spring* sp = s.springs.data();
  const std::size_t n = s.springs.size();
  for (std::size_t e = 0; e < n; ++e) {
    const Spring& p = sp[e];
    const P3 d = load(x[p.j]) - load(x[p.i]);
    const Real inv = safe_inverse_sqrt(dot(d, d), kTinyLength2);
    const P3 u = inv * d;
    const Real c = std::max(Real{0}, 1.0 - p.rest_length * inv);
    const P3 delta = load(dx[p.j]) - load(dx[p.i]);
    const P3 k_delta = p.stiffness * (c * delta + ((1.0 - c) * dot(u, delta)) * u);
    add_to(out[p.i], k_delta);
    subtract_from(out[p.j], k_delta);
  }
}

// Damping: ∂f_i/∂v_j = λ u uᵀ, ∂f_i/∂v_i = −λ u uᵀ (exact; u does not depend on v).
[[gnu::noinline]] void spring_damping_product(const MassSpringSettings& s, const Vec3* x, const Vec3* dv, Vec3* out) {
  const Spring* sp = s.springs.data();
  const std::size_t n = s.springs.size();
  for (std::size_t e = 0; e < n; ++e) {
    const Spring& p = sp[e];
    const P3 d = load(x[p.j]) - load(x[p.i]);
    const Real len2 = dot(d, d);
    const Real inv2 = len2 > kTinyLength2 ? 1.0 / len2 : 0.0;
    // λ u (u·Δv) = λ d (d·Δv)/|d|²: no sqrt needed.
    const P3 g = (p.damping * dot(d, load(dv[p.j]) - load(dv[p.i])) * inv2) * d;
    add_to(out[p.i], g);
    subtract_from(out[p.j], g);
  }
}

// ---------------------------------------------------------------------------------------------
// Area and volume constraints
//
// Area: E_t = ½ κ (A − A0)² with κ = k_area/Ā0. A = ½|n|, dA = ½ n̂·dn and, for a corner
// displacement da, dn = da × (b − c), so n̂·(da × (b − c)) = da·((b − c) × n̂) and
//   ∂A/∂x_a = ½ n̂ × (c − b),  ∂A/∂x_b = ½ n̂ × (a − c),  ∂A/∂x_c = ½ n̂ × (b − a)
// (cyclic). Force f_a = −κ (A − A0) ∂A/∂x_a. These three sum to zero and are unchanged by a
// rigid motion, so the term is frame-invariant.
//
// Volume: V = Σ_t (a − o)·((b − o) × (c − o))/6 for any origin o (exact for a closed mesh);
// (a − o)·((b − o) × (c − o)) = (a − o)·n, and we take o = the current position of the first
// triangle's first vertex so the sum is accurate however far the organ is from the world origin.
// (Its contribution to the gradient is zero: V does not depend on o for a closed mesh.)
// ∂V/∂x_v = Σ_{t∋v} (b_t − o) × (c_t − o)/6 (a, b, c cyclic with v = a). Around a closed vertex
// ring Σ (c_t − b_t) = 0, so the sum does not depend on o; choosing o = x_v gives
//   ∂V/∂x_v = Σ_{t∋v} n_t/6,
// i.e. each triangle pushes all three corners by n_t/6: a pressure p = −κ_V (V − V0),
// κ_V = k_volume/V0, on every triangle. Two passes over the triangles: V, then the pressure.
// (On an open mesh this per-triangle form is not the gradient of anything: settings.closed
// switches the term off there.)

/// Corner positions and n = (b − a) × (c − a) of triangle t.
struct TriangleGeometry {
  P3 a, b, c, n;
};
inline TriangleGeometry triangle_geometry(const Triangle& tri, const Vec3* x) {
  const P3 a = load(x[tri[0]]);
  const P3 b = load(x[tri[1]]);
  const P3 c = load(x[tri[2]]);
  return {a, b, c, cross(b - a, c - a)};
}

// Each pass below is its own (non-inlined) loop: fusing the area pass with the volume sum, or
// inlining the loops into one function, made GCC spill registers and ran up to 1.8× slower on
// the liver than separate passes (measured with g++ 12 -O3, SSE2).

/// Area forces f_a += −κ (A − A0) ∂A/∂x_a over all triangles.
template <class Force>
[[gnu::noinline]] void area_forces(const MassSpringSettings& s, const Vec3* x, Force* f) {
  const Triangle* tris = s.triangles.data();
  const Real* rest = s.rest_areas.data();
  const std::size_t nt = s.triangles.size();
  const Real kappa = s.k_area / s.mean_rest_area;
  for (std::size_t t = 0; t < nt; ++t) {
    const Triangle& tri = tris[t];
    const TriangleGeometry g = triangle_geometry(tri, x);
    const Real n2 = dot(g.n, g.n);
    const Real inv = safe_inverse_sqrt(n2, kTinyNormal2);
    const Real area = 0.5 * n2 * inv;
    // f_a = −κ (A − A0) · ½ n̂ × (c − b) with n̂ = n·inv (and cyclic for b, c).
    const Real coef = -kappa * (area - rest[t]) * 0.5 * inv;
    add_to(f[tri[0]], coef * cross(g.n, g.c - g.b));
    add_to(f[tri[1]], coef * cross(g.n, g.a - g.c));
    add_to(f[tri[2]], coef * cross(g.n, g.b - g.a));
  }
}

/// V of a closed mesh (m³): Σ (a − o)·n/6 about o = a vertex of the mesh, for accuracy.
[[gnu::noinline]] Real volume_of(const MassSpringSettings& s, const Vec3* x) {
  const P3 origin = load(x[s.triangles.front()[0]]);
  Real six_v = 0;
  for (const Triangle& tri : s.triangles) {
    const TriangleGeometry g = triangle_geometry(tri, x);
    six_v += dot(g.a - origin, g.n);
  }
  return six_v / 6.0;
}

/// Adds scale · n_t/6 to each corner of every triangle (scale · ∂V/∂x on a closed mesh).
[[gnu::noinline]] void add_volume_gradient(const MassSpringSettings& s, const Vec3* x, Real scale, Vec3* out) {
  const Real w = scale / 6.0;
  for (const Triangle& tri : s.triangles) {
    const P3 g = w * triangle_geometry(tri, x).n;
    add_to(out[tri[0]], g);
    add_to(out[tri[1]], g);
    add_to(out[tri[2]], g);
  }
}

void triangle_forces(const MassSpringSettings& s, const Vec3* x, Vec3* f, const ForceTerms& terms) {
  if (area_term_on(s, terms)) area_forces(s, x, f);
  if (volume_term_on(s, terms))  // pressure p = −κ_V (V − V0) on every triangle
    add_volume_gradient(s, x, -s.k_volume / s.rest_volume * (volume_of(s, x) - s.rest_volume), f);
}

// Stiffness of the constraints: ∇²E = κ [∇A ∇Aᵀ + (A − A0) ∇²A] (likewise for V). We keep the
// Gauss–Newton part only, ∂f/∂x ≈ −κ ∇A ∇Aᵀ (and −κ_V ∇V ∇Vᵀ): negative semidefinite by
// construction, and exact at rest, where A = A0 and V = V0 cancel the dropped second-order
// terms (∇²A and ∇²V are indefinite and would break conjugate gradients far from rest).
// The product is rank one per triangle: out_a += −κ (∇A·dx) ∂A/∂x_a, with
// ∇A·dx = Σ_corners ∂A/∂x_corner · dx_corner; for the volume, ∇V·dx = Σ_t (n_t/6)·(dx_a+dx_b+dx_c)
// is a single scalar over the whole mesh, then every triangle adds −κ_V (∇V·dx) n_t/6.
[[gnu::noinline]] void area_stiffness_product(const MassSpringSettings& s, const Vec3* x, const Vec3* dx,
                                              Vec3* out) {
  const Triangle* tris = s.triangles.data();
  const std::size_t nt = s.triangles.size();
  const Real kappa = s.k_area / s.mean_rest_area;
  for (std::size_t t = 0; t < nt; ++t) {
    const Triangle& tri = tris[t];
    const TriangleGeometry g = triangle_geometry(tri, x);
    const Real half_inv = 0.5 * safe_inverse_sqrt(dot(g.n, g.n), kTinyNormal2);
    const P3 ga = half_inv * cross(g.n, g.c - g.b);
    const P3 gb = half_inv * cross(g.n, g.a - g.c);
    const P3 gc = half_inv * cross(g.n, g.b - g.a);
    const Real coef = -kappa * (dot(ga, load(dx[tri[0]])) + dot(gb, load(dx[tri[1]])) + dot(gc, load(dx[tri[2]])));
    add_to(out[tri[0]], coef * ga);
    add_to(out[tri[1]], coef * gb);
    add_to(out[tri[2]], coef * gc);
  }
}

/// ∇V·dx = Σ_t (n_t/6)·(dx_a + dx_b + dx_c) (m³).
[[gnu::noinline]] Real volume_slope(const MassSpringSettings& s, const Vec3* x, const Vec3* dx) {
  Real six_slope = 0;
  for (const Triangle& tri : s.triangles)
    six_slope += dot(triangle_geometry(tri, x).n, load(dx[tri[0]]) + load(dx[tri[1]]) + load(dx[tri[2]]));
  return six_slope / 6.0;
}

void triangle_stiffness_product(const MassSpringSettings& s, const Vec3* x, const Vec3* dx, Vec3* out,
                                const ForceTerms& terms) {
  if (area_term_on(s, terms)) area_stiffness_product(s, x, dx, out);
  if (volume_term_on(s, terms))
    add_volume_gradient(s, x, -s.k_volume / s.rest_volume * volume_slope(s, x, dx), out);
}

}  // namespace

namespace tissue_detail {
void add_area_forces(const MassSpringSettings& s, const Vec3* x, Padded3* f) {
  if (area_term_on(s, ForceTerms{})) area_forces(s, x, f);
}
}  // namespace tissue_detail

void accumulate_forces(const MassSpringSettings& s, std::span<const Vec3> x, std::span<const Vec3> v,
                       std::span<Vec3> forces, const ForceTerms& terms) {
  const std::size_t n = s.vertex_count();
  assert(x.size() == n && v.size() == n && forces.size() == n);
  const Vec3* xp = x.data();
  Vec3* f = forces.data();
  if (terms.springs && !s.springs.empty()) spring_forces(s, xp, v.data(), f);
  if (!s.triangles.empty()) triangle_forces(s, xp, f, terms);

  // Per-vertex terms in one pass: home −k_home (x − x0), global damping −γ m v, gravity m g.
  const Real k_home = terms.home ? s.k_home : 0.0;
  const Real gamma = terms.global_damping ? s.damping : 0.0;
  const Vec3 g = terms.gravity ? s.gravity : Vec3::Zero();
  if (k_home == 0 && gamma == 0 && g.isZero(0)) return;
  const Vec3* x0 = s.home_positions.data();
  const Real* m = s.masses.data();
  const Vec3* vp = v.data();
  for (std::size_t i = 0; i < n; ++i) f[i] += m[i] * (g - gamma * vp[i]) - k_home * (xp[i] - x0[i]);
}

Real potential_energy(const MassSpringSettings& s, std::span<const Vec3> x, const ForceTerms& terms) {
  assert(x.size() == s.vertex_count());
  const Vec3* xp = x.data();
  Real e = 0;
  if (terms.springs) e += spring_energy(s, xp);
  if (area_term_on(s, terms)) {
    Real sum = 0;
    for (std::size_t t = 0; t < s.triangles.size(); ++t) {
      const P3 n = triangle_geometry(s.triangles[t], xp).n;
      const Real da = 0.5 * std::sqrt(dot(n, n)) - s.rest_areas[t];
      sum += da * da;
    }
    e += 0.5 * s.k_area / s.mean_rest_area * sum;
  }
  if (volume_term_on(s, terms)) e += volume_energy(s, volume_of(s, xp));
  if (terms.home && s.k_home != 0) {
    Real sum = 0;
    for (std::size_t i = 0; i < x.size(); ++i) sum += (xp[i] - s.home_positions[i]).squaredNorm();
    e += 0.5 * s.k_home * sum;
  }
  if (terms.gravity) {
    // −Σ m g·x, so that −∇ gives m g.
    for (std::size_t i = 0; i < x.size(); ++i) e -= s.masses[i] * s.gravity.dot(xp[i]);
  }
  return e;
}

Real kinetic_energy(const MassSpringSettings& s, std::span<const Vec3> v) {
  assert(v.size() == s.vertex_count());
  Real e = 0;
  for (std::size_t i = 0; i < v.size(); ++i) e += s.masses[i] * v[i].squaredNorm();
  return 0.5 * e;
}

void add_stiffness_product(const MassSpringSettings& s, std::span<const Vec3> x, std::span<const Vec3> dx,
                           std::span<Vec3> out, const ForceTerms& terms) {
  const std::size_t n = s.vertex_count();
  assert(x.size() == n && dx.size() == n && out.size() == n);
  if (terms.springs && !s.springs.empty()) spring_stiffness_product(s, x.data(), dx.data(), out.data());
  if (!s.triangles.empty()) triangle_stiffness_product(s, x.data(), dx.data(), out.data(), terms);
  // Home springs: ∂(−k_home (x − x0))/∂x = −k_home I. Gravity and damping have no x-derivative.
  if (terms.home && s.k_home != 0)
    for (std::size_t i = 0; i < n; ++i) out[i] -= s.k_home * dx[i];
}

void add_damping_product(const MassSpringSettings& s, std::span<const Vec3> x, std::span<const Vec3> dv,
                         std::span<Vec3> out, const ForceTerms& terms) {
  const std::size_t n = s.vertex_count();
  assert(x.size() == n && dv.size() == n && out.size() == n);
  if (terms.springs && !s.springs.empty()) spring_damping_product(s, x.data(), dv.data(), out.data());
  // Global damping: ∂(−γ m_i v_i)/∂v_i = −γ m_i I.
  if (terms.global_damping && s.damping != 0)
    for (std::size_t i = 0; i < n; ++i) out[i] -= (s.damping * s.masses[i]) * dv[i];
}

}  // namespace trocar
