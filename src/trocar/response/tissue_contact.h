#pragma once
/// Contact between deformable bodies and attachments between their surfaces: the prosthetic mesh
/// resting on the abdominal wall without crossing it or itself, and the tacks that fix it there
/// (docs/response.md, "Tissue against tissue"). Runs once per step after every tissue's integrator
/// and instrument response. No allocation after warm-up (attachments up to their capacity).
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/geometry/closest_point.h"
#include "trocar/mesh/sheet_boundary.h"
#include "trocar/response/triangle_grid.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"
#include "trocar/tissue/xpbd.h"

namespace trocar {

/// Two tissues whose surfaces must stay apart by `thickness` (scene key "tissue_contacts");
/// a == b is a tissue's contact with itself (a cloth that must not cross itself).
struct TissueContactPair {
  std::size_t a = 0;         ///< tissue index
  std::size_t b = 0;         ///< tissue index (== a: self contact)
  Real thickness = 1e-3;     ///< the gap kept between the surfaces (m)
  Real friction = 0.3;       ///< Coulomb coefficient of the tangential correction
  /// Adhesion (m/s²): the largest acceleration with which a surface holds a vertex that lies
  /// within `adhesion_range` beyond the gap and moves away from it (a wet mesh clinging to moist
  /// tissue; docs/response.md, "Adhesion"). 0: none.
  Real adhesion = 0;
  Real adhesion_range = 0.002;  ///< m beyond the gap within which adhesion holds
};

/// A point on a tissue's surface, carried by the triangle it lies in.
struct SurfacePoint {
  std::uint32_t tissue = 0;    ///< tissue index
  std::uint32_t triangle = 0;  ///< triangle of the tissue's settings.triangles
  Vec3 bary = Vec3(1, 0, 0);   ///< barycentric weights (sum 1)
};

/// Two surface points held together (a tack through the mesh into the tissue): a compliant
/// constraint holding a at `offset` from b in b's triangle frame, that lets go for good when its
/// force exceeds `pullout_force`.
struct AttachmentSpec {
  SurfacePoint a;              ///< e.g. on the prosthetic mesh
  SurfacePoint b;              ///< e.g. on the abdominal wall
  /// m, a's place relative to b in b's triangle frame (surface_frame()): where a lay when tacked.
  /// A tack must keep what the pair's contact keeps: held at zero length across a contact of
  /// thickness h (or with the sideways offset between two closest points), tack and contact undo
  /// each other by h per iteration, as a velocity of h/dt, and the step blows up (a mesh of real
  /// mass, 1 mg a vertex, within 10 ms).
  Vec3 offset = Vec3::Zero();
  Real pullout_force = 28.6;   ///< N; docs/response.md cites the figure
  /// m/N (the inverse of the tack's stiffness): 2e-5 stretches 0.57 mm at the pull-out force.
  Real compliance = 2e-5;
};

/// An attachment and what it did.
struct AttachmentState {
  AttachmentSpec spec;
  bool holding = true;   ///< false once torn out
  Real force = 0;        ///< the constraint force of the last step (N)
  Real torn_at = -1;     ///< simulated time it tore (s), < 0 while holding
  /// Torn because it was stretched beyond a tack's length (coupled solve), whatever its force.
  bool stretched_out = false;
};

/// The tissues as the solver sees them (pieces live in the World; they never move).
struct ContactTissue {
  const MassSpringSettings* settings = nullptr;
  MassSpringState* state = nullptr;
};

/// One tissue as the coupled solve steps it (by its index among the contact solver's tissues;
/// solver null: not stepped in lock-step, e.g. not XPBD, or outside the body).
struct CoupledTissue {
  XpbdSolver* solver = nullptr;
  MassSpringState* state = nullptr;
  const TissueLoads* loads = nullptr;
  XpbdContacts* contacts = nullptr;  ///< its instrument contact handler (null: none)
};

/// Solves the pairs' contacts and the attachments, either after the integrators (solve()) or,
/// when every tissue they join is stepped by XPBD, inside the tissues' substeps, all of them in
/// lock-step (coupled: begin_coupled() … end_coupled(); xpbd_coupling.h drives it).
///
/// Coupled, the contacts and tacks are constraints of one Gauss–Seidel system with each tissue's
/// springs and its instruments: every substep, after the tissues' own constraints and their
/// instruments' contacts, one pass over the contacts and tacks moves both sides in proportion to
/// their inverse masses; the velocities are the substep's Δx/h (XPBD), with the contacts' velocity
/// pass (inelastic, friction, adhesion) after. The tissue pass comes last, as it did after the
/// integrators: with the instruments last instead, a grasper pressing the light mesh into the
/// wall's gap and the contact pushing it back out fed each other until the TAPP scene blew up
/// (2.89 s into the expert track). After the integrators, the tissues' solvers and this one take
/// turns a whole step apart, and a tack's pull enters the velocities as Δx/dt on top.
class TissueContactSolver {
 public:
  /// `attachment_capacity`: attachments held without allocating.
  TissueContactSolver(std::vector<ContactTissue> tissues, std::vector<TissueContactPair> pairs,
                      std::size_t attachment_capacity = 256);
  ~TissueContactSolver();
  TissueContactSolver(const TissueContactSolver&) = delete;
  TissueContactSolver& operator=(const TissueContactSolver&) = delete;

  /// At the start of a step, before the integrators: remembers the positions the surfaces start
  /// from (which side of a surface each vertex is on).
  void begin_step();
  /// After the integrators: pushes the surfaces apart, holds the attachments (tearing those above
  /// their pull-out force at `time`), and corrects the velocities for the step dt.
  void solve(Real dt, Real time);

  /// Adds an attachment; returns its index, or SIZE_MAX when the capacity is full or the spec
  /// names a tissue or triangle that does not exist.
  std::size_t attach(const AttachmentSpec& spec);
  std::span<const AttachmentState> attachments() const { return attachments_; }
  /// Tissue t's model changed (a cut or coagulation): `tissue` is its new model and state,
  /// `triangle_origin` maps each new triangle to the old one. Re-sizes its proximity structures;
  /// an attachment on a triangle that is gone lets go (torn at `time`, force 0), the others
  /// follow their triangle's new index. Allocates.
  void remodel(std::size_t t, const ContactTissue& tissue, std::span<const std::uint32_t> triangle_origin,
               std::size_t old_triangle_count, Real time);
  std::span<const TissueContactPair> pairs() const { return pairs_; }

  /// Whether the contacts and the holding tacks can be solved inside the substeps of the
  /// tissues whose solvers are given (per tissue; null: not stepped in lock-step, e.g. not XPBD):
  /// every holding tack joins two of them, and every pair joins two of them unless one of its
  /// tissues is `outside` the body (per tissue, 1: waiting to enter; its pairs are skipped). False
  /// also when there is nothing to solve.
  bool can_couple(std::span<const CoupledTissue> tissues, std::span<const std::uint8_t> outside) const;
  /// After begin_step() and every coupled solver's begin(): the candidates for this step, from
  /// the start positions grown by how far each vertex may move in it (twice its last step's
  /// motion and gravity's, at least 0.5 mm, at most 5 mm). `tissues` as can_couple (true for it;
  /// null at a tissue outside the body).
  void begin_coupled(std::span<const CoupledTissue> tissues, Real dt, int substeps);
  /// Inside substep s of length h, after the tissues' own constraints: one pass over the contacts
  /// and the tacks (each tack's multiplier starts at 0 every substep, as the springs' do).
  void solve_coupled_positions(Real h);
  /// After the substep's velocities: the contacts' velocity pass.
  void solve_coupled_velocities(Real h);
  /// After the substeps: each tack's force (the mean over the substeps) and its tearing at `time`.
  void end_coupled(Real time);
  /// Vertices the last solve moved (all pairs).
  std::uint32_t corrected() const { return corrected_; }
  /// Vertices the last step's fail-safe put back where they started it (self pairs: untangle()).
  std::uint32_t rewound() const { return rewound_; }

 private:
  /// A tissue that takes part in a pair: where its vertices started, its triangles' boxes and
  /// their grid, sized once.
  struct Body {
    std::uint32_t tissue = 0;
    Real reach = 0;                 ///< the largest thickness of its pairs (m)
    Real side = 0;                  ///< closed: +1 outward normals (−1 inward); open: 0 (start side)
    std::vector<Vec3> start;        ///< positions at begin_step
    std::vector<Vec3> lo, hi;       ///< per triangle: box over start and end, ± reach
    std::vector<Real> motion;       ///< coupled: per vertex, how far it may move this step (m)
    SheetBoundary border;           ///< its boundary edges and their vertices (none when closed)
    /// Per triangle, the triangle across each local edge k (corners k, k+1); UINT32_MAX on the
    /// border or at a non-manifold edge.
    std::vector<std::array<std::uint32_t, 3>> across;
    /// Its unique edges (vertex pairs) and, per triangle, the edge ids of its local edges k
    /// (corners k, k+1): the self contact's edge–edge candidates.
    std::vector<std::array<std::uint32_t, 2>> edges;
    std::vector<std::array<std::uint32_t, 3>> triangle_edges;
    std::vector<std::uint64_t> edge_seen;  ///< per edge: the last gather round that paired it
    std::vector<std::uint8_t> rewind;      ///< per vertex: to be put back (untangle)
    bool self = false;                     ///< in a self pair
    TriangleGrid grid;
  };
  /// A vertex near a triangle (of the same or another tissue) and the side it must stay on.
  struct Candidate {
    std::uint32_t vertex_tissue, vertex, triangle_tissue, triangle;
    Real side;        ///< +1 / −1: the side of the triangle's plane the vertex must end on
    Real thickness;   ///< the pair's gap (m)
    Real friction;    ///< the pair's Coulomb coefficient
    Real reach;       ///< the deepest violation this step's motion can explain (m)
    Vec3 direction;   ///< last correction: the unit direction that separates
    Vec3 bary;        ///< last correction: the closest point's barycentric weights
    bool touching;    ///< pushed apart in some sweep of this solve (its velocity is corrected)
    bool adhered;     ///< last sweep: beyond the gap but within the adhesion range
    Real adhesion;    ///< the pair's adhesion (m/s²) and range (m)
    Real adhesion_range;
    Real excess;      ///< last sweep, when adhered: how far beyond the gap (m)
    bool corrected;   ///< moved at least once this solve
  };

  /// Two edges of one tissue near each other (self contact) and the side of each other's line
  /// they started on (Bridson, Fedkiw & Anderson 2002, §7: edge–edge proximity; a vertex–face
  /// test alone misses an edge passing through another with no vertex changing side).
  struct EdgeCandidate {
    std::uint32_t tissue, e, f;  ///< edges e = (i, j) and f = (k, l) of the tissue
    /// Where the closest points of the two segments lay strictly inside both at the step's start:
    /// the sign of (e × f)·(x_k − x_i) then (the side of e's line f's lay on); 0 otherwise (no
    /// crossing can be told from the lines' sides).
    Real sigma;
    Real thickness, friction;
    Real reach;       ///< the deepest violation this step's motion can explain (m)
    Vec3 direction;   ///< last correction: unit, from e's closest point toward f's
    Real s, t;        ///< last correction: the closest points' parameters on e and f
    bool touching;    ///< pushed apart in some sweep of this solve
    bool corrected;
  };

  /// `predicted`: the coupled gather (start ± each vertex's motion bound) instead of start and
  /// end.
  void gather(const TissueContactPair& pair, Body& vertices, Body& triangles, bool self, bool predicted);
  // The projections, on the tissues' states (after the integrators) or on the coupled solvers'
  // particles: `Access` reads and moves positions and velocities (tissue_contact.cpp).
  template <typename Access>
  void project_contact(Candidate& c, Access& access);
  /// Whether vertex p, beyond feature q of the candidate's triangle (normal n) at offset d from
  /// it and on the far side of the triangle's plane, has crossed the surface there.
  template <typename Access>
  bool crossed_beyond(const Candidate& c, const TriangleClosestPoint& q, const Vec3& p, const Vec3& n, const Vec3& d,
                      Access& access) const;
  /// The self pair's edge–edge candidates (same motion bounds as gather()).
  void gather_edges(const TissueContactPair& pair, Body& body, bool predicted);
  template <typename Access>
  void project_edges(EdgeCandidate& c, Access& access);
  template <typename Access>
  void edge_velocities(const EdgeCandidate& c, Access& access);
  /// The fail-safe after a step, for each tissue in a self pair: every edge that now passes
  /// through one of its triangles is put back, with that triangle, where they started the step,
  /// at rest (Provot 1997's rewind; Bridson, Fedkiw & Anderson 2002 §7.4 use it as the last
  /// resort too). The step started uncrossed, so a vertex put back cannot cross another put back;
  /// repeated until nothing crosses (after kMaxRewinds rounds the whole tissue goes back).
  void untangle();
  /// The edges of the tissues in self pairs (the edge candidates' reserve).
  std::size_t self_edges() const;
  /// Sets body's border and its triangles' neighbours from its tissue's model.
  void set_adjacency(Body& body);
  /// False (and nothing moved) when the attachment is stretched past `stretch_limit` (m).
  template <typename Access>
  bool project_attachment(std::size_t i, Real alpha, Real dt, Access& access, bool move_velocities,
                          Real stretch_limit);
  /// The velocity pass of a touching candidate (inelastic, friction), or of an adhered one (the
  /// bounded pull back toward the gap, with friction), over a step or substep of length dt.
  template <typename Access>
  void contact_velocities(const Candidate& c, Real dt, Access& access);
  /// True when the pair's tissues are both stepped in lock-step (coupled).
  bool pair_coupled(const TissueContactPair& pair) const;

  std::vector<ContactTissue> tissues_;
  std::vector<TissueContactPair> pairs_;
  std::vector<AttachmentState> attachments_;
  std::vector<Vec3> lambda_;                 ///< per attachment: this step's Lagrange multiplier
  std::vector<Body> bodies_;                 ///< the tissues in pairs
  std::vector<std::int32_t> body_of_;        ///< per tissue: index into bodies_, −1 if in no pair
  std::vector<Candidate> candidates_;
  std::vector<EdgeCandidate> edge_candidates_;
  std::uint64_t edge_round_ = 0;             ///< gather rounds (one per edge queried), never reset
  std::size_t capacity_ = 0;
  std::uint32_t corrected_ = 0;
  std::uint32_t rewound_ = 0;
  // Coupled: per tissue its solver (null: not in lock-step), the substeps, and per attachment
  // Σ |λ|/h² over the substeps so far.
  std::vector<XpbdSolver*> coupled_;
  std::vector<std::span<XpbdParticle>> coupled_x_, coupled_v_;  ///< their particles and velocities
  int coupled_substeps_ = 1;
  std::vector<Real> coupled_force_;
};

/// The world position of a surface point.
Vec3 surface_position(const MassSpringSettings& settings, const MassSpringState& state, const SurfacePoint& p);

/// The orthonormal frame of triangle abc: columns the first edge's direction (b − a), the
/// normal × that edge, and the unit normal as wound (the identity for a degenerate triangle).
Mat3 triangle_frame(const Vec3& a, const Vec3& b, const Vec3& c);

/// p's triangle's frame (triangle_frame) as it is now.
Mat3 surface_frame(const MassSpringSettings& settings, const MassSpringState& state, const SurfacePoint& p);

}  // namespace trocar
