#include "trocar/collision/narrow_phase.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "trocar/collision/narrow_phase_detail.h"
#include "trocar/core/cpu_features.h"
#include "trocar/geometry/triangle_triangle.h"

namespace trocar {
namespace narrow_detail {
namespace {

// A triangle's plane: the unnormalised normal n = (q1 − q0) × (q2 − q0) (no square root), |n|²,
// and whether the triangle is well shaped (not a sliver: |n|² > 1e-6·(longest edge)⁴).
struct TrianglePlane {
  Vec3 n = Vec3::Zero();
  Real n2 = 0;
  bool well_shaped = false;
};

// One candidate after the plane tests, in coordinates relative to a0 (so that the rounding of
// what follows is that of the pair's size, not of its distance from the origin).
struct PlaneStage {
  Vec3 ra[3];     // A's corners − a0
  Vec3 rb[3];     // B's corners − a0
  TrianglePlane a;
  TrianglePlane b;
  Real d_a[3];    // A's corners to B's plane (× |nB|)
  Real d_b[3];    // B's corners to A's plane (× |nA|)
  Real size = 0;  // the pair's size L: largest side of the six corners' box
};

// Cheap, conservative rejections before the exact test (intersect_triangles). Each may only
// reject pairs that intersect_triangles rejects too, so they change nothing but the time; the
// margins below are orders of magnitude wider than the test's tolerance (kTriTriTolerance = 1e-12
// of the pair's size L) and than its rounding errors.

// The plane of triangle q0q1q2 from differences of its own corners, so that its rounding follows
// the triangle's size, not its distance from the origin.
TrianglePlane plane_of(const Vec3& q0, const Vec3& q1, const Vec3& q2) {
  const Vec3 e1 = q1 - q0;
  const Vec3 e2 = q2 - q0;
  TrianglePlane plane;
  plane.n = e1.cross(e2);
  plane.n2 = plane.n.squaredNorm();
  const Real longest2 = std::max({e1.squaredNorm(), e2.squaredNorm(), (q2 - q1).squaredNorm()});
  plane.well_shaped = plane.n2 > 1e-6 * longest2 * longest2;
  return plane;
}

// Plane rejection: all of the three distances d (× |n|) strictly on one side of the plane, by
// more than 1e-9·L (compared squared, d_i² > (1e-9·L)²·|n|²). Skipped (false) for slivers, whose
// plane is ill-conditioned.
bool separated_by_plane(const TrianglePlane& plane, const Real (&d)[3], Real size) {
  if (!plane.well_shaped) return false;
  const bool all_above = d[0] > 0 && d[1] > 0 && d[2] > 0;
  const bool all_below = d[0] < 0 && d[1] < 0 && d[2] < 0;
  if (!all_above && !all_below) return false;
  const Real threshold2 = 1e-18 * size * size * plane.n2;
  return d[0] * d[0] > threshold2 && d[1] * d[1] > threshold2 && d[2] * d[2] > threshold2;
}

// Extends [lo, hi] by the projections on `dir` of the part of triangle p0p1p2 (corners relative
// to a common origin) that lies within the slab |d| ≤ tau of the other plane, d being the
// corners' signed distances (× |n|): per edge, the sub-segment inside the slab.
void slab_interval(const Vec3 (&p)[3], const Real (&d)[3], Real tau, const Vec3& dir, Real& lo, Real& hi) {
  Real proj[3];
  for (int i = 0; i < 3; ++i) proj[i] = dir.dot(p[i]);
  for (int i = 0; i < 3; ++i) {
    const int j = i == 2 ? 0 : i + 1;
    const Real di = d[i];
    const Real dj = d[j];
    if ((di > tau && dj > tau) || (di < -tau && dj < -tau)) continue;  // edge outside the slab
    Real l0 = 0;
    Real l1 = 1;
    const Real dd = dj - di;
    if (std::abs(dd) > tau) {
      // d(λ) = di + λ·dd ∈ [−tau, tau] for λ between these two values.
      const Real a = (-tau - di) / dd;
      const Real b = (tau - di) / dd;
      l0 = std::max(l0, std::min(a, b));
      l1 = std::min(l1, std::max(a, b));
      if (l0 > l1) {  // only by rounding (the edge reaches the slab): keep the nearer end
        l0 = l1 = std::clamp(0.5 * (l0 + l1), Real{0}, Real{1});
      }
    }
    // Nearly parallel to the plane (|dd| ≤ tau): the whole edge is within 2·tau, keep it all.
    const Real x0 = proj[i] + l0 * (proj[j] - proj[i]);
    const Real x1 = proj[i] + l1 * (proj[j] - proj[i]);
    lo = std::min({lo, x0, x1});
    hi = std::max({hi, x0, x1});
  }
}

// Interval rejection (Möller's test, made conservative): when the planes cross at a clear angle
// (sin θ ≥ 0.01) and neither triangle is a sliver, the parts of A and B near the other's plane
// (within 1e-9·L, far more than the exact test's snapping and rounding) project on the
// intersection line direction nA × nB to two intervals; the pair is rejected when they are apart
// by more than 1e-7·L. Every point the exact test puts on a trace lies in those parts, and its
// ordering direction differs from the line by far less than that margin allows.
bool separated_on_line(const PlaneStage& s) {
  if (!s.a.well_shaped || !s.b.well_shaped) return false;
  const Vec3 dir = s.a.n.cross(s.b.n);  // nA × nB
  const Real dir2 = dir.squaredNorm();
  if (!(dir2 >= 1e-4 * s.a.n2 * s.b.n2)) return false;  // sin²θ < 1e-4
  constexpr Real kInf = std::numeric_limits<Real>::infinity();
  Real a_lo = kInf, a_hi = -kInf, b_lo = kInf, b_hi = -kInf;
  slab_interval(s.ra, s.d_a, 1e-9 * s.size * std::sqrt(s.b.n2), dir, a_lo, a_hi);
  slab_interval(s.rb, s.d_b, 1e-9 * s.size * std::sqrt(s.a.n2), dir, b_lo, b_hi);
  if (!(a_lo <= a_hi) || !(b_lo <= b_hi)) return false;  // (not expected: both straddle)
  const Real gap = std::max(a_lo, b_lo) - std::min(a_hi, b_hi);  // in units of |dir|
  return gap > 0 && gap * gap > 1e-14 * s.size * s.size * dir2;
}

// The plane stage of one candidate (the portable path). A's plane is kept while consecutive
// candidates share A (the broad phases emit a triangle's partners one after another).
struct ScalarStage {
  std::uint64_t a_key = ~std::uint64_t{0};  // (object << 32) | triangle of the cached A plane
  TrianglePlane a_plane;

  // False when the pair is rejected (or not finite); otherwise fills s.
  bool run(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair& pair, PlaneStage& s) {
    const Triangle& ta = oa.triangles[pair.triangle_a];
    const Triangle& tb = ob.triangles[pair.triangle_b];
    const Vec3& a0 = oa.positions[ta[0]];
    s.ra[0] = Vec3::Zero();
    s.ra[1] = oa.positions[ta[1]] - a0;
    s.ra[2] = oa.positions[ta[2]] - a0;
    for (int i = 0; i < 3; ++i) s.rb[i] = ob.positions[tb[i]] - a0;
    Vec3 lo = s.ra[0].cwiseMin(s.ra[1]).cwiseMin(s.ra[2]);
    Vec3 hi = s.ra[0].cwiseMax(s.ra[1]).cwiseMax(s.ra[2]);
    for (const Vec3& x : s.rb) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
    s.size = (hi - lo).maxCoeff();
    if (!(s.size < std::numeric_limits<Real>::infinity())) return false;  // NaN or infinite input
    const std::uint64_t key = (std::uint64_t{pair.object_a} << 32) | pair.triangle_a;
    if (key != a_key) {
      a_key = key;
      a_plane = plane_of(s.ra[0], s.ra[1], s.ra[2]);
    }
    s.a = a_plane;
    for (int i = 0; i < 3; ++i) s.d_b[i] = s.a.n.dot(s.rb[i]);
    if (separated_by_plane(s.a, s.d_b, s.size)) return false;
    s.b = plane_of(s.rb[0], s.rb[1], s.rb[2]);
    for (int i = 0; i < 3; ++i) s.d_a[i] = s.b.n.dot(s.ra[i] - s.rb[0]);
    return !separated_by_plane(s.b, s.d_a, s.size);
  }
};

}  // namespace

void append_contact(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair& pair,
                    const TriTriResult& r, std::vector<Contact>& out) {
  if (!r.intersects) return;
  Contact c;
  c.object_a = pair.object_a;
  c.object_b = pair.object_b;
  c.triangle_a = pair.triangle_a;
  c.triangle_b = pair.triangle_b;
  c.kind = contact_kind(oa.role, ob.role);
  c.coplanar = r.coplanar;
  c.segment_p = r.p;
  c.segment_q = r.q;
  out.push_back(c);
}

void exact_candidate(const CollisionObject& oa, const CollisionObject& ob, const CandidatePair& pair,
                     std::vector<Contact>& out) {
  const Triangle& ta = oa.triangles[pair.triangle_a];
  const Triangle& tb = ob.triangles[pair.triangle_b];
  append_contact(oa, ob, pair,
                 intersect_triangles(oa.positions[ta[0]], oa.positions[ta[1]], oa.positions[ta[2]],
                                     ob.positions[tb[0]], ob.positions[tb[1]], ob.positions[tb[2]]),
                 out);
}

namespace {

// The candidates the vector rejection tests keep, four at a time, for the vector exact test
// (those it leaves go through intersect_triangles one by one). The same contacts as one
// exact_candidate() each.
class ExactBatch {
 public:
  static constexpr int kLanes = 4;

  void add(std::span<const CollisionObject> objects, const CandidatePair& pair, std::vector<Contact>& out) {
    pairs_[count_++] = &pair;
    if (count_ == kLanes) flush(objects, out);
  }

  void flush(std::span<const CollisionObject> objects, std::vector<Contact>& out) {
    if (count_ == 0) return;
    const Vec3* corners[kLanes][6];
    for (int k = 0; k < kLanes; ++k) {
      const CandidatePair& pair = *pairs_[k < count_ ? k : 0];  // spare lanes repeat the first
      const CollisionObject& oa = objects[pair.object_a];
      const CollisionObject& ob = objects[pair.object_b];
      const Triangle& ta = oa.triangles[pair.triangle_a];
      const Triangle& tb = ob.triangles[pair.triangle_b];
      for (int c = 0; c < 3; ++c) {
        corners[k][c] = &oa.positions[ta[c]];
        corners[k][3 + c] = &ob.positions[tb[c]];
      }
    }
    TriTriResult r[kLanes];
    const int done = exact4_avx2(corners, r);
    for (int k = 0; k < count_; ++k) {
      const CandidatePair& pair = *pairs_[k];
      const CollisionObject& oa = objects[pair.object_a];
      const CollisionObject& ob = objects[pair.object_b];
      if (done >> k & 1) {
        append_contact(oa, ob, pair, r[k], out);
      } else {
        exact_candidate(oa, ob, pair, out);
      }
    }
    count_ = 0;
  }

 private:
  const CandidatePair* pairs_[kLanes] = {};
  int count_ = 0;
};

}  // namespace

namespace {

// Sorts contacts by (object_a, object_b, triangle_a, triangle_b) without allocating. Up to
// kKeyed contacts: their keys (two 64-bit words) and positions are sorted on the stack and the
// contacts (72 bytes each) are then moved once, cycle by cycle, into place; sorting the contacts
// themselves moved them about log n times each (bench_collision scene a: ~5 % of the frame).
// More contacts: std::sort in place.
void sort_contacts(std::vector<Contact>& out) {
  constexpr std::size_t kKeyed = 512;
  if (out.size() > kKeyed) {
    std::sort(out.begin(), out.end(), contact_less);  // introsort in place: no allocation
    return;
  }
  struct Key {
    std::uint64_t objects;
    std::uint64_t triangles;
    std::uint32_t index;
  };
  Key keys[kKeyed];
  const auto n = static_cast<std::uint32_t>(out.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    const Contact& c = out[i];
    keys[i] = {(std::uint64_t{c.object_a} << 32) | c.object_b, (std::uint64_t{c.triangle_a} << 32) | c.triangle_b, i};
  }
  std::sort(keys, keys + n, [](const Key& x, const Key& y) {
    return x.objects != y.objects ? x.objects < y.objects : x.triangles < y.triangles;
  });
  // Position k takes the contact at keys[k].index; each cycle of that permutation is rotated
  // once, and a placed position is marked by pointing at itself.
  for (std::uint32_t k = 0; k < n; ++k) {
    if (keys[k].index == k) continue;
    const Contact first = out[k];
    std::uint32_t j = k;
    while (keys[j].index != k) {
      const std::uint32_t from = keys[j].index;
      out[j] = out[from];
      keys[j].index = j;
      j = from;
    }
    out[j] = first;
    keys[j].index = j;
  }
}

}  // namespace
}  // namespace narrow_detail

void narrow_phase(std::span<const CollisionObject> objects, std::span<const CandidatePair> pairs,
                  std::vector<Contact>& out, bool allow_simd) {
  using namespace narrow_detail;
  out.clear();
  const bool simd = allow_simd && cpu_has_avx2_fma();
  ScalarStage scalar;
  PlaneStage s;
  ExactBatch batch;
  // Whether the four candidates from k on share pairs[k]'s object pair.
  const auto four_same_objects = [&](std::size_t k) {
    if (k + 4 > pairs.size()) return false;
    for (std::size_t m = k + 1; m < k + 4; ++m) {
      if (pairs[m].object_a != pairs[k].object_a || pairs[m].object_b != pairs[k].object_b) return false;
    }
    return true;
  };
  for (std::size_t k = 0; k < pairs.size();) {
    const CandidatePair& pair = pairs[k];
    const CollisionObject& oa = objects[pair.object_a];
    const CollisionObject& ob = objects[pair.object_b];
    // Four candidates of one object pair at a time (AVX2); the rest one by one.
    if (simd && four_same_objects(k)) {
      const int keep = reject4_avx2(oa, ob, &pairs[k]);
      for (int lane = 0; lane < 4; ++lane) {
        if (keep >> lane & 1) batch.add(objects, pairs[k + static_cast<std::size_t>(lane)], out);
      }
      k += 4;
      continue;
    }
    if (scalar.run(oa, ob, pair, s) && !separated_on_line(s)) exact_candidate(oa, ob, pair, out);
    ++k;
  }
  batch.flush(objects, out);
  sort_contacts(out);
}

}  // namespace trocar
