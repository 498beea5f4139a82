#pragma once
/// The XPBD passes over one colour (internal to the tissue module): a portable scalar version and
/// an AVX2 version that takes 8 springs or triangles of a colour at a time. No two items of a
/// colour share a vertex, so the 8 lanes read and write different particles and the result does
/// not depend on the order within the colour.
#include <cstddef>
#include <cstdint>

#include "trocar/tissue/xpbd.h"

namespace trocar::tissue_detail {

/// Springs of one colour, structure of arrays, `count` a multiple of 8 (padding springs join the
/// padding particle, whose inverse mass is 0, to itself).
struct XpbdSpringColour {
  const std::uint32_t* i;
  const std::uint32_t* j;
  const float* rest;        ///< l (m)
  const float* compliance;  ///< α = 1/k (m/N)
  const float* damping;     ///< λ (N·s/m), for the dashpot pass
  std::size_t count;
};

/// Triangles of one colour (area term), `count` a multiple of 8 (padding as for springs).
struct XpbdTriangleColour {
  const std::uint32_t* v0;
  const std::uint32_t* v1;
  const std::uint32_t* v2;
  const float* rest_area;  ///< A0 (m²)
  std::size_t count;
};

/// One Gauss–Seidel pass over a colour of springs (XPBD eq. 18, no damping term). Returns the
/// largest |C|/l before the correction when `strain` is set, else 0.
float xpbd_springs_scalar(XpbdParticle* x, const XpbdSpringColour& c, float inv_h2, bool strain);
float xpbd_springs_avx2(XpbdParticle* x, const XpbdSpringColour& c, float inv_h2, bool strain);
/// The springs' dashpots on the velocities v (xyz of each XpbdParticle), implicitly over h: for
/// each spring, with n along it and u = n·(v_i − v_j), P = −λ h u / (1 + h λ (w_i + w_j)),
/// v_i += w_i P n, v_j −= w_j P n (the exact backward-Euler solution of one dashpot).
void xpbd_dashpots_scalar(const XpbdParticle* x, XpbdParticle* v, const XpbdSpringColour& c, float h);
void xpbd_dashpots_avx2(const XpbdParticle* x, XpbdParticle* v, const XpbdSpringColour& c, float h);
/// One pass over a colour of area constraints C = A − A0 with compliance α̃ = alpha.
void xpbd_triangles_scalar(XpbdParticle* x, const XpbdTriangleColour& c, float alpha);
void xpbd_triangles_avx2(XpbdParticle* x, const XpbdTriangleColour& c, float alpha);

}  // namespace trocar::tissue_detail
