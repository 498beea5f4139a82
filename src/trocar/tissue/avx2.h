#pragma once
/// AVX2+FMA building blocks shared by the tissue module's explicit and implicit passes
/// (internal). Every function carries the avx2,fma target attribute, so only code that has
/// checked cpu_has_avx2_fma() may call them; the library is built for baseline x86-64.
#if defined(__x86_64__)
#include <immintrin.h>

#include <cstdint>

#include "trocar/core/types.h"
#include "trocar/tissue/explicit_kernels.h"
#include "trocar/tissue/internal.h"
#include "trocar/tissue/volume_fans.h"

#define TROCAR_HAVE_X86 1
#define TROCAR_AVX2 __attribute__((target("avx2,fma")))

namespace trocar::tissue_detail::avx2 {

TROCAR_AVX2 inline __m256d load(const Padded3& p) { return _mm256_load_pd(&p.x); }
TROCAR_AVX2 inline void store(Padded3& p, __m256d a) { _mm256_store_pd(&p.x, a); }
/// A Vec3 as (x, y, z, 0); the masked lane is not read, so the last vertex is safe.
TROCAR_AVX2 inline __m256d load3(const Vec3& p) {
  return _mm256_maskload_pd(p.data(), _mm256_setr_epi64x(-1, -1, -1, 0));
}
/// Stores x, y, z of (x, y, z, ·) as 16 + 8 bytes. (A masked 256-bit store is slower, and it
/// stalls the next vertex's overlapping load: measured 2.6× slower update pass.)
TROCAR_AVX2 inline void store3(Vec3& p, __m256d a) {
  _mm_storeu_pd(p.data(), _mm256_castpd256_pd128(a));
  _mm_store_sd(p.data() + 2, _mm256_extractf128_pd(a, 1));
}

/// The padded vector at byte offset `offset` (an index × 32, precomputed: no shift per access).
TROCAR_AVX2 inline __m256d load_at(const Padded3* base, std::uint32_t offset) {
  return _mm256_load_pd(reinterpret_cast<const Real*>(reinterpret_cast<const char*>(base) + offset));
}
TROCAR_AVX2 inline void add_at(Padded3* base, std::uint32_t offset, __m256d a) {
  Real* p = reinterpret_cast<Real*>(reinterpret_cast<char*>(base) + offset);
  _mm256_store_pd(p, _mm256_add_pd(_mm256_load_pd(p), a));
}
TROCAR_AVX2 inline void subtract_at(Padded3* base, std::uint32_t offset, __m256d a) {
  Real* p = reinterpret_cast<Real*>(reinterpret_cast<char*>(base) + offset);
  _mm256_store_pd(p, _mm256_sub_pd(_mm256_load_pd(p), a));
}

/// (y, z, x, ·) and (z, x, y, ·).
TROCAR_AVX2 inline __m256d yzx(__m256d a) { return _mm256_permute4x64_pd(a, _MM_SHUFFLE(3, 0, 2, 1)); }
TROCAR_AVX2 inline __m256d zxy(__m256d a) { return _mm256_permute4x64_pd(a, _MM_SHUFFLE(3, 1, 0, 2)); }
/// a × b for (x, y, z, 0) vectors: yzx(a ∘ yzx(b) − yzx(a) ∘ b), three permutes.
TROCAR_AVX2 inline __m256d cross(__m256d a, __m256d b) {
  return yzx(_mm256_fmsub_pd(a, yzx(b), _mm256_mul_pd(yzx(a), b)));
}

/// [Σa, Σb, Σc, Σd]: four horizontal sums in one register (hadd, then swap 128-bit halves).
TROCAR_AVX2 inline __m256d horizontal_sums(__m256d a, __m256d b, __m256d c, __m256d d) {
  const __m256d ab = _mm256_hadd_pd(a, b);  // [a0+a1, b0+b1, a2+a3, b2+b3]
  const __m256d cd = _mm256_hadd_pd(c, d);
  return _mm256_add_pd(_mm256_permute2f128_pd(ab, cd, 0x20), _mm256_permute2f128_pd(ab, cd, 0x31));
}
/// Σ of the four lanes.
TROCAR_AVX2 inline Real sum(__m256d a) {
  alignas(32) Real lanes[4];
  _mm256_store_pd(lanes, a);
  return (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
}
/// x + y + z of an (x, y, z, ·) vector: the padding lane is left out.
TROCAR_AVX2 inline Real sum_xyz(__m256d a) {
  alignas(32) Real lanes[4];
  _mm256_store_pd(lanes, a);
  return lanes[0] + lanes[1] + lanes[2];
}

/// The x, y and z rows of four (x, y, z, ·) vectors: 4 unpacks and 3 lane swaps.
TROCAR_AVX2 inline void transpose_rows(const __m256d* a, __m256d& rx, __m256d& ry, __m256d& rz) {
  const __m256d t0 = _mm256_unpacklo_pd(a[0], a[1]), t1 = _mm256_unpackhi_pd(a[0], a[1]);
  const __m256d t2 = _mm256_unpacklo_pd(a[2], a[3]), t3 = _mm256_unpackhi_pd(a[2], a[3]);
  rx = _mm256_permute2f128_pd(t0, t2, 0x20);
  ry = _mm256_permute2f128_pd(t1, t3, 0x20);
  rz = _mm256_permute2f128_pd(t0, t2, 0x31);
}

/// Four springs' geometry: d = x_j − x_i and w = v_j − v_i per spring, and lane by lane |d|²,
/// Δv·d and 1/|d| (0 where |d|² ≤ kTinyLength2 or NaN, as safe_inverse_sqrt; one exact
/// vsqrtpd and vdivpd for four springs). kStar: the four share their first vertex, loaded once.
struct QuadGeometry {
  __m256d d[4], w[4];
  __m256d length2, speed, inverse_length;
};
template <bool kStar, class Quad>
TROCAR_AVX2 inline QuadGeometry quad_geometry(const Quad& s, const Padded3* x, const Padded3* v) {
  QuadGeometry g;
  if constexpr (kStar) {
    const __m256d xi = load_at(x, s.i[0]), vi = load_at(v, s.i[0]);
    for (int k = 0; k < 4; ++k) {
      g.d[k] = _mm256_sub_pd(load_at(x, s.j[k]), xi);
      g.w[k] = _mm256_sub_pd(load_at(v, s.j[k]), vi);
    }
  } else {
    for (int k = 0; k < 4; ++k) {
      g.d[k] = _mm256_sub_pd(load_at(x, s.j[k]), load_at(x, s.i[k]));
      g.w[k] = _mm256_sub_pd(load_at(v, s.j[k]), load_at(v, s.i[k]));
    }
  }
  // d and w as (x, y, z) rows of four springs; then |d|² and Δv·d are three multiply-adds each.
  const __m256d* d = g.d;
  const __m256d* w = g.w;
  __m256d dx, dy, dz, wx, wy, wz;
  transpose_rows(d, dx, dy, dz);
  transpose_rows(w, wx, wy, wz);
  g.length2 = _mm256_fmadd_pd(dz, dz, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dx, dx)));
  g.speed = _mm256_fmadd_pd(wz, dz, _mm256_fmadd_pd(wy, dy, _mm256_mul_pd(wx, dx)));
  const __m256d tiny = _mm256_set1_pd(kTinyLength2);
  g.inverse_length = _mm256_and_pd(_mm256_div_pd(_mm256_set1_pd(1.0), _mm256_sqrt_pd(g.length2)),
                                   _mm256_cmp_pd(g.length2, tiny, _CMP_GT_OQ));
  return g;
}

/// A fan's four normals n_k = e_k × e_{k+1}, e_k = r_k − c (volume_fans.h), each e_k permuted
/// once (cross above).
TROCAR_AVX2 inline void fan_normals(__m256d c, const __m256d* r, __m256d* n) {
  __m256d e[5], y[5];
  for (int k = 0; k < 5; ++k) {
    e[k] = _mm256_sub_pd(r[k], c);
    y[k] = yzx(e[k]);
  }
  for (int k = 0; k < 4; ++k) n[k] = yzx(_mm256_fmsub_pd(e[k], y[k + 1], _mm256_mul_pd(y[k], e[k + 1])));
}

/// The per-step constants of the explicit update (explicit_kernels.h's explicit_update).
struct UpdateConstants {
  __m256d gravity, gamma, k_home, dt;
  bool symplectic;
};
/// One vertex's explicit update: f += m (g − γ v) − k_home (x − x0); v₁ = v + h f / m;
/// x₁ = x + h (symplectic ? v₁ : v). Writes x₁ and v₁ to the state's vectors and returns x₁ + v₁
/// (for the step's finiteness check).
TROCAR_AVX2 inline __m256d explicit_vertex_update(const UpdateConstants& c, __m256d f, __m256d x, __m256d v,
                                                  __m256d x0, Real mass, Real inverse_mass, Vec3& x_out,
                                                  Vec3& v_out) {
  f = _mm256_fmadd_pd(_mm256_set1_pd(mass), _mm256_fnmadd_pd(c.gamma, v, c.gravity), f);
  f = _mm256_fnmadd_pd(c.k_home, _mm256_sub_pd(x, x0), f);
  const __m256d v1 = _mm256_fmadd_pd(_mm256_mul_pd(c.dt, _mm256_set1_pd(inverse_mass)), f, v);
  const __m256d x1 = _mm256_fmadd_pd(c.dt, c.symplectic ? v1 : v, x);
  store3(v_out, v1);
  store3(x_out, x1);
  return _mm256_add_pd(x1, v1);
}

/// Vertex loads for volume_gradient: from a padded array, or from the state's own Vec3s (the
/// masked load3). Offsets are index × 32, as the layouts store them.
struct PaddedLoad {
  const Padded3* x;
  TROCAR_AVX2 __m256d operator()(std::uint32_t offset) const { return load_at(x, offset); }
};
struct StateLoad {
  const Vec3* x;
  TROCAR_AVX2 __m256d operator()(std::uint32_t offset) const { return load3(x[offset / sizeof(Padded3)]); }
};

/// g_i += Σ_{t∋i} n_t over the layout's fans and single triangles, and returns 6V about the
/// layout's origin (volume_fans.h's add_volume_gradient).
template <class Load>
TROCAR_AVX2 inline Real volume_gradient(const VolumeLayout& layout, Load vertex, Padded3* g) {
  constexpr std::uint32_t kStride = sizeof(Padded3);
  const __m256d origin = vertex(layout.origin * kStride);
  __m256d six_v = _mm256_setzero_pd();
  for (const TriangleFan& f : layout.fans) {
    const __m256d c = vertex(f.center);
    __m256d r[5], n[4];
    for (int k = 0; k < 5; ++k) r[k] = vertex(f.ring[k]);
    fan_normals(c, r, n);
    const __m256d n01 = _mm256_add_pd(n[0], n[1]), n23 = _mm256_add_pd(n[2], n[3]);
    const __m256d total = _mm256_add_pd(n01, n23);
    six_v = _mm256_fmadd_pd(_mm256_sub_pd(c, origin), total, six_v);
    add_at(g, f.center, total);
    add_at(g, f.ring[0], n[0]);
    add_at(g, f.ring[1], n01);
    add_at(g, f.ring[2], _mm256_add_pd(n[1], n[2]));
    add_at(g, f.ring[3], n23);
    add_at(g, f.ring[4], n[3]);
  }
  for (const Triangle& tri : layout.singles) {
    // Indices into locals: the stores below may alias anything, so the compiler would reload them.
    const std::uint32_t ia = tri[0], ib = tri[1], ic = tri[2];
    const __m256d a = vertex(ia * kStride);
    const __m256d n = cross(_mm256_sub_pd(vertex(ib * kStride), a), _mm256_sub_pd(vertex(ic * kStride), a));
    six_v = _mm256_fmadd_pd(_mm256_sub_pd(a, origin), n, six_v);
    store(g[ia], _mm256_add_pd(load(g[ia]), n));
    store(g[ib], _mm256_add_pd(load(g[ib]), n));
    store(g[ic], _mm256_add_pd(load(g[ic]), n));
  }
  return sum_xyz(six_v);
}

/// Four springs' rest lengths, stiffnesses and dampings, lane by lane.
struct QuadParameters {
  __m256d rest_length, stiffness, damping;
};
/// A SpringQuad's own parameters.
struct OwnParameters {
  TROCAR_AVX2 QuadParameters operator()(const SpringQuad& s) const {
    return {_mm256_load_pd(s.rest_length), _mm256_load_pd(s.stiffness), _mm256_load_pd(s.damping)};
  }
};

/// f += the spring forces of `count` quads (eq. 3.2; forces.cpp's spring_forces), lane by lane;
/// `parameters(quad)` gives their rest lengths, stiffnesses and dampings.
/// kStar: the quad's four springs share their first vertex (SpringLayout::stars), so x_i and v_i
/// are loaded once and f_i gets one read-modify-write of the four forces' sum.
template <bool kStar, class Quad, class Parameters>
TROCAR_AVX2 inline void add_quad_spring_forces(const Quad* quads, std::size_t count, Parameters parameters,
                                               const Padded3* x, const Padded3* v, Padded3* f) {
  for (std::size_t q = 0; q < count; ++q) {
    const Quad& s = quads[q];
    const QuadGeometry g = quad_geometry<kStar>(s, x, v);
    const QuadParameters p = parameters(s);
    const __m256d* d = g.d;
    const __m256d len2 = g.length2, speed = g.speed, inv = g.inverse_length;
    // σ = k (|d| − l)/|d| + λ (Δv·d)/|d|²; f_i = σ d, f_j = −σ d.
    const __m256d stretch = _mm256_sub_pd(_mm256_mul_pd(len2, inv), p.rest_length);
    const __m256d damping = _mm256_mul_pd(_mm256_mul_pd(p.damping, speed), _mm256_mul_pd(inv, inv));
    alignas(32) Real sigma[4];
    _mm256_store_pd(sigma, _mm256_fmadd_pd(_mm256_mul_pd(p.stiffness, stretch), inv, damping));
    __m256d sum = _mm256_setzero_pd();
    for (int k = 0; k < 4; ++k) {
      const __m256d fk = _mm256_mul_pd(_mm256_broadcast_sd(&sigma[k]), d[k]);
      if constexpr (kStar)
        sum = _mm256_add_pd(sum, fk);
      else
        add_at(f, s.i[k], fk);
      subtract_at(f, s.j[k], fk);
    }
    if constexpr (kStar) add_at(f, s.i[0], sum);
  }
}

}  // namespace trocar::tissue_detail::avx2
#endif  // __x86_64__
