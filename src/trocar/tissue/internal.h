#pragma once
/// Shared by the tissue module's scalar passes (forces.cpp, integrator_implicit.cpp) and its
/// AVX2 passes: the degenerate-geometry thresholds, which force terms are on, and a plain
/// 3-vector for hot loops. Internal to the module.
#include <cmath>

#include "trocar/core/types.h"
#include "trocar/tissue/forces.h"
#include "trocar/tissue/settings.h"

namespace trocar::tissue_detail {

/// Squared spring length (m²) below which a spring has no direction (1e-15 m: far below any
/// mesh edge, far above the denormal range so 1/|d| stays finite).
constexpr Real kTinyLength2 = 1e-30;
/// Squared |n| = (2A)² (m⁴) below which a triangle has no normal (A < 5e-16 m²).
constexpr Real kTinyNormal2 = 1e-30;

/// 1/|d| for a squared length, or 0 for a degenerate one (so u = d·inv is 0, never NaN).
inline Real safe_inverse_sqrt(Real length2, Real tiny2) { return length2 > tiny2 ? 1.0 / std::sqrt(length2) : 0.0; }

/// The area term applies: switched on, k_area > 0 and rest areas present.
inline bool area_term_on(const MassSpringSettings& s, const ForceTerms& t) {
  return t.area && s.k_area > 0 && s.mean_rest_area > 0 && s.rest_areas.size() == s.triangles.size();
}
/// The volume term applies: switched on, a closed non-empty mesh, k_volume > 0, V0 > 0.
inline bool volume_term_on(const MassSpringSettings& s, const ForceTerms& t) {
  return t.volume && s.closed && s.k_volume > 0 && s.rest_volume > 0 && !s.triangles.empty();
}

/// The volume term's energy ½ k_volume (V − V0)²/V0 at volume V (J).
inline Real volume_energy(const MassSpringSettings& s, Real volume) {
  const Real dv = volume - s.rest_volume;
  return 0.5 * s.k_volume / s.rest_volume * dv * dv;
}

/// A plain 3-vector for the hot loops. Eigen's Vec3 arithmetic packs (x, y) into an SSE register
/// and, for values computed lane by lane (cross products), builds that packet through the stack,
/// which stalls store forwarding (measured: the area pass ran 2.5× slower). Scalar code avoids it.
struct P3 {
  Real x, y, z;
};
inline P3 load(const Vec3& v) { return {v[0], v[1], v[2]}; }
inline P3 load(const Real* v) { return {v[0], v[1], v[2]}; }
inline void store(Real* out, const P3& a) {
  out[0] = a.x;
  out[1] = a.y;
  out[2] = a.z;
}
inline P3 operator-(const P3& a, const P3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline P3 operator+(const P3& a, const P3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline P3 operator*(Real s, const P3& a) { return {s * a.x, s * a.y, s * a.z}; }
inline Real dot(const P3& a, const P3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline P3 cross(const P3& a, const P3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline void add_to(Vec3& f, const P3& a) {
  f[0] += a.x;
  f[1] += a.y;
  f[2] += a.z;
}
inline void subtract_from(Vec3& f, const P3& a) {
  f[0] -= a.x;
  f[1] -= a.y;
  f[2] -= a.z;
}

}  // namespace trocar::tissue_detail
