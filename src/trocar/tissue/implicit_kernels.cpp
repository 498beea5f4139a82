// The implicit step in AVX2+FMA. integrator_implicit.cpp derives every formula used here
// (system A Δv = b, spring blocks a u uᵀ + b I, volume rank-one term, contacts, block-Jacobi
// preconditioner, warm start, stopping rule); this file only changes the layout:
//  * every vertex vector is padded to (x, y, z, 0), so it is one aligned 256-bit access;
//  * the spring force pass takes four springs at a time (avx2.h's quad_geometry: |d|², Δv·d and
//    1/|d| of four springs from one transpose and one vsqrtpd + vdivpd) and writes the CG cache
//    four springs at a time (CgSpringQuad); star quads (four springs sharing their first
//    vertex) load and write that vertex once, here and in the product;
//  * in the CG product a spring is: two loads of p and two of x (d = x_j − x_i, recomputed
//    rather than caching u: the cache is then 96 bytes per quad, not 224, and on meshes whose
//    cache outgrows L2 the product streams half the bytes), d·δ for four springs at once, two
//    broadcasts, and two read-modify-writes of A·p;
//  * the preconditioner blocks are (xx, yy, zz, 0 | xy, yz, zx, 0), so P⁻¹ r is two multiplies
//    and two permuted products per vertex.
// With the area term on, the portable solver runs instead (supports()).
#include "trocar/tissue/implicit_kernels.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "trocar/tissue/avx2.h"
#include "trocar/tissue/integrator.h"
#include "trocar/tissue/internal.h"

namespace trocar::tissue_detail {

#ifdef TROCAR_HAVE_X86
namespace {

constexpr Real kVelocityFloorPerTolerance = 0.1;   ///< as integrator_implicit.cpp (m/s)

using namespace avx2;

TROCAR_AVX2 inline void add_block(Block3* base, std::uint32_t vertex_offset, __m256d diagonal, __m256d off) {
  // Block3 is 64 bytes per vertex, Padded3 32: the block offset is twice the vertex offset.
  Real* p = reinterpret_cast<Real*>(reinterpret_cast<char*>(base) + 2 * std::size_t{vertex_offset});
  _mm256_store_pd(p, _mm256_add_pd(_mm256_load_pd(p), diagonal));
  _mm256_store_pd(p + 4, _mm256_add_pd(_mm256_load_pd(p + 4), off));
}
TROCAR_AVX2 inline __m256d vec3(const Vec3& a) { return _mm256_setr_pd(a[0], a[1], a[2], 0); }
TROCAR_AVX2 inline Real max_lane(__m256d a) {
  alignas(32) Real lanes[4];
  _mm256_store_pd(lanes, a);
  return std::max(std::max(lanes[0], lanes[1]), std::max(lanes[2], lanes[3]));
}
/// The symmetric block times r: diagonal ∘ r + (xy r_y + zx r_z, yz r_z + xy r_x, zx r_x + yz r_y).
TROCAR_AVX2 inline __m256d block_times(const Block3& m, __m256d r) {
  const __m256d off = _mm256_load_pd(m.off);
  return _mm256_fmadd_pd(_mm256_load_pd(m.diagonal), r,
                         _mm256_fmadd_pd(off, yzx(r), _mm256_mul_pd(zxy(off), zxy(r))));
}
TROCAR_AVX2 inline __m256d absolute(__m256d a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }


/// The inverse of a symmetric positive definite block by cofactors (integrator_implicit.cpp's).
void invert(Block3& m) {
  const Real xx = m.diagonal[0], yy = m.diagonal[1], zz = m.diagonal[2];
  const Real xy = m.off[0], yz = m.off[1], zx = m.off[2];
  const Real c00 = yy * zz - yz * yz, c11 = xx * zz - zx * zx, c22 = xx * yy - xy * xy;
  const Real c01 = zx * yz - xy * zz, c02 = xy * yz - zx * yy, c12 = xy * zx - xx * yz;
  const Real r = 1.0 / (xx * c00 + xy * c01 + zx * c02);
  m = Block3{{c00 * r, c11 * r, c22 * r, 0}, {c01 * r, c12 * r, c02 * r, 0}};
}

/// Springs four at a time (kStar: the quad's springs share their first vertex, so x_i, v_i load
/// once and f_i, A_ii get one read-modify-write each): the force σ d plus h K_s v₀ =
/// h k (c δv + (1 − c)(u·δv) u), the cached block (u, a, b) and A_ii += a u uᵀ + b I at both
/// ends. With u·δv = (d·δv)/|d|:  f_i += (σ + h k (1 − c)(d·δv)/|d|²) d + h k c δv,  f_j −= it.
template <bool kStar>
TROCAR_AVX2 void linearise_springs(const std::vector<SpringQuad>& quads, CgSpringQuad* cache, const Padded3* x,
                                   const Padded3* v, Padded3* f, Block3* pre, Real h) {
  const __m256d one = _mm256_set1_pd(1.0), zero = _mm256_setzero_pd();
  const __m256d h_v = _mm256_set1_pd(h), xyz = _mm256_setr_pd(1, 1, 1, 0);
  for (std::size_t qi = 0; qi < quads.size(); ++qi) {
    const SpringQuad& sq = quads[qi];
    CgSpringQuad& cq = cache[qi];
    const QuadGeometry geometry = quad_geometry<kStar>(sq, x, v);
    const __m256d* d = geometry.d;
    const __m256d* w = geometry.w;
    const __m256d len2 = geometry.length2, speed = geometry.speed, inv = geometry.inverse_length;
    const __m256d rest = _mm256_load_pd(sq.rest_length), k_v = _mm256_load_pd(sq.stiffness);
    const __m256d lambda = _mm256_load_pd(sq.damping);
    const __m256d inv2 = _mm256_mul_pd(inv, inv);
    const __m256d sigma = _mm256_fmadd_pd(_mm256_mul_pd(k_v, _mm256_sub_pd(_mm256_mul_pd(len2, inv), rest)), inv,
                                          _mm256_mul_pd(_mm256_mul_pd(lambda, speed), inv2));
    const __m256d c = _mm256_max_pd(zero, _mm256_fnmadd_pd(rest, inv, one));  // max(0, 1 − l/|d|)
    const __m256d hk = _mm256_mul_pd(h_v, k_v);
    const __m256d one_minus_c = _mm256_sub_pd(one, c);
    alignas(32) Real a_s[4];
    const __m256d a = _mm256_mul_pd(h_v, _mm256_fmadd_pd(hk, one_minus_c, lambda));
    _mm256_store_pd(a_s, a);
    _mm256_store_pd(cq.a_d, _mm256_mul_pd(a, inv2));
    _mm256_store_pd(cq.b, _mm256_mul_pd(_mm256_mul_pd(h_v, hk), c));
    alignas(32) Real along_d[4], along_w[4], inv_s[4];
    _mm256_store_pd(along_d, _mm256_fmadd_pd(_mm256_mul_pd(hk, one_minus_c), _mm256_mul_pd(speed, inv2), sigma));
    _mm256_store_pd(along_w, _mm256_mul_pd(hk, c));
    _mm256_store_pd(inv_s, inv);
    __m256d t_sum = zero, diagonal_sum = zero, off_sum = zero;
    for (int k = 0; k < 4; ++k) {
      const __m256d u = _mm256_mul_pd(_mm256_broadcast_sd(&inv_s[k]), d[k]);
      const __m256d t =
          _mm256_fmadd_pd(_mm256_broadcast_sd(&along_d[k]), d[k], _mm256_mul_pd(_mm256_broadcast_sd(&along_w[k]), w[k]));
      subtract_at(f, sq.j[k], t);
      // a u uᵀ + b I: diagonal a u∘u + b (1, 1, 1, 0); off-diagonal a (ux uy, uy uz, uz ux).
      const __m256d au = _mm256_mul_pd(_mm256_broadcast_sd(&a_s[k]), u);
      const __m256d diagonal = _mm256_fmadd_pd(au, u, _mm256_mul_pd(_mm256_broadcast_sd(&cq.b[k]), xyz));
      const __m256d off = _mm256_mul_pd(au, yzx(u));
      add_block(pre, sq.j[k], diagonal, off);
      if constexpr (kStar) {
        t_sum = _mm256_add_pd(t_sum, t);
        diagonal_sum = _mm256_add_pd(diagonal_sum, diagonal);
        off_sum = _mm256_add_pd(off_sum, off);
      } else {
        add_at(f, sq.i[k], t);
        add_block(pre, sq.i[k], diagonal, off);
      }
    }
    if constexpr (kStar) {
      add_at(f, sq.i[0], t_sum);
      add_block(pre, sq.i[0], diagonal_sum, off_sum);
    }
  }
}

/// The springs' part of A·p (kStar as above): g = a (u·δ) u + b δ = (a/|d|²)(d·δ) d + b δ,
/// δ = p_j − p_i, d = x_j − x_i; (A p)_i −= g, (A p)_j += g; pᵀ A p gains a (u·δ)² (pap_a) +
/// b |δ|² (pap_b).
template <bool kStar>
TROCAR_AVX2 void apply_springs(const std::vector<CgSpringQuad>& cache, const Padded3* x, const Padded3* p,
                               Padded3* out, __m256d& pap_a, __m256d& pap_b) {
  for (const CgSpringQuad& cq : cache) {
    __m256d delta[4], d[4];
    if constexpr (kStar) {
      const __m256d pi = load_at(p, cq.i[0]), xi = load_at(x, cq.i[0]);
      for (int k = 0; k < 4; ++k) {
        delta[k] = _mm256_sub_pd(load_at(p, cq.j[k]), pi);
        d[k] = _mm256_sub_pd(load_at(x, cq.j[k]), xi);
      }
    } else {
      for (int k = 0; k < 4; ++k) {
        delta[k] = _mm256_sub_pd(load_at(p, cq.j[k]), load_at(p, cq.i[k]));
        d[k] = _mm256_sub_pd(load_at(x, cq.j[k]), load_at(x, cq.i[k]));
      }
    }
    const __m256d dd = horizontal_sums(_mm256_mul_pd(d[0], delta[0]), _mm256_mul_pd(d[1], delta[1]),
                                       _mm256_mul_pd(d[2], delta[2]), _mm256_mul_pd(d[3], delta[3]));
    const __m256d add = _mm256_mul_pd(_mm256_load_pd(cq.a_d), dd);
    pap_a = _mm256_fmadd_pd(add, dd, pap_a);
    alignas(32) Real add_s[4];
    _mm256_store_pd(add_s, add);
    __m256d g_sum = _mm256_setzero_pd();
    for (int k = 0; k < 4; ++k) {
      const __m256d b_delta = _mm256_mul_pd(_mm256_broadcast_sd(&cq.b[k]), delta[k]);
      const __m256d g = _mm256_fmadd_pd(_mm256_broadcast_sd(&add_s[k]), d[k], b_delta);
      pap_b = _mm256_fmadd_pd(b_delta, delta[k], pap_b);
      add_at(out, cq.j[k], g);
      if constexpr (kStar)
        g_sum = _mm256_add_pd(g_sum, g);
      else
        subtract_at(out, cq.i[k], g);
    }
    if constexpr (kStar) subtract_at(out, cq.i[0], g_sum);
  }
}

}  // namespace
#endif  // TROCAR_HAVE_X86

void ImplicitAvx2::home_moved(const MassSpringSettings& settings) {
  copy_padded(settings.home_positions.data(), settings.vertex_count(), rest_.data());
}

ImplicitAvx2::ImplicitAvx2(const MassSpringSettings& settings)
    : settings_(settings),
      springs_(make_spring_layout(settings.springs, settings.vertex_count(), &settings.fixed)),
      triangles_(make_volume_layout(settings.triangles, settings.vertex_count())) {
  const std::size_t n = settings.vertex_count();
  for (auto [quads, cache] : {std::pair{&springs_.stars, &cache_stars_}, std::pair{&springs_.others, &cache_others_}}) {
    cache->resize(quads->size());
    for (std::size_t q = 0; q < quads->size(); ++q)
      for (int k = 0; k < 4; ++k) {
        (*cache)[q].i[k] = (*quads)[q].i[k];
        (*cache)[q].j[k] = (*quads)[q].j[k];
      }
  }
  std::span<Padded3>* arrays[] = {&x_, &v_, &rest_, &f_, &dv_, &r_, &p_, &z_, &q_, &gradient_};
  arrays_.allocate(n, std::size(arrays));
  for (std::size_t k = 0; k < std::size(arrays); ++k) *arrays[k] = arrays_[k];
  copy_padded(settings.home_positions.data(), n, rest_.data());
  preconditioner_.assign(n, Block3{});
  diagonal_mass_.assign(n, 0.0);
  free_.resize(n);
  for (std::size_t i = 0; i < n; ++i) free_[i] = settings.fixed[i] ? 0.0 : 1.0;
}

bool ImplicitAvx2::supports(const MassSpringSettings& s, const ForceTerms& terms) {
  return !area_term_on(s, terms);
}

#ifdef TROCAR_HAVE_X86

TROCAR_AVX2 void ImplicitAvx2::linearise(const TissueLoads& loads, Real h, const ForceTerms& terms) {
  const MassSpringSettings& s = settings_;
  const std::size_t n = s.vertex_count();
  // Per-vertex terms: f = f_ext + m (g − γ v) − k_home (x − x0 + h v); A_ii = m (1 + hγ) + h² k_home.
  {
    const Real gamma = terms.global_damping ? s.damping : 0.0;
    const Real k_home = terms.home ? s.k_home : 0.0;
    const __m256d g = terms.gravity ? vec3(s.gravity) : _mm256_setzero_pd();
    const __m256d gamma_v = _mm256_set1_pd(gamma), k_home_v = _mm256_set1_pd(k_home), h_v = _mm256_set1_pd(h);
    const __m256d xyz = _mm256_setr_pd(1, 1, 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const __m256d vi = load(v_[i]);
      __m256d fi = _mm256_mul_pd(_mm256_set1_pd(s.masses[i]), _mm256_fnmadd_pd(gamma_v, vi, g));
      fi = _mm256_fnmadd_pd(k_home_v, _mm256_add_pd(_mm256_sub_pd(load(x_[i]), load(rest_[i])), _mm256_mul_pd(h_v, vi)), fi);
      store(f_[i], fi);
      const Real d = s.masses[i] * (1 + h * gamma) + h * h * k_home;
      diagonal_mass_[i] = d;
      _mm256_store_pd(preconditioner_[i].diagonal, _mm256_mul_pd(_mm256_set1_pd(d), xyz));
      _mm256_store_pd(preconditioner_[i].off, _mm256_setzero_pd());
    }
    // f_ext: only at the vertices the step loaded (TissueLoads).
    add_external_forces(loads, f_.data(), n);
  }

  // Springs, four at a time: the force σ d (+ h K_s v₀ = h k (c δv + (1 − c)(u·δv) u)), the
  // cached block (u, a, b) and A_ii += a u uᵀ + b I at both ends. With u·δv = (d·δv)/|d|:
  //   f_i += (σ + h k (1 − c) (d·δv)/|d|²) d + h k c δv,   f_j −= the same.
  if (terms.springs) {
    linearise_springs<true>(springs_.stars, cache_stars_.data(), x_.data(), v_.data(), f_.data(),
                            preconditioner_.data(), h);
    linearise_springs<false>(springs_.others, cache_others_.data(), x_.data(), v_.data(), f_.data(),
                             preconditioner_.data(), h);
  }

  // Volume: ∇V_i = Σ_{t∋i} n_t/6; f += (−κ_V (V − V0) − h κ_V (∇V·v₀)) ∇V; A_ii += h² κ_V ∇V_i ∇V_iᵀ.
  const bool volume = volume_term_on(s, terms);
  if (volume) {
    std::fill(gradient_.begin(), gradient_.end(), Padded3{});
    six_volume_ = add_volume_gradient(triangles_, x_.data(), gradient_.data(), true);
    const __m256d sixth = _mm256_set1_pd(1.0 / 6.0);
    __m256d slope = _mm256_setzero_pd();
    for (std::size_t i = 0; i < n; ++i) {
      const __m256d g = _mm256_mul_pd(sixth, load(gradient_[i]));
      store(gradient_[i], g);
      slope = _mm256_fmadd_pd(g, load(v_[i]), slope);
    }
    const Real kappa_v = s.k_volume / s.rest_volume;
    const __m256d coef = _mm256_set1_pd(-kappa_v * (six_volume_ / 6.0 - s.rest_volume + h * sum(slope)));
    const __m256d c2 = _mm256_set1_pd(h * h * kappa_v);
    for (std::size_t i = 0; i < n; ++i) {
      const __m256d g = load(gradient_[i]);
      store(f_[i], _mm256_fmadd_pd(coef, g, load(f_[i])));
      const __m256d c2g = _mm256_mul_pd(c2, g);
      Block3& m = preconditioner_[i];
      _mm256_store_pd(m.diagonal, _mm256_fmadd_pd(c2g, g, _mm256_load_pd(m.diagonal)));
      _mm256_store_pd(m.off, _mm256_fmadd_pd(c2g, yzx(g), _mm256_load_pd(m.off)));
    }
  }

  // Contacts (few): h K v₀ at a = −h k w_a n (Σ_b w_b n·v₀_b); A_aa += (h μ + h² k) w_a² n nᵀ.
  for (const ContactJacobian& c : loads.contacts) {
    const __m256d nn = vec3(c.normal);
    Real sv = 0;
    for (int k = 0; k < 3; ++k) sv += c.weights[k] * sum(_mm256_mul_pd(nn, load(v_[c.vertices[k]])));
    const Real g = -h * c.stiffness * sv;
    const Real w = h * c.damping + h * h * c.stiffness;
    for (int k = 0; k < 3; ++k) {
      Padded3& fk = f_[c.vertices[k]];
      store(fk, _mm256_fmadd_pd(_mm256_set1_pd(g * c.weights[k]), nn, load(fk)));
      const __m256d wn = _mm256_mul_pd(_mm256_set1_pd(w * c.weights[k] * c.weights[k]), nn);
      Block3& m = preconditioner_[c.vertices[k]];
      _mm256_store_pd(m.diagonal, _mm256_fmadd_pd(wn, nn, _mm256_load_pd(m.diagonal)));
      _mm256_store_pd(m.off, _mm256_fmadd_pd(wn, yzx(nn), _mm256_load_pd(m.off)));
    }
  }
}

TROCAR_AVX2 Real ImplicitAvx2::apply_system(const TissueLoads& loads, Real h, Real volume_slope,
                                            const ForceTerms& terms) {
  const Padded3* p = p_.data();
  Padded3* out = q_.data();  // diagonal_mass · p on entry
  __m256d pap_a = _mm256_setzero_pd(), pap_b = _mm256_setzero_pd();
  // Springs: g = a (u·δ) u + b δ, δ = p_j − p_i; (A p)_i −= g, (A p)_j += g; pᵀ A p gains
  // a (u·δ)² + b |δ|².
  if (terms.springs) {
    apply_springs<true>(cache_stars_, x_.data(), p, out, pap_a, pap_b);
    apply_springs<false>(cache_others_, x_.data(), p, out, pap_a, pap_b);
  }
  // Contacts: (A p)_a += (h μ + h² k) w_a n (Σ_b w_b n·p_b).
  Real pap_contacts = 0;
  for (const ContactJacobian& c : loads.contacts) {
    const __m256d nn = vec3(c.normal);
    Real sl = 0;
    for (int k = 0; k < 3; ++k) sl += c.weights[k] * sum(_mm256_mul_pd(nn, load(p[c.vertices[k]])));
    const Real g = (h * c.damping + h * h * c.stiffness) * sl;
    for (int k = 0; k < 3; ++k) {
      Padded3& o = out[c.vertices[k]];
      store(o, _mm256_fmadd_pd(_mm256_set1_pd(g * c.weights[k]), nn, load(o)));
    }
    pap_contacts += g * sl;
  }
  const MassSpringSettings& s = settings_;
  const bool volume = volume_term_on(s, terms);
  const Real pap_volume = volume ? h * h * s.k_volume / s.rest_volume * volume_slope * volume_slope : 0.0;
  return sum(pap_a) + sum(pap_b) + pap_contacts + pap_volume;
}

TROCAR_AVX2 StepStats ImplicitAvx2::step(MassSpringState& state, const TissueLoads& loads, Real h,
                                         const ForceTerms& terms, const ImplicitOptions& options) {
  const MassSpringSettings& s = settings_;
  const std::size_t n = s.vertex_count();
  copy_padded(state.positions.data(), n, x_.data());
  copy_padded(state.velocities.data(), n, v_.data());
  linearise(loads, h, terms);

  const bool volume = volume_term_on(s, terms);
  const Real c_volume = volume ? h * h * s.k_volume / s.rest_volume : 0.0;
  const Padded3* gv = gradient_.data();
  const Real* free = free_.data();
  const Real* dm = diagonal_mass_.data();
  const __m256d zero = _mm256_setzero_pd();

  // b = S h f; r = b; the preconditioner inverted (0 at fixed vertices); the warm start.
  __m256d bb_v = zero, slope_v = zero, warm_v = zero;
  for (std::size_t i = 0; i < n; ++i) {
    const __m256d b = _mm256_mul_pd(_mm256_set1_pd(free[i] * h), load(f_[i]));
    store(r_[i], b);
    bb_v = _mm256_fmadd_pd(b, b, bb_v);
    if (free[i] != 0)
      invert(preconditioner_[i]);
    else
      preconditioner_[i] = Block3{};
    const __m256d d = _mm256_mul_pd(_mm256_set1_pd(free[i]), load(dv_[i]));
    store(p_[i], d);
    warm_v = _mm256_or_pd(warm_v, _mm256_cmp_pd(d, zero, _CMP_NEQ_UQ));
    store(q_[i], _mm256_mul_pd(_mm256_set1_pd(dm[i]), d));
    if (volume) slope_v = _mm256_fmadd_pd(load(gv[i]), d, slope_v);
  }
  const Real bb = sum(bb_v);
  bool warm = _mm256_movemask_pd(warm_v) != 0;
  StepStats stats;
  if (!(bb > 0 && std::isfinite(bb)) || !warm) {
    std::fill(dv_.begin(), dv_.end(), Padded3{});
    warm = false;
  }
  Real slope = sum(slope_v);
  if (warm) apply_system(loads, h, slope, terms);
  const __m256d warm_volume = _mm256_set1_pd(c_volume * slope);
  __m256d rho_v = zero, rr_v = zero, mpp_v = zero;
  slope_v = zero;
  for (std::size_t i = 0; i < n; ++i) {
    __m256d ri = load(r_[i]);
    if (warm) {
      ri = _mm256_fnmadd_pd(_mm256_set1_pd(free[i]), _mm256_fmadd_pd(warm_volume, load(gv[i]), load(q_[i])), ri);
      store(r_[i], ri);
    }
    rr_v = _mm256_fmadd_pd(ri, ri, rr_v);
    const __m256d zi = block_times(preconditioner_[i], ri);
    rho_v = _mm256_fmadd_pd(ri, zi, rho_v);
    store(p_[i], zi);
    const __m256d dmi = _mm256_set1_pd(dm[i]);
    store(q_[i], _mm256_mul_pd(dmi, zi));
    mpp_v = _mm256_fmadd_pd(_mm256_mul_pd(dmi, zi), zi, mpp_v);
    if (volume) slope_v = _mm256_fmadd_pd(load(gv[i]), zi, slope_v);
  }
  Real rho = sum(rho_v), rr = sum(rr_v), mpp = sum(mpp_v);
  slope = sum(slope_v);

  const Real tolerance2 = options.cg_tolerance * options.cg_tolerance * bb;
  const Real floor = kVelocityFloorPerTolerance * options.cg_tolerance;
  if (bb > 0 && std::isfinite(bb) && rr > 0) {
    while (stats.cg_iterations < options.max_cg_iterations) {
      const Real pap = mpp + apply_system(loads, h, slope, terms);
      if (!(pap > 0)) break;
      const __m256d alpha = _mm256_set1_pd(rho / pap);
      const __m256d cv = _mm256_set1_pd(c_volume * slope);
      rr_v = zero;
      __m256d rho_next_v = zero, zmax_v = zero;
      for (std::size_t i = 0; i < n; ++i) {
        const __m256d q = _mm256_mul_pd(_mm256_set1_pd(free[i]), _mm256_fmadd_pd(cv, load(gv[i]), load(q_[i])));
        store(dv_[i], _mm256_fmadd_pd(alpha, load(p_[i]), load(dv_[i])));
        const __m256d ri = _mm256_fnmadd_pd(alpha, q, load(r_[i]));
        store(r_[i], ri);
        rr_v = _mm256_fmadd_pd(ri, ri, rr_v);
        const __m256d zi = block_times(preconditioner_[i], ri);
        store(z_[i], zi);
        rho_next_v = _mm256_fmadd_pd(ri, zi, rho_next_v);
        zmax_v = _mm256_max_pd(zmax_v, absolute(zi));
      }
      ++stats.cg_iterations;
      rr = sum(rr_v);
      if (rr <= tolerance2 || max_lane(zmax_v) <= floor) break;
      const Real rho_next = sum(rho_next_v);
      const __m256d beta = _mm256_set1_pd(rho_next / rho);
      rho = rho_next;
      slope_v = zero;
      mpp_v = zero;
      for (std::size_t i = 0; i < n; ++i) {
        const __m256d pi = _mm256_fmadd_pd(beta, load(p_[i]), load(z_[i]));
        store(p_[i], pi);
        const __m256d dpi = _mm256_mul_pd(_mm256_set1_pd(dm[i]), pi);
        store(q_[i], dpi);
        mpp_v = _mm256_fmadd_pd(dpi, pi, mpp_v);
        if (volume) slope_v = _mm256_fmadd_pd(load(gv[i]), pi, slope_v);
      }
      mpp = sum(mpp_v);
      slope = sum(slope_v);
    }
  }
  stats.cg_residual = bb > 0 ? std::sqrt(rr / bb) : 0.0;

  // v₁ = v₀ + Δv, x₁ = x₀ + h v₁.
  const __m256d h_v = _mm256_set1_pd(h);
  __m256d check = zero;
  for (std::size_t i = 0; i < n; ++i) {
    const __m256d vi = _mm256_add_pd(load(v_[i]), load(dv_[i]));
    const __m256d xi = _mm256_fmadd_pd(h_v, vi, load(x_[i]));
    alignas(32) Real xs[4], vs[4];
    _mm256_store_pd(xs, xi);
    _mm256_store_pd(vs, vi);
    state.positions[i] = Vec3(xs[0], xs[1], xs[2]);
    state.velocities[i] = Vec3(vs[0], vs[1], vs[2]);
    check = _mm256_add_pd(check, _mm256_add_pd(xi, vi));
  }
  stats.finite = std::isfinite(sum(check)) && std::isfinite(bb);
  if (!stats.finite) std::fill(dv_.begin(), dv_.end(), Padded3{});  // no warm start from garbage
  return stats;
}

#else  // not x86: never constructed (cpu_has_avx2_fma() is false)

void ImplicitAvx2::linearise(const TissueLoads&, Real, const ForceTerms&) {}
Real ImplicitAvx2::apply_system(const TissueLoads&, Real, Real, const ForceTerms&) { return 0; }
StepStats ImplicitAvx2::step(MassSpringState&, const TissueLoads&, Real, const ForceTerms&, const ImplicitOptions&) {
  return {};
}

#endif  // TROCAR_HAVE_X86

}  // namespace trocar::tissue_detail
