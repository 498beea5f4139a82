#include "trocar/response/contact_response.h"

#include <algorithm>
#include <cmath>

#include "trocar/geometry/tolerance.h"

namespace trocar {

const char* contact_status_name(ContactStatus status) {
  switch (status) {
    case ContactStatus::kApplied: return "applied";
    case ContactStatus::kPierced: return "pierced";
    case ContactStatus::kDegenerateTissue: return "degenerate-tissue";
    case ContactStatus::kCoplanar: return "coplanar";
    case ContactStatus::kNoCrossing: return "no-crossing";
    case ContactStatus::kMissed: return "missed";
    case ContactStatus::kGrasped: return "grasped";
    case ContactStatus::kCount: break;
  }
  return "unknown";
}

Vec3 obb_penetration(const Obb& box, const Vec3& p, const Vec3& n_in) {
  const Vec3 r = p - box.center;
  Vec3 pd = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    const Vec3 a = box.axes.col(k);
    const Real g = a.dot(n_in);
    if (g == 0) continue;  // the ray runs parallel to the tissue plane: it never goes deeper
    const Real s = g > 0 ? Real{1} : Real{-1};
    // Slab |a·(x − c)| ≤ h along the ray x = P + t·s·a: a·(x − c) = p_k + t·s reaches s·h at
    // t = h − s·p_k (the ray–OBB exit of the other two slabs is never earlier: the ray keeps
    // their coordinates).
    const Real t = std::max(box.half_extents[k] - s * a.dot(r), Real{0});
    pd += (t * s) * a;
  }
  return pd;
}

namespace {

// Barycentric coordinates of x in the plane of B (x − B1 = β·e0 + γ·e1 + off-plane):
// β = (x − B1)·(e1 × n)/|n|², γ = (x − B1)·(n × e0)/|n|² (take (·)×e1 and e0×(·), dot n).
inline Vec3 bary(const Vec3& x, const Vec3& b0, const Vec3& c_beta, const Vec3& c_gamma) {
  const Vec3 w = x - b0;
  const Real beta = w.dot(c_beta);
  const Real gamma = w.dot(c_gamma);
  return {Real{1} - beta - gamma, beta, gamma};
}

}  // namespace

ContactResponse respond_contact(const ContactTriangles& tri, const Obb& box, const Vec3* top,
                                std::span<const Vec3> instrument_positions,
                                const ResponseSettings& settings) {
  ContactResponse r;
  // ---- Step 1: tissue normal. n = (B2 − B1)×(B3 − B1), |n| = twice the area.
  const Vec3& b0 = tri.b[0];
  const Vec3 e0 = tri.b[1] - b0;
  const Vec3 e1 = tri.b[2] - b0;
  const Vec3 nrm = e0.cross(e1);
  const Real nn = nrm.squaredNorm();
  const Real longest2 = std::max({e0.squaredNorm(), e1.squaredNorm(), (tri.b[2] - tri.b[1]).squaredNorm()});
  // Degenerate (tolerance.h): 2·area ≤ kDegenerateRatio·longest², compared squared. Zero and
  // non-finite areas fail the test too.
  if (!(nn > kDegenerateRatio * kDegenerateRatio * longest2 * longest2) || !std::isfinite(nn)) {
    r.status = ContactStatus::kDegenerateTissue;
    return r;
  }
  // The unit normal needs a square root and a division; everything up to step 7 uses only
  // signs and ratios of distances, so it works with the unnormalised n (|n| = 2·area) and keeps
  // the root off the critical path.
  const Real inv_len = Real{1} / std::sqrt(nn);
  const Vec3 n_out = nrm * inv_len;
  const Vec3 n_in = -n_out;
  r.normal_in = n_in;

  // ---- Step 9 (cheapest first): the far surface of a pierced organ has the top vertex inside.
  if (settings.pierce_filter && top != nullptr && nrm.dot(*top - b0) < 0) {
    r.status = ContactStatus::kPierced;
    return r;
  }

  // ---- Step 2: classify A_i by d_i = n_out·(A_i − B1); inside means d_i < 0 (a vertex exactly
  // on the plane counts as outside). d holds |n|·d_i (same signs and ratios).
  const Real d[3] = {nrm.dot(tri.a[0] - b0), nrm.dot(tri.a[1] - b0), nrm.dot(tri.a[2] - b0)};
  const Real dmax = std::max({std::abs(d[0]), std::abs(d[1]), std::abs(d[2])});
  // Coplanar: every vertex within kTriTriTolerance·L of the plane, L = B's longest edge (the
  // detector uses the pair's size; B's alone is cheaper and never larger, so no pair the
  // detector calls non-coplanar is called coplanar here).
  if (dmax * dmax <= kTriTriTolerance * kTriTriTolerance * longest2 * nn) {
    r.status = ContactStatus::kCoplanar;
    return r;
  }
  const int in0 = d[0] < 0, in1 = d[1] < 0, in2 = d[2] < 0;
  const int inside = in0 + in1 + in2;
  if (inside == 0 || inside == 3) {
    r.status = ContactStatus::kNoCrossing;
    return r;
  }
  // Relabel: A3 is the vertex alone on its side (the inside one for one vertex through, Fig.
  // 3.5a; the outside one for an edge through, Fig. 3.5b → c). A1, A2 follow in cyclic order.
  const int lone_in = inside == 1 ? 1 : 0;  // value of `in` that the lone vertex has
  const int i3 = in0 == lone_in ? 0 : (in1 == lone_in ? 1 : 2);
  const int i1 = (i3 + 1) % 3;
  const int i2 = (i3 + 2) % 3;
  r.inside_count = static_cast<std::uint8_t>(inside);
  r.lone_vertex = static_cast<std::uint8_t>(i3);

  // ---- Step 3: M on A1A3 and N on A2A3 where the signed distance is 0 (similar triangles:
  // t = d1/(d1 − d3)). d1 and d3 lie on different sides (one < 0 ≤ the other), so the
  // denominator is non-zero and t ∈ [0, 1].
  const Vec3& a1 = tri.a[i1];
  const Vec3& a2 = tri.a[i2];
  const Vec3& a3 = tri.a[i3];
  const Real tm = d[i1] / (d[i1] - d[i3]);
  const Real tn = d[i2] / (d[i2] - d[i3]);
  const Vec3 m = a1 + tm * (a3 - a1);
  const Vec3 n = a2 + tn * (a3 - a2);
  r.m = m;
  r.n = n;

  // ---- Step 4: P = N if its barycentric coordinates in B are all ≥ 0; otherwise move it along
  // MN to the tissue triangle's edge. λ(M + s(N − M)) = λM + s(λN − λM) is affine in s, so the
  // part of MN inside B is an interval of s ∈ [0, 1]; P is its end nearest N (the edge MN leaves
  // B through, Fig. 3.7): s = min(1, min over λN_i < 0 of λM_i/(λM_i − λN_i)), the first zero
  // crossing of a coordinate that is negative at N. If the interval is empty (MN misses B), some
  // coordinate of P is still negative, which the check below catches.
  const Real inv_nn = Real{1} / nn;
  const Vec3 c_beta = e1.cross(nrm) * inv_nn;
  const Vec3 c_gamma = nrm.cross(e0) * inv_nn;
  const Vec3 lm = bary(m, b0, c_beta, c_gamma);
  const Vec3 ln = bary(n, b0, c_beta, c_gamma);
  Real s = 1;
  for (int i = 0; i < 3; ++i) {
    // λN_i < 0 ≤ ... : λM_i − λN_i > 0 unless λM_i ≤ λN_i < 0 too (then the crossing is behind
    // M: s would be ≤ 0; clamp to 0 and let the check decide).
    if (ln[i] < 0) {
      const Real gap = lm[i] - ln[i];
      s = gap > 0 ? std::min(s, lm[i] / gap) : Real{0};
    }
  }
  s = std::max(s, Real{0});
  Vec3 wb = lm + s * (ln - lm);
  // A pair touching within the detector's tolerance leaves coordinates of rounding size below
  // 0; a real miss gives no force.
  if (wb.minCoeff() < 0) {
    if (wb.minCoeff() < -1e-9) {
      r.status = ContactStatus::kMissed;
      return r;
    }
    wb = wb.cwiseMax(Real{0});
    wb /= wb.sum();  // the sum stays ≥ 1 > 0
  }
  r.moved_to_edge = s < 1;
  r.point = m + s * (n - m);
  r.weights_b = wb;
  // Weights in A, exactly: M = (1−tm)A1 + tm·A3, N = (1−tn)A2 + tn·A3, P = (1−s)M + s·N.
  Vec3 wa = Vec3::Zero();
  wa[i1] = (1 - s) * (1 - tm);
  wa[i2] = s * (1 - tn);
  wa[i3] = (1 - s) * tm + s * tn;
  r.weights_a = wa;

  // ---- Step 6: relative velocity at P, each side interpolated with P's weights in its triangle.
  const Vec3 v_i = wa[0] * tri.va[0] + wa[1] * tri.va[1] + wa[2] * tri.va[2];
  const Vec3 v_t = wb[0] * tri.vb[0] + wb[1] * tri.vb[1] + wb[2] * tri.vb[2];
  const Vec3 v_rel = v_i - v_t;
  r.relative_velocity = v_rel;

  // ---- Steps 5 and 7: depth.
  Vec3 dvec = Vec3::Zero();
  Real depth = 0;
  switch (settings.method) {
    case ResponseMethod::kObb:
    case ResponseMethod::kProject: {
      // Eq. 3.7: PD = Pd1 + Pd2 + Pd3 from the carried OBB (only the signs of a_k·n_in matter,
      // so the unnormalised −n is passed).
      const Vec3 pd = obb_penetration(box, r.point, -nrm);
      r.penetration = pd;
      // Eq. 3.8: D = (PD·v̂) v̂ = (PD·v / v·v) v, |D| = PD·v / |v|; resting (|v| ≤ threshold) or
      // receding along PD (PD·v ≤ 0): D = (PD·n_in) n_in, |D| = PD·n_in (≥ 0: every Pd_k has
      // a non-negative component along n_in).
      const Real speed2 = v_rel.squaredNorm();
      const Real pv = pd.dot(v_rel);
      if (speed2 > settings.resting_speed * settings.resting_speed && speed2 > 0 && pv > 0) {
        dvec = (pv / speed2) * v_rel;
        depth = pv / std::sqrt(speed2);
      } else {
        depth = std::max(pd.dot(n_in), Real{0});
        dvec = depth * n_in;
      }
      // Depth cap (a departure from the seed, docs/response.md): PD measures to the side of the
      // instrument's box, which the instrument fills only if it is a box, so PD stays
      // millimetres or more however shallow the contact is. Capped at the instrument triangle's
      // deepest vertex below the tissue plane (step 2's d_i), |D| goes to 0 with the contact;
      // for a box-shaped instrument pressing face first the two depths are equal.
      if (settings.depth_cap) {
        const Real local = -std::min({d[0], d[1], d[2]}) * inv_len;
        r.depth_capped = depth > local;
        if (r.depth_capped) {
          dvec *= local / depth;  // depth > local > 0 (some d_i < 0)
          depth = local;
        }
      }
      break;
    }
    case ResponseMethod::kSdf:  // no penalty kernel (the solver skips it); if called, as primitive
    case ResponseMethod::kPrimitive: {
      // The two triangles alone: the instrument triangle's deepest vertex below the plane.
      depth = -std::min({d[0], d[1], d[2]}) * inv_len;
      dvec = depth * n_in;
      break;
    }
    case ResponseMethod::kNormal: {
      // The instrument's deepest vertex along n_in (A's vertices when none are given).
      depth = -std::min({d[0], d[1], d[2]}) * inv_len;
      for (const Vec3& x : instrument_positions) depth = std::max(depth, n_in.dot(x - b0));
      dvec = depth * n_in;
      break;
    }
  }
  r.deformation = dvec;
  r.depth = depth;

  // ---- Step 8, eq. 3.9 with the damping signed to resist approach: f = max(0, K|D| + μ v_rel·n_in).
  const Real f = std::max(Real{0}, settings.stiffness * r.depth + settings.damping * v_rel.dot(n_in));
  r.force = f * n_in;
  r.status = ContactStatus::kApplied;
  return r;
}

}  // namespace trocar
