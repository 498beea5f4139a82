// The XPBD passes over one colour (xpbd_kernels.h): scalar and AVX2 (8 items a lane each; a
// particle is one 16-byte load, 8 of them transposed into x, y, z, w vectors and back).
#include "trocar/tissue/xpbd_kernels.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>

#define TROCAR_XPBD_AVX2 __attribute__((target("avx2,fma")))

namespace trocar::tissue_detail {
namespace {

struct F3 {
  float x, y, z;
};
inline F3 sub(const XpbdParticle& a, const XpbdParticle& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline F3 cross(const F3& a, const F3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float dot(const F3& a, const F3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline void add_scaled(XpbdParticle& p, const F3& d, float s) {
  p.x += d.x * s;
  p.y += d.y * s;
  p.z += d.z * s;
}

/// The particles of 8 ids as x, y, z, w vectors.
struct Lanes {
  __m256 x, y, z, w;
};

/// Particles a and b in the low and high halves.
TROCAR_XPBD_AVX2 inline __m256 pair(const XpbdParticle& a, const XpbdParticle& b) {
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(&a.x)), _mm_load_ps(&b.x), 1);
}

TROCAR_XPBD_AVX2 inline Lanes load8(const XpbdParticle* p, const std::uint32_t* id) {
  const __m256 r0 = pair(p[id[0]], p[id[4]]), r1 = pair(p[id[1]], p[id[5]]), r2 = pair(p[id[2]], p[id[6]]),
               r3 = pair(p[id[3]], p[id[7]]);
  const __m256 t0 = _mm256_unpacklo_ps(r0, r1), t1 = _mm256_unpackhi_ps(r0, r1);
  const __m256 t2 = _mm256_unpacklo_ps(r2, r3), t3 = _mm256_unpackhi_ps(r2, r3);
  return {_mm256_shuffle_ps(t0, t2, 0x44), _mm256_shuffle_ps(t0, t2, 0xEE), _mm256_shuffle_ps(t1, t3, 0x44),
          _mm256_shuffle_ps(t1, t3, 0xEE)};
}

TROCAR_XPBD_AVX2 inline void store8(XpbdParticle* p, const std::uint32_t* id, const Lanes& l) {
  const __m256 t0 = _mm256_unpacklo_ps(l.x, l.y), t1 = _mm256_unpackhi_ps(l.x, l.y);
  const __m256 t2 = _mm256_unpacklo_ps(l.z, l.w), t3 = _mm256_unpackhi_ps(l.z, l.w);
  const __m256 r0 = _mm256_shuffle_ps(t0, t2, 0x44), r1 = _mm256_shuffle_ps(t0, t2, 0xEE);
  const __m256 r2 = _mm256_shuffle_ps(t1, t3, 0x44), r3 = _mm256_shuffle_ps(t1, t3, 0xEE);
  _mm_store_ps(&p[id[0]].x, _mm256_castps256_ps128(r0));
  _mm_store_ps(&p[id[1]].x, _mm256_castps256_ps128(r1));
  _mm_store_ps(&p[id[2]].x, _mm256_castps256_ps128(r2));
  _mm_store_ps(&p[id[3]].x, _mm256_castps256_ps128(r3));
  _mm_store_ps(&p[id[4]].x, _mm256_extractf128_ps(r0, 1));
  _mm_store_ps(&p[id[5]].x, _mm256_extractf128_ps(r1, 1));
  _mm_store_ps(&p[id[6]].x, _mm256_extractf128_ps(r2, 1));
  _mm_store_ps(&p[id[7]].x, _mm256_extractf128_ps(r3, 1));
}

TROCAR_XPBD_AVX2 inline float max8(__m256 v) {
  __m128 m = _mm_max_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
  m = _mm_max_ps(m, _mm_movehl_ps(m, m));
  m = _mm_max_ss(m, _mm_shuffle_ps(m, m, 1));
  return _mm_cvtss_f32(m);
}

TROCAR_XPBD_AVX2 inline void cross8(__m256 ax, __m256 ay, __m256 az, __m256 bx, __m256 by, __m256 bz, __m256& rx,
                                    __m256& ry, __m256& rz) {
  rx = _mm256_fmsub_ps(ay, bz, _mm256_mul_ps(az, by));
  ry = _mm256_fmsub_ps(az, bx, _mm256_mul_ps(ax, bz));
  rz = _mm256_fmsub_ps(ax, by, _mm256_mul_ps(ay, bx));
}

TROCAR_XPBD_AVX2 inline __m256 dot8(__m256 ax, __m256 ay, __m256 az, __m256 bx, __m256 by, __m256 bz) {
  return _mm256_fmadd_ps(az, bz, _mm256_fmadd_ps(ay, by, _mm256_mul_ps(ax, bx)));
}

}  // namespace

float xpbd_springs_scalar(XpbdParticle* x, const XpbdSpringColour& c, float inv_h2, bool strain) {
  float worst = 0;
  for (std::size_t k = 0; k < c.count; ++k) {
    XpbdParticle& a = x[c.i[k]];
    XpbdParticle& b = x[c.j[k]];
    const float w = a.w + b.w;
    if (w == 0.f) continue;
    const F3 d = sub(a, b);
    const float length = std::sqrt(dot(d, d));
    if (!(length > 1e-12f)) continue;
    const float inv_length = 1.f / length;
    const F3 u{d.x * inv_length, d.y * inv_length, d.z * inv_length};
    const float constraint = length - c.rest[k];
    const float dlambda = -constraint / (w + c.compliance[k] * inv_h2);
    add_scaled(a, u, a.w * dlambda);
    add_scaled(b, u, -b.w * dlambda);
    if (strain) worst = std::max(worst, std::abs(constraint) / c.rest[k]);
  }
  return worst;
}

TROCAR_XPBD_AVX2 float xpbd_springs_avx2(XpbdParticle* x, const XpbdSpringColour& c, float inv_h2, bool strain) {
  const __m256 one = _mm256_set1_ps(1.f), tiny = _mm256_set1_ps(1e-24f);
  const __m256 vinv_h2 = _mm256_set1_ps(inv_h2);
  const __m256 sign = _mm256_set1_ps(-0.f);
  __m256 worst = _mm256_setzero_ps();
  for (std::size_t k = 0; k < c.count; k += 8) {
    Lanes a = load8(x, c.i + k), b = load8(x, c.j + k);
    const __m256 dx = _mm256_sub_ps(a.x, b.x), dy = _mm256_sub_ps(a.y, b.y), dz = _mm256_sub_ps(a.z, b.z);
    const __m256 length2 = _mm256_fmadd_ps(dz, dz, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dx, dx)));
    const __m256 length = _mm256_sqrt_ps(length2);
    // 0 for a degenerate spring (and the padding): no correction.
    const __m256 valid = _mm256_cmp_ps(length2, tiny, _CMP_GT_OQ);
    const __m256 inv_length = _mm256_and_ps(valid, _mm256_div_ps(one, length));
    const __m256 ux = _mm256_mul_ps(dx, inv_length), uy = _mm256_mul_ps(dy, inv_length),
                 uz = _mm256_mul_ps(dz, inv_length);
    const __m256 rest = _mm256_loadu_ps(c.rest + k);
    const __m256 constraint = _mm256_and_ps(_mm256_sub_ps(length, rest), valid);
    const __m256 w = _mm256_add_ps(a.w, b.w);
    // A padding spring has w = 0 and α > 0: Δλ = 0 there.
    const __m256 denominator = _mm256_fmadd_ps(_mm256_loadu_ps(c.compliance + k), vinv_h2, w);
    const __m256 dlambda = _mm256_div_ps(_mm256_xor_ps(constraint, sign), denominator);
    const __m256 sa = _mm256_mul_ps(a.w, dlambda), sb = _mm256_mul_ps(b.w, dlambda);
    a.x = _mm256_fmadd_ps(ux, sa, a.x);
    a.y = _mm256_fmadd_ps(uy, sa, a.y);
    a.z = _mm256_fmadd_ps(uz, sa, a.z);
    b.x = _mm256_fnmadd_ps(ux, sb, b.x);
    b.y = _mm256_fnmadd_ps(uy, sb, b.y);
    b.z = _mm256_fnmadd_ps(uz, sb, b.z);
    store8(x, c.i + k, a);
    store8(x, c.j + k, b);
    if (strain) worst = _mm256_max_ps(worst, _mm256_div_ps(_mm256_andnot_ps(sign, constraint), rest));
  }
  return strain ? max8(worst) : 0.f;
}

void xpbd_dashpots_scalar(const XpbdParticle* x, XpbdParticle* v, const XpbdSpringColour& c, float h) {
  for (std::size_t k = 0; k < c.count; ++k) {
    const XpbdParticle& a = x[c.i[k]];
    const XpbdParticle& b = x[c.j[k]];
    const float w = a.w + b.w;
    if (w == 0.f || c.damping[k] == 0.f) continue;
    const F3 d = sub(a, b);
    const float length = std::sqrt(dot(d, d));
    if (!(length > 1e-12f)) continue;
    const F3 n{d.x / length, d.y / length, d.z / length};
    XpbdParticle& va = v[c.i[k]];
    XpbdParticle& vb = v[c.j[k]];
    const float u = dot(n, sub(va, vb));
    const float hl = h * c.damping[k];
    const float impulse = -hl * u / (1.f + hl * w);
    add_scaled(va, n, a.w * impulse);
    add_scaled(vb, n, -b.w * impulse);
  }
}

TROCAR_XPBD_AVX2 void xpbd_dashpots_avx2(const XpbdParticle* x, XpbdParticle* v, const XpbdSpringColour& c, float h) {
  const __m256 one = _mm256_set1_ps(1.f), tiny = _mm256_set1_ps(1e-24f), vh = _mm256_set1_ps(h);
  for (std::size_t k = 0; k < c.count; k += 8) {
    const Lanes a = load8(x, c.i + k), b = load8(x, c.j + k);
    Lanes va = load8(v, c.i + k), vb = load8(v, c.j + k);
    const __m256 dx = _mm256_sub_ps(a.x, b.x), dy = _mm256_sub_ps(a.y, b.y), dz = _mm256_sub_ps(a.z, b.z);
    const __m256 length2 = _mm256_fmadd_ps(dz, dz, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dx, dx)));
    const __m256 inv_length =
        _mm256_and_ps(_mm256_cmp_ps(length2, tiny, _CMP_GT_OQ), _mm256_div_ps(one, _mm256_sqrt_ps(length2)));
    const __m256 nx = _mm256_mul_ps(dx, inv_length), ny = _mm256_mul_ps(dy, inv_length),
                 nz = _mm256_mul_ps(dz, inv_length);
    const __m256 u = dot8(nx, ny, nz, _mm256_sub_ps(va.x, vb.x), _mm256_sub_ps(va.y, vb.y), _mm256_sub_ps(va.z, vb.z));
    const __m256 hl = _mm256_mul_ps(vh, _mm256_loadu_ps(c.damping + k));
    const __m256 w = _mm256_add_ps(a.w, b.w);
    // −hλu / (1 + hλw): 0 for the padding (λ = 0) and degenerate springs (n = 0).
    const __m256 impulse = _mm256_div_ps(_mm256_mul_ps(_mm256_sub_ps(_mm256_setzero_ps(), hl), u),
                                         _mm256_fmadd_ps(hl, w, one));
    const __m256 sa = _mm256_mul_ps(a.w, impulse), sb = _mm256_mul_ps(b.w, impulse);
    va.x = _mm256_fmadd_ps(nx, sa, va.x);
    va.y = _mm256_fmadd_ps(ny, sa, va.y);
    va.z = _mm256_fmadd_ps(nz, sa, va.z);
    vb.x = _mm256_fnmadd_ps(nx, sb, vb.x);
    vb.y = _mm256_fnmadd_ps(ny, sb, vb.y);
    vb.z = _mm256_fnmadd_ps(nz, sb, vb.z);
    store8(v, c.i + k, va);
    store8(v, c.j + k, vb);
  }
}

void xpbd_triangles_scalar(XpbdParticle* x, const XpbdTriangleColour& c, float alpha) {
  for (std::size_t k = 0; k < c.count; ++k) {
    XpbdParticle& p0 = x[c.v0[k]];
    XpbdParticle& p1 = x[c.v1[k]];
    XpbdParticle& p2 = x[c.v2[k]];
    const F3 normal = cross(sub(p1, p0), sub(p2, p0));
    const float twice_area = std::sqrt(dot(normal, normal));
    if (!(twice_area > 1e-20f)) continue;
    const float s = 0.5f / twice_area;  // ∂A/∂x_a = ½ n̂ × (x_c − x_b), (a, b, c) cyclic
    const F3 g0 = cross(normal, sub(p2, p1));
    const F3 g1 = cross(normal, sub(p0, p2));
    const F3 g2 = cross(normal, sub(p1, p0));
    const float denominator = s * s * (p0.w * dot(g0, g0) + p1.w * dot(g1, g1) + p2.w * dot(g2, g2)) + alpha;
    if (!(denominator > 0.f)) continue;
    const float dlambda = -(0.5f * twice_area - c.rest_area[k]) / denominator * s;
    add_scaled(p0, g0, p0.w * dlambda);
    add_scaled(p1, g1, p1.w * dlambda);
    add_scaled(p2, g2, p2.w * dlambda);
  }
}

TROCAR_XPBD_AVX2 void xpbd_triangles_avx2(XpbdParticle* x, const XpbdTriangleColour& c, float alpha) {
  const __m256 half = _mm256_set1_ps(0.5f), tiny = _mm256_set1_ps(1e-40f), valpha = _mm256_set1_ps(alpha);
  for (std::size_t k = 0; k < c.count; k += 8) {
    Lanes p0 = load8(x, c.v0 + k), p1 = load8(x, c.v1 + k), p2 = load8(x, c.v2 + k);
    __m256 nx, ny, nz;
    cross8(_mm256_sub_ps(p1.x, p0.x), _mm256_sub_ps(p1.y, p0.y), _mm256_sub_ps(p1.z, p0.z), _mm256_sub_ps(p2.x, p0.x),
           _mm256_sub_ps(p2.y, p0.y), _mm256_sub_ps(p2.z, p0.z), nx, ny, nz);
    const __m256 twice2 = dot8(nx, ny, nz, nx, ny, nz);
    const __m256 valid = _mm256_cmp_ps(twice2, tiny, _CMP_GT_OQ);
    const __m256 twice_area = _mm256_sqrt_ps(twice2);
    const __m256 s = _mm256_and_ps(valid, _mm256_div_ps(half, twice_area));
    __m256 g0x, g0y, g0z, g1x, g1y, g1z, g2x, g2y, g2z;
    cross8(nx, ny, nz, _mm256_sub_ps(p2.x, p1.x), _mm256_sub_ps(p2.y, p1.y), _mm256_sub_ps(p2.z, p1.z), g0x, g0y, g0z);
    cross8(nx, ny, nz, _mm256_sub_ps(p0.x, p2.x), _mm256_sub_ps(p0.y, p2.y), _mm256_sub_ps(p0.z, p2.z), g1x, g1y, g1z);
    cross8(nx, ny, nz, _mm256_sub_ps(p1.x, p0.x), _mm256_sub_ps(p1.y, p0.y), _mm256_sub_ps(p1.z, p0.z), g2x, g2y, g2z);
    const __m256 weighted = _mm256_fmadd_ps(
        p2.w, dot8(g2x, g2y, g2z, g2x, g2y, g2z),
        _mm256_fmadd_ps(p1.w, dot8(g1x, g1y, g1z, g1x, g1y, g1z), _mm256_mul_ps(p0.w, dot8(g0x, g0y, g0z, g0x, g0y, g0z))));
    const __m256 denominator = _mm256_fmadd_ps(_mm256_mul_ps(s, s), weighted, valpha);
    const __m256 constraint = _mm256_fmsub_ps(half, twice_area, _mm256_loadu_ps(c.rest_area + k));
    // −C s / denominator; 0 where degenerate (s = 0).
    const __m256 dlambda = _mm256_div_ps(_mm256_mul_ps(_mm256_sub_ps(_mm256_setzero_ps(), constraint), s), denominator);
    const __m256 s0 = _mm256_mul_ps(p0.w, dlambda), s1 = _mm256_mul_ps(p1.w, dlambda), s2 = _mm256_mul_ps(p2.w, dlambda);
    p0.x = _mm256_fmadd_ps(g0x, s0, p0.x);
    p0.y = _mm256_fmadd_ps(g0y, s0, p0.y);
    p0.z = _mm256_fmadd_ps(g0z, s0, p0.z);
    p1.x = _mm256_fmadd_ps(g1x, s1, p1.x);
    p1.y = _mm256_fmadd_ps(g1y, s1, p1.y);
    p1.z = _mm256_fmadd_ps(g1z, s1, p1.z);
    p2.x = _mm256_fmadd_ps(g2x, s2, p2.x);
    p2.y = _mm256_fmadd_ps(g2y, s2, p2.y);
    p2.z = _mm256_fmadd_ps(g2z, s2, p2.z);
    store8(x, c.v0 + k, p0);
    store8(x, c.v1 + k, p1);
    store8(x, c.v2 + k, p2);
  }
}

}  // namespace trocar::tissue_detail
