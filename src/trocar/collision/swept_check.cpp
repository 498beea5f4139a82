#include "trocar/collision/swept_check.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "trocar/collision/detector.h"
#include "trocar/core/aabb.h"
#include "trocar/core/error.h"
#include "trocar/geometry/aabb_tree.h"
#include "trocar/geometry/closest_point.h"
#include "trocar/geometry/triangle_triangle.h"

namespace trocar {
namespace {

// Value of the cubic c0 + c1 t + c2 t² + c3 t³ (Horner).
Real cubic(const Real c[4], Real t) { return ((c[3] * t + c[2]) * t + c[1]) * t + c[0]; }

// A root of the cubic in [lo, hi] where it changes sign (or is zero at an end), by bisection to
// the resolution of doubles.
Real bisect(const Real c[4], Real lo, Real hi) {
  Real f_lo = cubic(c, lo);
  for (int it = 0; it < 200 && hi - lo > 0; ++it) {
    const Real mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    const Real f_mid = cubic(c, mid);
    if (f_mid == 0) return mid;
    if ((f_mid < 0) == (f_lo < 0)) {
      lo = mid;
      f_lo = f_mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

Real extent(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 lo = a.cwiseMin(b).cwiseMin(c).cwiseMin(d);
  const Vec3 hi = a.cwiseMax(b).cwiseMax(c).cwiseMax(d);
  return (hi - lo).maxCoeff();
}

// Does vertex p cross triangle abc (all moving linearly, positions at 0 and 1) at some t ∈ [0,1]?
bool vertex_triangle_touch(const Vec3& p0, const Vec3& p1, const Vec3& a0, const Vec3& a1, const Vec3& b0,
                           const Vec3& b1, const Vec3& c0, const Vec3& c1) {
  Real roots[3];
  const int count = coplanarity_times(a0, b0, c0, p0, a1 - a0, b1 - b0, c1 - c0, p1 - p0, roots);
  for (int k = 0; k < count; ++k) {
    const Real t = roots[k];
    const Vec3 p = p0 + t * (p1 - p0);
    const Vec3 a = a0 + t * (a1 - a0);
    const Vec3 b = b0 + t * (b1 - b0);
    const Vec3 c = c0 + t * (c1 - c0);
    const Real tol = kSweptTolerance * extent(p, a, b, c);
    if ((closest_point_on_triangle(p, a, b, c).point - p).squaredNorm() <= tol * tol) return true;
  }
  return false;
}

// Do edges pq and rs (moving linearly) meet at some t ∈ [0, 1]?
bool edge_edge_touch(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, const Vec3& r0,
                     const Vec3& r1, const Vec3& s0, const Vec3& s1) {
  Real roots[3];
  const int count = coplanarity_times(p0, q0, r0, s0, p1 - p0, q1 - q0, r1 - r0, s1 - s0, roots);
  for (int k = 0; k < count; ++k) {
    const Real t = roots[k];
    const Vec3 p = p0 + t * (p1 - p0);
    const Vec3 q = q0 + t * (q1 - q0);
    const Vec3 r = r0 + t * (r1 - r0);
    const Vec3 s = s0 + t * (s1 - s0);
    const Real tol = kSweptTolerance * extent(p, q, r, s);
    if (closest_points_segment_segment(p, q, r, s).distance_squared <= tol * tol) return true;
  }
  return false;
}

Aabb swept_triangle_box(const SweptObject& o, const Triangle& tri) {
  Aabb box;
  for (const std::uint32_t v : tri) {
    box.expand(o.positions_start[v]);
    box.expand(o.positions_end[v]);
  }
  return box.inflated(1e-9 * box.size().maxCoeff());
}

void check_object(const SweptObject& o, const char* what) {
  if (o.positions_start.size() != o.positions_end.size()) {
    throw Error(std::string("swept_check: ") + what + " has " + std::to_string(o.positions_start.size()) +
                " start positions but " + std::to_string(o.positions_end.size()) + " end positions");
  }
  for (const Triangle& tri : o.triangles) {
    for (const std::uint32_t v : tri) {
      if (v >= o.positions_start.size()) {
        throw Error(std::string("swept_check: ") + what + " has a triangle index out of range");
      }
    }
  }
}

// A feature pair met by one triangle pair. kind 0: instrument vertex f1 vs tissue triangle f2;
// 1: tissue vertex f1 vs instrument triangle f2; 2: instrument edge f1 vs tissue edge f2 (edges
// as (min vertex << 32 | max vertex)).
struct FeaturePair {
  std::uint8_t kind;
  std::uint64_t f1;
  std::uint64_t f2;
};

// Per vertex of one object: bit f set when, at frame f (0 start, 1 end), the discrete detector
// reports a contact on a triangle of that object incident to the vertex.
void mark_contacts(const SweptObject& instrument, const SweptObject& tissue, std::vector<std::uint8_t>& seen_i,
                   std::vector<std::uint8_t>& seen_t) {
  seen_i.assign(instrument.positions_start.size(), 0);
  seen_t.assign(tissue.positions_start.size(), 0);
  CollisionDetector detector;
  for (int frame = 0; frame < 2; ++frame) {
    const CollisionObject objects[] = {
        {ObjectRole::kInstrument, frame == 0 ? instrument.positions_start : instrument.positions_end,
         instrument.triangles},
        {ObjectRole::kTissue, frame == 0 ? tissue.positions_start : tissue.positions_end, tissue.triangles}};
    const auto bit = static_cast<std::uint8_t>(1u << frame);
    for (const Contact& c : detector.detect(objects)) {
      for (const std::uint32_t v : instrument.triangles[c.triangle_a]) seen_i[v] |= bit;
      for (const std::uint32_t v : tissue.triangles[c.triangle_b]) seen_t[v] |= bit;
    }
  }
}

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

}  // namespace

int coplanarity_times(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3, const Vec3& v0,
                      const Vec3& v1, const Vec3& v2, const Vec3& v3, Real roots[3]) {
  // With a(t) = a0 + t·a1 (a = x1 − x0), b(t) = x2 − x0 moving, c(t) = x3 − x0 moving, the
  // triple product f(t) = (a × b)·c expands to the cubic
  //   f = a0×b0·c0 + t (a1×b0·c0 + a0×b1·c0 + a0×b0·c1)
  //         + t² (a1×b1·c0 + a1×b0·c1 + a0×b1·c1) + t³ a1×b1·c1        (Provot 1997).
  const Vec3 a0 = x1 - x0, b0 = x2 - x0, c0 = x3 - x0;
  const Vec3 a1 = v1 - v0, b1 = v2 - v0, c1 = v3 - v0;
  const Vec3 a0b0 = a0.cross(b0), a1b0 = a1.cross(b0), a0b1 = a0.cross(b1), a1b1 = a1.cross(b1);
  const Real c[4] = {a0b0.dot(c0), a1b0.dot(c0) + a0b1.dot(c0) + a0b0.dot(c1),
                     a1b1.dot(c0) + a1b0.dot(c1) + a0b1.dot(c1), a1b1.dot(c1)};
  // Scale for "zero": the size of the four points over the motion, cubed.
  Real scale = 0;
  for (const Vec3* x : {&a0, &b0, &c0}) scale = std::max(scale, x->norm());
  for (const Vec3* x : {&a1, &b1, &c1}) scale = std::max(scale, x->norm());
  const Real zero = 1e-14 * scale * scale * scale;
  if (std::abs(c[0]) <= zero && std::abs(c[1]) <= zero && std::abs(c[2]) <= zero && std::abs(c[3]) <= zero) {
    return 0;  // coplanar throughout: left to the edge–edge tests of the neighbouring features
  }
  // Split [0, 1] at the critical points (roots of f' = c1 + 2 c2 t + 3 c3 t²) into monotone
  // pieces; each piece holds at most one root, found by bisection where f changes sign.
  Real cuts[4] = {0, 0, 0, 1};
  int cut_count = 1;
  const Real qa = 3 * c[3], qb = 2 * c[2], qc = c[1];
  if (qa != 0) {
    const Real disc = qb * qb - 4 * qa * qc;
    if (disc >= 0) {
      const Real sq = std::sqrt(disc);
      // Numerically stable quadratic roots.
      const Real q = -0.5 * (qb + std::copysign(sq, qb));
      Real r1 = q / qa;
      Real r2 = q != 0 ? qc / q : r1;
      if (r1 > r2) std::swap(r1, r2);
      if (r1 > 0 && r1 < 1) cuts[cut_count++] = r1;
      if (r2 > 0 && r2 < 1 && r2 != r1) cuts[cut_count++] = r2;
    }
  } else if (qb != 0) {
    const Real r = -qc / qb;
    if (r > 0 && r < 1) cuts[cut_count++] = r;
  }
  cuts[cut_count++] = 1;
  int count = 0;
  for (int k = 0; k + 1 < cut_count; ++k) {
    const Real lo = cuts[k], hi = cuts[k + 1];
    const Real f_lo = cubic(c, lo), f_hi = cubic(c, hi);
    Real root = -1;
    if (std::abs(f_lo) <= zero) {
      root = lo;
    } else if (std::abs(f_hi) <= zero) {
      root = hi;
    } else if ((f_lo < 0) != (f_hi < 0)) {
      root = bisect(c, lo, hi);
    }
    if (root < 0) continue;
    if (count > 0 && root - roots[count - 1] <= 1e-12) continue;  // same root at a shared cut
    if (count < 3) roots[count++] = root;
  }
  return count;
}

SweptCheckResult swept_check(const SweptObject& instrument, const SweptObject& tissue) {
  check_object(instrument, "instrument");
  check_object(tissue, "tissue");
  SweptCheckResult result;
  if (instrument.triangles.empty() || tissue.triangles.empty()) return result;

  // Candidate triangle pairs: the instrument's swept boxes against a tree of the tissue's.
  std::vector<Aabb> tissue_boxes(tissue.triangles.size());
  for (std::size_t t = 0; t < tissue.triangles.size(); ++t) tissue_boxes[t] = swept_triangle_box(tissue, tissue.triangles[t]);
  const AabbTree tree(tissue_boxes);
  const auto nodes = tree.nodes();
  const auto items = tree.items();

  std::vector<FeaturePair> features;
  std::vector<std::uint32_t> stack;
  const auto& ip0 = instrument.positions_start;
  const auto& ip1 = instrument.positions_end;
  const auto& tp0 = tissue.positions_start;
  const auto& tp1 = tissue.positions_end;
  for (std::uint32_t ta = 0; ta < instrument.triangles.size(); ++ta) {
    const Triangle& A = instrument.triangles[ta];
    const Aabb box = swept_triangle_box(instrument, A);
    stack.assign(1, 0);
    while (!stack.empty()) {
      const AabbTree::Node& node = nodes[stack.back()];
      stack.pop_back();
      if (!node.box.overlaps(box)) continue;
      if (node.count == 0) {
        stack.push_back(node.first);
        stack.push_back(node.first + 1);
        continue;
      }
      for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
        const std::uint32_t tb = items[k];
        if (!tissue_boxes[tb].overlaps(box)) continue;
        ++result.triangle_pairs_tested;
        const Triangle& B = tissue.triangles[tb];
        for (int i = 0; i < 3; ++i) {
          features.push_back({0, A[i], tb});
          features.push_back({1, B[i], ta});
          for (int j = 0; j < 3; ++j) {
            features.push_back({2, edge_key(A[i], A[(i + 1) % 3]), edge_key(B[j], B[(j + 1) % 3])});
          }
        }
      }
    }
  }

  // One entry per feature pair (the same pair is met through several triangle pairs).
  std::sort(features.begin(), features.end(), [](const FeaturePair& x, const FeaturePair& y) {
    return std::tie(x.kind, x.f1, x.f2) < std::tie(y.kind, y.f1, y.f2);
  });
  features.erase(std::unique(features.begin(), features.end(),
                             [](const FeaturePair& x, const FeaturePair& y) {
                               return x.kind == y.kind && x.f1 == y.f1 && x.f2 == y.f2;
                             }),
                 features.end());
  std::vector<std::uint8_t> seen_i;
  std::vector<std::uint8_t> seen_t;
  mark_contacts(instrument, tissue, seen_i, seen_t);
  // The frames (bits) at which the discrete test saw a contact around each feature.
  const auto around = [](const std::vector<std::uint8_t>& seen, std::initializer_list<std::uint32_t> vertices) {
    std::uint8_t bits = 0;
    for (const std::uint32_t v : vertices) bits |= seen[v];
    return bits;
  };
  for (std::size_t k = 0; k < features.size(); ++k) {
    const FeaturePair& f = features[k];
    bool touch = false;
    std::uint8_t seen_instrument = 0;
    std::uint8_t seen_tissue = 0;
    if (f.kind == 0) {
      const auto v = static_cast<std::uint32_t>(f.f1);
      const Triangle& B = tissue.triangles[f.f2];
      seen_instrument = around(seen_i, {v});
      seen_tissue = around(seen_t, {B[0], B[1], B[2]});
      touch = vertex_triangle_touch(ip0[v], ip1[v], tp0[B[0]], tp1[B[0]], tp0[B[1]], tp1[B[1]], tp0[B[2]], tp1[B[2]]);
    } else if (f.kind == 1) {
      const auto v = static_cast<std::uint32_t>(f.f1);
      const Triangle& A = instrument.triangles[f.f2];
      seen_instrument = around(seen_i, {A[0], A[1], A[2]});
      seen_tissue = around(seen_t, {v});
      touch = vertex_triangle_touch(tp0[v], tp1[v], ip0[A[0]], ip1[A[0]], ip0[A[1]], ip1[A[1]], ip0[A[2]], ip1[A[2]]);
    } else {
      const auto a = static_cast<std::uint32_t>(f.f1 >> 32), b = static_cast<std::uint32_t>(f.f1 & 0xffffffffu);
      const auto c = static_cast<std::uint32_t>(f.f2 >> 32), d = static_cast<std::uint32_t>(f.f2 & 0xffffffffu);
      seen_instrument = around(seen_i, {a, b});
      seen_tissue = around(seen_t, {c, d});
      touch = edge_edge_touch(ip0[a], ip1[a], ip0[b], ip1[b], tp0[c], tp1[c], tp0[d], tp1[d]);
    }
    // Seen when at one frame the discrete detector reports contacts on the tissue around the
    // tissue's feature (the instrument side is not required: a tool tip pushed deeper than its
    // first ring of triangles touches the tissue only through triangles not incident to the tip).
    (void)seen_instrument;
    const bool detected = seen_tissue != 0;
    if (touch) {
      if (f.kind == 2) {
        ++result.edge_edge_events;
        if (!detected) ++result.missed_edge_edge;
      } else {
        ++result.vertex_triangle_events;
        if (!detected) ++result.missed_vertex_triangle;
      }
    }
  }
  return result;
}

}  // namespace trocar
