// Tissue against tissue (docs/response.md, "Tissue against tissue"): vertex–triangle proximity
// with a gap, side memory against tunnelling, inverse-mass-weighted Gauss–Seidel projection, a
// velocity pass with Coulomb friction, and XPBD attachments that tear above their pull-out force.
#include "trocar/response/tissue_contact.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "trocar/geometry/barycentric.h"
#include "trocar/geometry/closest_point.h"
#include "trocar/geometry/segment_triangle.h"
#include "trocar/mesh/topology.h"

namespace trocar {
namespace {

constexpr std::uint32_t kNoTriangle = std::numeric_limits<std::uint32_t>::max();

/// Gauss–Seidel sweeps over the contacts and attachments per step: the mesh-on-wall test
/// (tests/response/tissue_contact_test.cpp) meets its 0.5 mm p99 with 4; more cost linearly.
constexpr int kIterations = 4;

/// Rounds of untangle() before it puts the whole tissue back.
constexpr int kMaxRewinds = 8;

/// Coupled: a tack stretched further than its own length (m) has come out (helical titanium tacks
/// are about 4 mm long; assumed).
constexpr Real kTackLength = 0.004;

Vec3 component_min(const Vec3& a, const Vec3& b) { return a.cwiseMin(b); }
Vec3 component_max(const Vec3& a, const Vec3& b) { return a.cwiseMax(b); }

/// Mean extent of the triangles' boxes at rest: the grid's cell edge (about one triangle per
/// cell).
Real mean_triangle_extent(const MassSpringSettings& s) {
  if (s.triangles.empty()) return 1e-3;
  Real sum = 0;
  for (const Triangle& t : s.triangles) {
    const Vec3& a = s.rest_positions[t[0]];
    const Vec3& b = s.rest_positions[t[1]];
    const Vec3& c = s.rest_positions[t[2]];
    sum += (component_max(component_max(a, b), c) - component_min(component_min(a, b), c)).maxCoeff();
  }
  return std::max(sum / static_cast<Real>(s.triangles.size()), 1e-6);
}

/// Which side of segment ij's line segment kl's line lies on, as the sign of (x_j − x_i) × (x_l −
/// x_k) · (x_k − x_i), where the segments' closest points `q` lie strictly inside both and the
/// segments are not near parallel (the angle between them over about 3°); else 0 (the sides of
/// two lines say nothing about crossing beyond the segments' ends, and parallel lines have none).
Real edge_side(const Vec3& xi, const Vec3& xj, const Vec3& xk, const Vec3& xl, const SegmentSegmentClosest& q) {
  constexpr Real kInside = 1e-3, kSinParallel = 0.05;
  if (!(q.s > kInside && q.s < 1 - kInside && q.t > kInside && q.t < 1 - kInside)) return 0;
  const Vec3 e = xj - xi, f = xl - xk;
  const Vec3 n = e.cross(f);
  const Real nn = n.norm();
  if (!(nn > kSinParallel * e.norm() * f.norm())) return 0;
  const Real g = n.dot(xk - xi);
  return g > 0 ? 1 : g < 0 ? -1 : 0;
}

/// Positions and velocities as the tissues' states hold them (after the integrators).
struct StateAccess {
  std::span<const ContactTissue> tissues;
  Vec3 x(std::uint32_t t, std::uint32_t v) const { return tissues[t].state->positions[v]; }
  void move(std::uint32_t t, std::uint32_t v, const Vec3& d) const { tissues[t].state->positions[v] += d; }
  Vec3 u(std::uint32_t t, std::uint32_t v) const { return tissues[t].state->velocities[v]; }
  void push(std::uint32_t t, std::uint32_t v, const Vec3& d) const { tissues[t].state->velocities[v] += d; }
};

/// The same, as the coupled solvers hold them inside their substeps (float particles), per tissue.
struct ParticleAccess {
  std::span<const std::span<XpbdParticle>> positions, velocities;
  Vec3 x(std::uint32_t t, std::uint32_t v) const {
    const XpbdParticle& p = positions[t][v];
    return Vec3(p.x, p.y, p.z);
  }
  void move(std::uint32_t t, std::uint32_t v, const Vec3& d) const { add(positions[t][v], d); }
  Vec3 u(std::uint32_t t, std::uint32_t v) const {
    const XpbdParticle& p = velocities[t][v];
    return Vec3(p.x, p.y, p.z);
  }
  void push(std::uint32_t t, std::uint32_t v, const Vec3& d) const { add(velocities[t][v], d); }
  static void add(XpbdParticle& p, const Vec3& d) {
    p.x = static_cast<float>(p.x + d.x());
    p.y = static_cast<float>(p.y + d.y());
    p.z = static_cast<float>(p.z + d.z());
  }
};

}  // namespace

TissueContactSolver::TissueContactSolver(std::vector<ContactTissue> tissues, std::vector<TissueContactPair> pairs,
                                         std::size_t attachment_capacity)
    : tissues_(std::move(tissues)), pairs_(std::move(pairs)), capacity_(attachment_capacity) {
  attachments_.reserve(capacity_);
  lambda_.reserve(capacity_);
  body_of_.assign(tissues_.size(), -1);
  for (const TissueContactPair& p : pairs_)
    for (const std::size_t t : {p.a, p.b}) {
      if (t >= tissues_.size()) continue;  // the scene reader rejects these; a program may not
      if (body_of_[t] < 0) {
        body_of_[t] = static_cast<std::int32_t>(bodies_.size());
        bodies_.emplace_back();
        bodies_.back().tissue = static_cast<std::uint32_t>(t);
      }
      Body& body = bodies_[static_cast<std::size_t>(body_of_[t])];
      body.reach = std::max(body.reach, p.thickness + (p.adhesion > 0 ? p.adhesion_range : 0));
      body.self = body.self || p.a == p.b;
    }
  std::size_t vertices = 0;
  for (Body& body : bodies_) {
    const MassSpringSettings& s = *tissues_[body.tissue].settings;
    if (s.closed) body.side = s.rest_volume >= 0 ? 1 : -1;
    body.start.resize(s.vertex_count());
    body.lo.resize(s.triangles.size());
    body.hi.resize(s.triangles.size());
    body.motion.resize(s.vertex_count());
    set_adjacency(body);
    body.grid.reset(s.triangles.size(), mean_triangle_extent(s) + 2 * body.reach);
    vertices += s.vertex_count();
  }
  candidates_.reserve(4 * vertices);
  edge_candidates_.reserve(4 * self_edges());
  coupled_.assign(tissues_.size(), nullptr);
  coupled_x_.resize(tissues_.size());
  coupled_v_.resize(tissues_.size());
  coupled_force_.reserve(capacity_);
}

TissueContactSolver::~TissueContactSolver() = default;

void TissueContactSolver::remodel(std::size_t t, const ContactTissue& tissue,
                                  std::span<const std::uint32_t> triangle_origin, std::size_t old_triangle_count,
                                  Real time) {
  if (t >= tissues_.size()) return;
  tissues_[t] = tissue;
  std::vector<std::uint32_t> renumbered(old_triangle_count, std::numeric_limits<std::uint32_t>::max());
  for (std::uint32_t k = 0; k < triangle_origin.size(); ++k) renumbered[triangle_origin[k]] = k;
  for (AttachmentState& a : attachments_)
    for (SurfacePoint* p : {&a.spec.a, &a.spec.b}) {
      if (p->tissue != t) continue;
      const std::uint32_t now = p->triangle < renumbered.size() ? renumbered[p->triangle]
                                                                 : std::numeric_limits<std::uint32_t>::max();
      if (now != std::numeric_limits<std::uint32_t>::max()) {
        p->triangle = now;
      } else if (a.holding) {
        a.holding = false;  // its tissue was cut away under it
        a.torn_at = time;
        a.force = 0;
      }
    }
  if (body_of_[t] < 0) return;
  Body& body = bodies_[static_cast<std::size_t>(body_of_[t])];
  const MassSpringSettings& s = *tissue.settings;
  body.side = s.closed ? (s.rest_volume >= 0 ? 1 : -1) : 0;
  body.start = tissue.state->positions;
  body.lo.resize(s.triangles.size());
  body.hi.resize(s.triangles.size());
  body.motion.resize(s.vertex_count());
  set_adjacency(body);
  body.grid.reset(s.triangles.size(), mean_triangle_extent(s) + 2 * body.reach);
  std::size_t vertices = 0;
  for (const Body& b : bodies_) vertices += tissues_[b.tissue].settings->vertex_count();
  candidates_.reserve(4 * vertices);
  edge_candidates_.reserve(4 * self_edges());
}

std::size_t TissueContactSolver::self_edges() const {
  std::size_t n = 0;
  for (const TissueContactPair& p : pairs_)
    if (p.a == p.b && p.a < tissues_.size() && body_of_[p.a] >= 0)
      n += bodies_[static_cast<std::size_t>(body_of_[p.a])].edges.size();
  return n;
}

void TissueContactSolver::set_adjacency(Body& body) {
  const MassSpringSettings& s = *tissues_[body.tissue].settings;
  TriMesh mesh;
  mesh.positions = s.rest_positions;
  mesh.triangles = s.triangles;
  const MeshTopology topology(mesh);
  body.border = SheetBoundary(topology);
  body.across.assign(s.triangles.size(), {kNoTriangle, kNoTriangle, kNoTriangle});
  body.edges.clear();
  for (const Edge& e : topology.edges()) body.edges.push_back({e.v0, e.v1});
  body.edge_seen.assign(body.edges.size(), 0);
  body.rewind.assign(s.vertex_count(), 0);
  body.triangle_edges.resize(s.triangles.size());
  for (std::uint32_t t = 0; t < s.triangles.size(); ++t) body.triangle_edges[t] = topology.triangle_edges(t);
  for (std::uint32_t t = 0; t < s.triangles.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t e = topology.triangle_edges(t)[k];
      if (e == MeshTopology::kNone || topology.edge_valence(e) != 2) continue;
      const std::span<const std::uint32_t> two = topology.edge_triangles(e);
      body.across[t][k] = two[0] == t ? two[1] : two[0];
    }
}

void TissueContactSolver::begin_step() {
  for (Body& body : bodies_) {
    const std::vector<Vec3>& x = tissues_[body.tissue].state->positions;
    std::copy(x.begin(), x.end(), body.start.begin());
  }
}

void TissueContactSolver::gather(const TissueContactPair& pair, Body& vb, Body& tb, bool self, bool predicted) {
  const MassSpringSettings& vs = *tissues_[vb.tissue].settings;
  const MassSpringSettings& ts = *tissues_[tb.tissue].settings;
  const std::vector<Vec3>& x = tissues_[vb.tissue].state->positions;
  const std::vector<Vec3>& y = tissues_[tb.tissue].state->positions;
  for (std::uint32_t v = 0; v < x.size(); ++v) {
    const Vec3& p0 = vb.start[v];
    const Vec3& p = x[v];
    // Where the vertex may go this step: from its start to its end, or (coupled, before the
    // step is solved) anywhere within its motion bound of its start.
    const Real vertex_motion = predicted ? vb.motion[v] : (p - p0).norm();
    const bool vertex_fixed = vs.inverse_masses[v] == 0;
    const Vec3 lo = predicted ? Vec3(p0.array() - vertex_motion) : component_min(p0, p);
    const Vec3 hi = predicted ? Vec3(p0.array() + vertex_motion) : component_max(p0, p);
    tb.grid.query(lo, hi, [&](std::uint32_t t) {
      const Triangle& tri = ts.triangles[t];
      if (self && (tri[0] == v || tri[1] == v || tri[2] == v)) return;
      if (vertex_fixed && ts.inverse_masses[tri[0]] == 0 && ts.inverse_masses[tri[1]] == 0 &&
          ts.inverse_masses[tri[2]] == 0)
        return;
      // The box test the hash may have skipped (buckets are shared by distant cells).
      if ((lo.array() > tb.hi[t].array()).any() || (hi.array() < tb.lo[t].array()).any()) return;
      const Vec3 &a0 = tb.start[tri[0]], &b0 = tb.start[tri[1]], &c0 = tb.start[tri[2]];
      const Vec3 &a = y[tri[0]], &b = y[tri[1]], &c = y[tri[2]];
      // The side the vertex must end on: outside a closed tissue; for an open one the side of
      // the triangle's plane it started on (a vertex can reach the triangle's other side only
      // through its plane, so the start plane is the right reference even when the vertex
      // approached from beyond an edge).
      Real side = tb.side;
      if (side == 0) {
        const Real s0 = (b0 - a0).cross(c0 - a0).dot(p0 - a0);
        const Real s1 = (b - a).cross(c - a).dot(p - a);
        side = s0 > 0 ? 1 : s0 < 0 ? -1 : (s1 >= 0 ? 1 : -1);
      }
      const Real triangle_motion =
          predicted ? std::max({tb.motion[tri[0]], tb.motion[tri[1]], tb.motion[tri[2]]})
                    : std::max({(a - a0).norm(), (b - b0).norm(), (c - c0).norm()});
      Candidate c_{};
      c_.vertex_tissue = vb.tissue;
      c_.vertex = v;
      c_.triangle_tissue = tb.tissue;
      c_.triangle = t;
      c_.side = side;
      c_.thickness = pair.thickness;
      c_.friction = pair.friction;
      c_.reach = pair.thickness + vertex_motion + triangle_motion + 0.5 * pair.thickness;
      c_.direction = Vec3::Zero();
      c_.bary = Vec3::Zero();
      c_.touching = false;
      c_.adhered = false;
      c_.adhesion = pair.adhesion;
      c_.adhesion_range = pair.adhesion_range;
      c_.corrected = false;
      candidates_.push_back(c_);
    });
  }
}

void TissueContactSolver::gather_edges(const TissueContactPair& pair, Body& body, bool predicted) {
  const MassSpringSettings& s = *tissues_[body.tissue].settings;
  const std::vector<Vec3>& x = tissues_[body.tissue].state->positions;
  const std::vector<Vec3>& x0 = body.start;
  const auto motion = [&](std::uint32_t v) { return predicted ? body.motion[v] : (x[v] - x0[v]).norm(); };
  const auto fixed = [&](std::uint32_t v) { return s.inverse_masses[v] == 0; };
  for (std::uint32_t e = 0; e < body.edges.size(); ++e) {
    const std::uint32_t i = body.edges[e][0], j = body.edges[e][1];
    const Real edge_motion = std::max(motion(i), motion(j));
    // Where it may be this step: from its start to its end, or (coupled) anywhere within its
    // motion bound of its start.
    Vec3 lo = component_min(x0[i], x0[j]), hi = component_max(x0[i], x0[j]);
    if (predicted) {
      lo.array() -= edge_motion;
      hi.array() += edge_motion;
    } else {
      lo = component_min(lo, component_min(x[i], x[j]));
      hi = component_max(hi, component_max(x[i], x[j]));
    }
    const std::uint64_t round = ++edge_round_;
    body.grid.query(lo, hi, [&](std::uint32_t t) {
      if ((lo.array() > body.hi[t].array()).any() || (hi.array() < body.lo[t].array()).any()) return;
      for (const std::uint32_t f : body.triangle_edges[t]) {
        // Each unordered pair once (f > e), each f once per e.
        if (f == MeshTopology::kNone || f <= e || body.edge_seen[f] == round) continue;
        body.edge_seen[f] = round;
        const std::uint32_t k = body.edges[f][0], l = body.edges[f][1];
        if (k == i || k == j || l == i || l == j) continue;  // they share a vertex: never apart
        if (fixed(i) && fixed(j) && fixed(k) && fixed(l)) continue;
        const Real edge_reach = pair.thickness + edge_motion + std::max(motion(k), motion(l));
        const SegmentSegmentClosest start = closest_points_segment_segment(x0[i], x0[j], x0[k], x0[l]);
        if (start.distance_squared > edge_reach * edge_reach) continue;  // cannot come within the gap
        EdgeCandidate c{};
        c.tissue = body.tissue;
        c.e = e;
        c.f = f;
        c.sigma = edge_side(x0[i], x0[j], x0[k], x0[l], start);
        c.thickness = pair.thickness;
        c.friction = pair.friction;
        c.reach = edge_reach + 0.5 * pair.thickness;
        c.direction = Vec3::Zero();
        edge_candidates_.push_back(c);
      }
    });
  }
}

template <typename Access>
void TissueContactSolver::project_edges(EdgeCandidate& c, Access& access) {
  const Body& body = bodies_[static_cast<std::size_t>(body_of_[c.tissue])];
  const MassSpringSettings& s = *tissues_[c.tissue].settings;
  const std::uint32_t i = body.edges[c.e][0], j = body.edges[c.e][1], k = body.edges[c.f][0], l = body.edges[c.f][1];
  const Vec3 xi = access.x(c.tissue, i), xj = access.x(c.tissue, j), xk = access.x(c.tissue, k),
             xl = access.x(c.tissue, l);
  const SegmentSegmentClosest q = closest_points_segment_segment(xi, xj, xk, xl);
  const Vec3 d = q.on_q - q.on_p;
  Real distance = std::sqrt(q.distance_squared);
  Vec3 direction;
  const Real now = edge_side(xi, xj, xk, xl, q);
  if (c.sigma != 0 && now != 0 && now != c.sigma) {
    // Crossed: f's segment went through e's within the step (both closest points inside both
    // segments, the lines' sides swapped). Back to the side it started on, along e × f.
    direction = c.sigma * (xj - xi).cross(xl - xk).normalized();
    distance = direction.dot(d);  // ≤ 0: how far past
  } else {
    if (!(distance > 0)) return;  // touching, no direction to part them: the faces' contacts do
    direction = d / distance;
  }
  const Real violation = c.thickness - distance;
  if (violation <= 0) return;
  Real reach = c.reach;
  if (coupled_[c.tissue] != nullptr) {  // the motion so far, as project_contact
    reach = 1.5 * c.thickness +
            std::max((xi - body.start[i]).norm(), (xj - body.start[j]).norm()) +
            std::max((xk - body.start[k]).norm(), (xl - body.start[l]).norm());
  }
  if (violation > reach) return;
  const Real wi = s.inverse_masses[i], wj = s.inverse_masses[j], wk = s.inverse_masses[k], wl = s.inverse_masses[l];
  const Real a = 1 - q.s, b = q.s, g = 1 - q.t, h = q.t;
  const Real w = a * a * wi + b * b * wj + g * g * wk + h * h * wl;
  if (!(w > 0)) return;
  const Real lambda = violation / w;
  // e's side moves against the direction, f's along it, each in proportion to its weight on the
  // closest point and its inverse mass (the four vertices are distinct).
  access.move(c.tissue, i, -a * wi * lambda * direction);
  access.move(c.tissue, j, -b * wj * lambda * direction);
  access.move(c.tissue, k, g * wk * lambda * direction);
  access.move(c.tissue, l, h * wl * lambda * direction);
  c.direction = direction;
  c.s = q.s;
  c.t = q.t;
  c.touching = true;
  c.corrected = true;
}

template <typename Access>
void TissueContactSolver::edge_velocities(const EdgeCandidate& c, Access& access) {
  const Body& body = bodies_[static_cast<std::size_t>(body_of_[c.tissue])];
  const MassSpringSettings& s = *tissues_[c.tissue].settings;
  const std::uint32_t i = body.edges[c.e][0], j = body.edges[c.e][1], k = body.edges[c.f][0], l = body.edges[c.f][1];
  const Real wi = s.inverse_masses[i], wj = s.inverse_masses[j], wk = s.inverse_masses[k], wl = s.inverse_masses[l];
  const Real a = 1 - c.s, b = c.s, g = 1 - c.t, h = c.t;
  const Real w = a * a * wi + b * b * wj + g * g * wk + h * h * wl;
  if (!(w > 0)) return;
  const Vec3 relative = g * access.u(c.tissue, k) + h * access.u(c.tissue, l) - a * access.u(c.tissue, i) -
                        b * access.u(c.tissue, j);
  const Real normal = c.direction.dot(relative);  // > 0: separating
  if (normal >= 0) return;
  // Inelastic, with Coulomb friction up to μ times the normal change (as contact_velocities).
  const Vec3 tangential = relative - normal * c.direction;
  const Real slip = tangential.norm();
  Vec3 change = -normal * c.direction;
  if (slip > 0) change -= std::min(slip, c.friction * -normal) * (tangential / slip);
  const Vec3 impulse = change / w;
  access.push(c.tissue, i, -a * wi * impulse);
  access.push(c.tissue, j, -b * wj * impulse);
  access.push(c.tissue, k, g * wk * impulse);
  access.push(c.tissue, l, h * wl * impulse);
}

template <typename Access>
void TissueContactSolver::project_contact(Candidate& c, Access& access) {
  const MassSpringSettings& vs = *tissues_[c.vertex_tissue].settings;
  const MassSpringSettings& ts = *tissues_[c.triangle_tissue].settings;
  const Triangle& tri = ts.triangles[c.triangle];
  const std::uint32_t vt = c.vertex_tissue, tt = c.triangle_tissue;
  const Vec3 p = access.x(vt, c.vertex);
  const Vec3 a = access.x(tt, tri[0]), b = access.x(tt, tri[1]), cc = access.x(tt, tri[2]);
  c.adhered = false;
  const Vec3 normal_area = (b - a).cross(cc - a);
  const Real area2 = normal_area.norm();
  if (!(area2 > 0)) return;
  const Vec3 n = normal_area / area2;
  // On the remembered side and beyond the gap from the plane, the vertex is beyond it from every
  // point of the triangle too: only adhesion can act, and only over the face (below). The face
  // test by barycentric coordinates is the closest-point query's kFace case without its edges
  // (the query was a third of the coupled step).
  const Real height = c.side * n.dot(p - a);
  if (height > c.thickness) {
    if (!(c.adhesion > 0) || height - c.thickness > c.adhesion_range) return;
    const Vec3 bary = barycentric(p, a, b, cc);
    if ((bary.array() < 0).any()) return;  // beyond an edge: nothing to cling to
    c.adhered = true;
    c.excess = height - c.thickness;
    c.direction = c.side * n;
    c.bary = bary;
    return;
  }
  const TriangleClosestPoint q = closest_point_on_triangle(p, a, b, cc);
  Vec3 direction;
  Real distance;
  if (q.feature == TriangleFeature::kFace) {
    // Within the triangle's projection: the plane separates, on the remembered side.
    direction = c.side * n;
    distance = direction.dot(p - a);
  } else {
    // Beyond an edge or a corner: keep the gap to the nearest feature, on the remembered side
    // of the plane (a vertex that went through a crease between two triangles ends beyond both
    // of their edges; without the side it would be pushed on through), but only where the
    // plane's side still says the vertex crossed (crossed_beyond): otherwise the correction
    // pulls it back around the edge by the gap plus its distance.
    const Vec3 d = p - q.point;
    distance = d.norm();
    if (distance == 0) return;
    direction = d / distance;
    if (c.side * n.dot(d) < 0 && crossed_beyond(c, q, p, n, d, access)) {
      direction = -direction;
      distance = -distance;
    }
  }
  const Real violation = c.thickness - distance;
  if (violation <= 0) {
    // Beyond the gap: held by adhesion when within its range (velocities only, after the sweeps),
    // by the face beneath the vertex only. Beyond an edge there is no surface to cling to (an open
    // sheet's rim would pull a cloth laid over its hole sideways toward the rim from all around),
    // and a vertex over a face is held once, not once for each triangle around it.
    if (c.adhesion > 0 && -violation <= c.adhesion_range && q.feature == TriangleFeature::kFace) {
      c.adhered = true;
      c.excess = -violation;
      c.direction = direction;
      c.bary = q.barycentric;
    }
    return;
  }
  // Deeper than this step's motion explains: not this triangle's. Coupled, the motion so far
  // (the gather's bound only says how far it may go).
  Real reach = c.reach;
  if (coupled_[vt] != nullptr) {
    const Body& vb = bodies_[static_cast<std::size_t>(body_of_[vt])];
    const Body& tb = bodies_[static_cast<std::size_t>(body_of_[tt])];
    reach = 1.5 * c.thickness + (p - vb.start[c.vertex]).norm() +
            std::max({(a - tb.start[tri[0]]).norm(), (b - tb.start[tri[1]]).norm(), (cc - tb.start[tri[2]]).norm()});
  }
  if (violation > reach) return;
  c.touching = true;
  c.direction = direction;
  c.bary = q.barycentric;
  const Real wp = vs.inverse_masses[c.vertex];
  const Real w0 = ts.inverse_masses[tri[0]], w1 = ts.inverse_masses[tri[1]], w2 = ts.inverse_masses[tri[2]];
  const Real w = wp + c.bary[0] * c.bary[0] * w0 + c.bary[1] * c.bary[1] * w1 + c.bary[2] * c.bary[2] * w2;
  if (!(w > 0)) return;
  const Real lambda = violation / w;
  // Same vertex in both roles cannot happen (incident triangles are skipped), so these
  // references never alias one another's written values within the update.
  access.move(vt, c.vertex, wp * lambda * direction);
  access.move(tt, tri[0], -c.bary[0] * w0 * lambda * direction);
  access.move(tt, tri[1], -c.bary[1] * w1 * lambda * direction);
  access.move(tt, tri[2], -c.bary[2] * w2 * lambda * direction);
  c.corrected = true;
}

template <typename Access>
bool TissueContactSolver::crossed_beyond(const Candidate& c, const TriangleClosestPoint& q, const Vec3& p,
                                         const Vec3& n, const Vec3& d, Access& access) const {
  const Body& tb = bodies_[static_cast<std::size_t>(body_of_[c.triangle_tissue])];
  const Triangle& tri = tissues_[c.triangle_tissue].settings->triangles[c.triangle];
  // On the sheet's border a point passes from one side of the plane to the other around the
  // edge without crossing anything.
  if (tb.border.on_boundary(c.triangle, tri, q.feature, q.index)) return false;
  if (q.feature == TriangleFeature::kVertex) {
    // Beyond a corner the other triangles around it decide; this one only within the gap (a
    // vertex through the surface at one of its vertices), so the correction stays under two gaps.
    return d.norm() < c.thickness;
  }
  const std::uint32_t other = tb.across[c.triangle][static_cast<std::size_t>(q.index)];
  if (other == kNoTriangle) return false;  // a non-manifold edge: no side to keep
  const Triangle& o = tissues_[c.triangle_tissue].settings->triangles[other];
  const Vec3 a = access.x(c.triangle_tissue, o[0]), b = access.x(c.triangle_tissue, o[1]),
             cc = access.x(c.triangle_tissue, o[2]);
  // Over the neighbour's face the neighbour decides: beside a fold a point over one face lies
  // beyond its neighbour's plane without having crossed anything (a wall vertex 1.6 mm beyond a
  // fold of the novice's falling mesh was pulled 2.6 mm through it in one substep).
  if ((barycentric(p, a, b, cc).array() >= 0).all()) return false;
  // Beyond both triangles: the edge's pseudonormal decides (Bærentzen & Aanæs 2005), so a
  // vertex that went through the fold line between two triangles is pushed back, not on through.
  const Vec3 other_normal = (b - a).cross(cc - a);
  const Real length = other_normal.norm();
  if (!(length > 0)) return true;
  return c.side * (n + other_normal / length).dot(d) < 0;
}

template <typename Access>
void TissueContactSolver::contact_velocities(const Candidate& c, Real dt, Access& access) {
  const std::uint32_t vt = c.vertex_tissue, tt = c.triangle_tissue;
  const MassSpringSettings& vs = *tissues_[c.vertex_tissue].settings;
  const MassSpringSettings& ts = *tissues_[c.triangle_tissue].settings;
  const Triangle& tri = ts.triangles[c.triangle];
  const Real wp = vs.inverse_masses[c.vertex];
  const Real wt[3] = {ts.inverse_masses[tri[0]], ts.inverse_masses[tri[1]], ts.inverse_masses[tri[2]]};
  const Real w = wp + c.bary[0] * c.bary[0] * wt[0] + c.bary[1] * c.bary[1] * wt[1] + c.bary[2] * c.bary[2] * wt[2];
  if (!(w > 0)) return;
  const Vec3 relative = access.u(vt, c.vertex) - c.bary[0] * access.u(tt, tri[0]) - c.bary[1] * access.u(tt, tri[1]) -
                        c.bary[2] * access.u(tt, tri[2]);
  const Real normal = c.direction.dot(relative);  // > 0: separating
  const Vec3 tangential = relative - normal * c.direction;
  const Real slip = tangential.norm();
  Vec3 change;
  if (c.touching) {
    if (normal >= 0) return;  // separating already
    // Inelastic: the normal relative velocity goes to zero; Coulomb friction takes up to μ times
    // that change off the tangential relative velocity.
    change = -normal * c.direction;
    if (slip > 0) change -= std::min(slip, c.friction * -normal) * (tangential / slip);
  } else {
    // Adhered: the position returns toward the gap by at most adhesion·dt² (what gravity moved it
    // away this step, when adhesion exceeds gravity), never past the gap. The separating speed
    // loses at most adhesion·dt per step (a force of at most m·adhesion on the vertex), so a
    // light wet mesh stays where it was laid and a grasper that lifts it peels it off; the pull
    // presses it as a normal force would, so Coulomb friction takes up to μ·adhesion·dt off its
    // sliding speed (it does not slide down a tilted wall).
    const Real pull = std::min(c.excess, c.adhesion * dt * dt) / w;
    access.move(vt, c.vertex, -wp * pull * c.direction);
    for (int k = 0; k < 3; ++k) access.move(tt, tri[k], c.bary[k] * wt[k] * pull * c.direction);
    change = -std::clamp(normal, Real{0}, c.adhesion * dt) * c.direction;
    if (slip > 0) change -= std::min(slip, c.friction * c.adhesion * dt) * (tangential / slip);
  }
  const Vec3 impulse = change / w;  // per unit of w: Δv_p = w_p·impulse, Δv_i = −β_i w_i·impulse
  access.push(vt, c.vertex, wp * impulse);
  for (int k = 0; k < 3; ++k) access.push(tt, tri[k], -c.bary[k] * wt[k] * impulse);
}

template <typename Access>
bool TissueContactSolver::project_attachment(std::size_t i, Real alpha, Real dt, Access& access, bool move_velocities,
                                             Real stretch_limit) {
  const AttachmentSpec& s = attachments_[i].spec;
  const MassSpringSettings& ma = *tissues_[s.a.tissue].settings;
  const MassSpringSettings& mb = *tissues_[s.b.tissue].settings;
  const Triangle& ta = ma.triangles[s.a.triangle];
  const Triangle& tb = mb.triangles[s.b.triangle];
  Real w = alpha;
  for (int k = 0; k < 3; ++k)
    w += s.a.bary[k] * s.a.bary[k] * ma.inverse_masses[ta[k]] + s.b.bary[k] * s.b.bary[k] * mb.inverse_masses[tb[k]];
  if (!(w > 0)) return true;
  // XPBD (Macklin, Müller & Chentanez 2016, eq. 18) for the vector constraint
  // C = x_a − (x_b + F_b·offset), F_b b's triangle frame (taken as constant within the step):
  // Δλ = −(C + α̃λ)/(w̃ + α̃), α̃ = compliance/dt².
  const std::uint32_t at = s.a.tissue, bt = s.b.tissue;
  Vec3 xa = Vec3::Zero(), xb = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    xa += s.a.bary[k] * access.x(at, ta[k]);
    xb += s.b.bary[k] * access.x(bt, tb[k]);
  }
  Vec3 constraint = xa - xb;
  if (!s.offset.isZero()) {
    // b's triangle frame from the positions the access holds.
    constraint -= triangle_frame(access.x(bt, tb[0]), access.x(bt, tb[1]), access.x(bt, tb[2])) * s.offset;
  }
  const Real stretch = constraint.norm();
  if (stretch > stretch_limit) return false;  // torn: nothing moves
  const Vec3 delta = -(constraint + alpha * lambda_[i]) / w;
  lambda_[i] += delta;
  // After the integrators the move also enters the velocities (as XPBD's v = Δx/dt): otherwise a
  // pulled vertex keeps the velocity the pull gave it and the constraint's force climbs step
  // after step. Coupled, the substep's v = Δx/h does it.
  for (int k = 0; k < 3; ++k) {
    const Vec3 da = s.a.bary[k] * ma.inverse_masses[ta[k]] * delta;
    const Vec3 db = s.b.bary[k] * mb.inverse_masses[tb[k]] * delta;
    access.move(at, ta[k], da);
    access.move(bt, tb[k], -db);
    if (move_velocities) {
      access.push(at, ta[k], da / dt);
      access.push(bt, tb[k], -db / dt);
    }
  }
  return true;
}

void TissueContactSolver::solve(Real dt, Real time) {
  corrected_ = 0;
  if (bodies_.empty() && attachments_.empty()) return;  // nothing to do: no work at all
  candidates_.clear();
  edge_candidates_.clear();
  for (Body& body : bodies_) {
    const MassSpringSettings& s = *tissues_[body.tissue].settings;
    const std::vector<Vec3>& x = tissues_[body.tissue].state->positions;
    const Vec3 pad = Vec3::Constant(body.reach);
    for (std::size_t t = 0; t < s.triangles.size(); ++t) {
      const Triangle& tri = s.triangles[t];
      Vec3 lo = component_min(x[tri[0]], body.start[tri[0]]), hi = component_max(x[tri[0]], body.start[tri[0]]);
      for (int k = 1; k < 3; ++k) {
        lo = component_min(lo, component_min(x[tri[k]], body.start[tri[k]]));
        hi = component_max(hi, component_max(x[tri[k]], body.start[tri[k]]));
      }
      body.lo[t] = lo - pad;
      body.hi[t] = hi + pad;
    }
    body.grid.build(body.lo, body.hi);
  }
  for (const TissueContactPair& pair : pairs_) {
    if (pair.a >= tissues_.size() || pair.b >= tissues_.size()) continue;
    Body& a = bodies_[static_cast<std::size_t>(body_of_[pair.a])];
    Body& b = bodies_[static_cast<std::size_t>(body_of_[pair.b])];
    gather(pair, a, b, pair.a == pair.b, false);
    if (pair.a != pair.b) gather(pair, b, a, false, false);
    if (pair.a == pair.b) gather_edges(pair, a, false);
  }

  StateAccess access{tissues_};
  const Real alpha_scale = 1 / (dt * dt);
  for (std::size_t i = 0; i < attachments_.size(); ++i) lambda_[i] = Vec3::Zero();
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    for (Candidate& c : candidates_) project_contact(c, access);
    for (EdgeCandidate& c : edge_candidates_) project_edges(c, access);
    for (std::size_t i = 0; i < attachments_.size(); ++i)
      if (attachments_[i].holding)
        project_attachment(i, attachments_[i].spec.compliance * alpha_scale, dt, access, true,
                           std::numeric_limits<Real>::infinity());
  }
  for (const Candidate& c : candidates_) {
    if (c.touching || c.adhered) contact_velocities(c, dt, access);
    if (c.corrected) ++corrected_;
  }
  for (const EdgeCandidate& c : edge_candidates_) {
    if (c.touching) edge_velocities(c, access);
    if (c.corrected) ++corrected_;
  }
  for (std::size_t i = 0; i < attachments_.size(); ++i) {
    AttachmentState& a = attachments_[i];
    if (!a.holding) continue;
    a.force = lambda_[i].norm() * alpha_scale;
    if (a.force > a.spec.pullout_force) {
      a.holding = false;  // torn out: for good
      a.torn_at = time;
    }
  }
  untangle();
}

void TissueContactSolver::untangle() {
  rewound_ = 0;
  for (Body& body : bodies_) {
    if (!body.self) continue;
    const MassSpringSettings& s = *tissues_[body.tissue].settings;
    MassSpringState& state = *tissues_[body.tissue].state;
    std::vector<Vec3>& x = state.positions;
    bool crossed = true;
    for (int round = 0; round <= kMaxRewinds && crossed; ++round) {
      if (round == kMaxRewinds) {  // still tangled: the whole tissue goes back
        for (std::size_t v = 0; v < x.size(); ++v) body.rewind[v] = 1;
      } else {
        // The triangles' boxes as they are now, and every edge against the triangles its box meets.
        for (std::size_t t = 0; t < s.triangles.size(); ++t) {
          const Triangle& tri = s.triangles[t];
          body.lo[t] = component_min(component_min(x[tri[0]], x[tri[1]]), x[tri[2]]);
          body.hi[t] = component_max(component_max(x[tri[0]], x[tri[1]]), x[tri[2]]);
        }
        body.grid.build(body.lo, body.hi);
        crossed = false;
        for (const auto& edge : body.edges) {
          const std::uint32_t i = edge[0], j = edge[1];
          const Vec3 lo = component_min(x[i], x[j]), hi = component_max(x[i], x[j]);
          body.grid.query(lo, hi, [&](std::uint32_t t) {
            const Triangle& tri = s.triangles[t];
            if (tri[0] == i || tri[1] == i || tri[2] == i || tri[0] == j || tri[1] == j || tri[2] == j) return;
            if ((lo.array() > body.hi[t].array()).any() || (hi.array() < body.lo[t].array()).any()) return;
            if (!segment_crosses_triangle(x[i], x[j], x[tri[0]], x[tri[1]], x[tri[2]])) return;
            body.rewind[i] = body.rewind[j] = 1;
            for (const std::uint32_t v : tri) body.rewind[v] = 1;
            crossed = true;
          });
        }
        if (!crossed) break;
      }
      for (std::size_t v = 0; v < x.size(); ++v) {
        if (body.rewind[v] == 0) continue;
        body.rewind[v] = 0;
        if (x[v] == body.start[v] && state.velocities[v].isZero()) continue;
        x[v] = body.start[v];
        state.velocities[v].setZero();
        ++rewound_;
      }
    }
  }
}

bool TissueContactSolver::can_couple(std::span<const CoupledTissue> tissues, std::span<const std::uint8_t> outside) const {
  const auto stepped = [&](std::size_t t) { return t < tissues.size() && tissues[t].solver != nullptr; };
  const auto away = [&](std::size_t t) { return t < outside.size() && outside[t] != 0; };
  bool any = false;
  for (const TissueContactPair& pair : pairs_) {
    if (away(pair.a) || away(pair.b)) continue;  // a tissue outside the body: nothing to solve
    // A tissue stepped otherwise (not XPBD) needs the solve after the integrators.
    if (!stepped(pair.a) || !stepped(pair.b)) return false;
    any = true;
  }
  for (const AttachmentState& a : attachments_) {
    if (!a.holding) continue;
    if (!stepped(a.spec.a.tissue) || !stepped(a.spec.b.tissue)) return false;
    any = true;
  }
  return any;
}

bool TissueContactSolver::pair_coupled(const TissueContactPair& pair) const {
  return pair.a < coupled_.size() && pair.b < coupled_.size() && coupled_[pair.a] != nullptr &&
         coupled_[pair.b] != nullptr;
}

void TissueContactSolver::begin_coupled(std::span<const CoupledTissue> tissues, Real dt, int substeps) {
  corrected_ = 0;
  coupled_substeps_ = std::max(substeps, 1);
  for (std::size_t t = 0; t < coupled_.size(); ++t) {
    coupled_[t] = t < tissues.size() ? tissues[t].solver : nullptr;
    coupled_x_[t] = coupled_[t] != nullptr ? coupled_[t]->view().x : std::span<XpbdParticle>();
    coupled_v_[t] = coupled_[t] != nullptr ? coupled_[t]->velocities() : std::span<XpbdParticle>();
  }
  std::fill(coupled_force_.begin(), coupled_force_.end(), Real{0});
  candidates_.clear();
  edge_candidates_.clear();
  // How far a vertex may move this step: twice its last step's (its velocity's) plus gravity's
  // fall, at least kMotionFloor (an instrument can set a resting vertex moving), at most
  // kMotionCap (the instruments' own contact reach is 3 m/s). A vertex that moves further within
  // one step can cross a surface unseen (the instruments' contact has the same bound).
  constexpr Real kMotionFloor = 5e-4, kMotionCap = 5e-3;
  for (Body& body : bodies_) {
    if (coupled_[body.tissue] == nullptr) continue;
    const MassSpringSettings& s = *tissues_[body.tissue].settings;
    const std::vector<Vec3>& u = tissues_[body.tissue].state->velocities;
    const Real fall = s.gravity.norm() * dt * dt;
    for (std::size_t v = 0; v < u.size(); ++v)
      body.motion[v] = std::clamp(2 * u[v].norm() * dt + fall, kMotionFloor, kMotionCap);
    for (std::size_t t = 0; t < s.triangles.size(); ++t) {
      const Triangle& tri = s.triangles[t];
      Vec3 lo = body.start[tri[0]], hi = lo;
      Real grow = 0;
      for (int k = 0; k < 3; ++k) {
        lo = component_min(lo, body.start[tri[k]]);
        hi = component_max(hi, body.start[tri[k]]);
        grow = std::max(grow, body.motion[tri[k]]);
      }
      body.lo[t] = lo.array() - (grow + body.reach);
      body.hi[t] = hi.array() + (grow + body.reach);
    }
    body.grid.build(body.lo, body.hi);
  }
  for (const TissueContactPair& pair : pairs_) {
    if (!pair_coupled(pair)) continue;
    Body& a = bodies_[static_cast<std::size_t>(body_of_[pair.a])];
    Body& b = bodies_[static_cast<std::size_t>(body_of_[pair.b])];
    gather(pair, a, b, pair.a == pair.b, true);
    if (pair.a != pair.b) gather(pair, b, a, false, true);
    if (pair.a == pair.b) gather_edges(pair, a, true);
  }
}

void TissueContactSolver::solve_coupled_positions(Real h) {
  ParticleAccess access{coupled_x_, coupled_v_};
  for (Candidate& c : candidates_) {
    c.touching = false;  // this substep's
    project_contact(c, access);
  }
  for (EdgeCandidate& c : edge_candidates_) {
    c.touching = false;
    project_edges(c, access);
  }
  const Real alpha_scale = 1 / (h * h);
  for (std::size_t i = 0; i < attachments_.size(); ++i) {
    AttachmentState& a = attachments_[i];
    if (!a.holding || a.stretched_out) continue;
    lambda_[i] = Vec3::Zero();  // one pass a substep, from zero ("Small steps" §4)
    // Stretched beyond a tack's own length within a substep, it holds nothing and has come out. A
    // tack into a light tissue that an instrument presses against the mesh would otherwise fling
    // that tissue back by the stretch in one substep (10 mm in 0.25 ms: the vas deferens under
    // the novice's tacker at 40 m/s), while its force, m·a of a light tissue, stays far under
    // the pull-out force.
    if (!project_attachment(i, a.spec.compliance * alpha_scale, h, access, false, kTackLength)) {
      a.stretched_out = true;  // torn at end_coupled
      continue;
    }
    coupled_force_[i] += lambda_[i].norm() * alpha_scale;
  }
}

void TissueContactSolver::solve_coupled_velocities(Real h) {
  ParticleAccess access{coupled_x_, coupled_v_};
  for (const Candidate& c : candidates_)
    if (c.touching || c.adhered) contact_velocities(c, h, access);
  for (const EdgeCandidate& c : edge_candidates_)
    if (c.touching) edge_velocities(c, access);
}

void TissueContactSolver::end_coupled(Real time) {
  for (const Candidate& c : candidates_)
    if (c.corrected) ++corrected_;
  for (const EdgeCandidate& c : edge_candidates_)
    if (c.corrected) ++corrected_;
  for (std::size_t i = 0; i < attachments_.size(); ++i) {
    AttachmentState& a = attachments_[i];
    if (!a.holding) continue;
    a.force = coupled_force_[i] / coupled_substeps_;
    if (a.force > a.spec.pullout_force || a.stretched_out) {
      a.holding = false;  // torn out: for good
      a.torn_at = time;
    }
  }
  std::fill(coupled_.begin(), coupled_.end(), nullptr);
  untangle();  // on the states the solvers' finish() wrote
}

std::size_t TissueContactSolver::attach(const AttachmentSpec& spec) {
  constexpr std::size_t kRefused = std::numeric_limits<std::size_t>::max();
  if (attachments_.size() >= capacity_) return kRefused;
  for (const SurfacePoint* p : {&spec.a, &spec.b}) {
    if (p->tissue >= tissues_.size() || p->triangle >= tissues_[p->tissue].settings->triangles.size())
      return kRefused;
    if (!p->bary.allFinite() || (p->bary.array() < -1e-9).any() || std::abs(p->bary.sum() - 1) > 1e-6) return kRefused;
  }
  if (!(spec.pullout_force > 0) || !(spec.compliance >= 0) || !std::isfinite(spec.compliance) ||
      !spec.offset.allFinite())
    return kRefused;
  attachments_.push_back({spec, true, 0, -1, false});
  lambda_.push_back(Vec3::Zero());
  coupled_force_.push_back(0);
  return attachments_.size() - 1;
}

Vec3 surface_position(const MassSpringSettings& settings, const MassSpringState& state, const SurfacePoint& p) {
  const Triangle& t = settings.triangles[p.triangle];
  return p.bary[0] * state.positions[t[0]] + p.bary[1] * state.positions[t[1]] + p.bary[2] * state.positions[t[2]];
}

Mat3 triangle_frame(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e = b - a;
  const Vec3 n = e.cross(c - a);
  Mat3 frame = Mat3::Identity();
  if (!(e.norm() > 0) || !(n.norm() > 0)) return frame;
  frame.col(0) = e.normalized();
  frame.col(2) = n.normalized();
  frame.col(1) = frame.col(2).cross(frame.col(0));
  return frame;
}

Mat3 surface_frame(const MassSpringSettings& settings, const MassSpringState& state, const SurfacePoint& p) {
  const Triangle& t = settings.triangles[p.triangle];
  return triangle_frame(state.positions[t[0]], state.positions[t[1]], state.positions[t[2]]);
}

}  // namespace trocar
