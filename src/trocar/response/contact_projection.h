#pragma once
/// The `sdf` response: contact as a position constraint that a position-driven instrument
/// enforces on the tissue (docs/response.md "Contact as a constraint"). Runs after the tissue's
/// integration, so the tissue's implicit system never sees a stiff penalty term.
#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/collision/contact.h"
#include "trocar/core/types.h"
#include "trocar/instrument/instrument.h"
#include "trocar/response/grasp.h"
#include "trocar/response/instrument_field.h"
#include "trocar/response/settings.h"

namespace trocar {

/// One tissue as the projection sees it (the World's TissueBody parts).
struct ProjectedTissue {
  std::span<Vec3> positions;                 ///< x_i (m), corrected in place
  std::span<Vec3> velocities;                ///< v_i (m/s), corrected in place
  std::span<const Real> masses;              ///< m_i (kg)
  std::span<const std::uint8_t> fixed;       ///< 1 for vertices that never move
  std::span<const Triangle> triangles;       ///< outward triangles
};

/// What one projection did.
struct ProjectionStats {
  std::uint32_t candidates = 0;   ///< tissue vertices near enough for an exact query
  std::uint32_t projected = 0;    ///< tissue vertices moved out of the instrument
  std::uint32_t face_pushes = 0;  ///< instrument vertices that pushed a tissue triangle away
  Real max_correction = 0;        ///< largest |Δx| of a tissue vertex (m)
  /// Force on the instrument (N): −Σ m_i Δx_i / dt², the force that moved the tissue out over
  /// this step (in a held press, exactly what the tissue's springs push with); unclamped.
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();     ///< about the pose origin (N·m)
};

/// Keeps one tissue outside one rigid instrument (one projector per instrument–tissue pair).
///
/// Each step, after the integrator and the grasp:
///  (a) every free tissue vertex x near the instrument (world box, then the field's grid bound)
///      is taken to the instrument's frame, q = R⁻¹(x − t), and queried exactly. Inside (or
///      within `contact_margin` of the surface) it goes back to the surface plus the margin:
///      onto the plane of the instrument feature it was nearest to at the end of the last step
///      when it was outside then (so a vertex that went past the middle of a thin hook leaves by
///      the side it came in, not the nearer far side), else onto the nearest surface point.
///      Friction (position-based, Macklin et al., "Unified particle physics", SIGGRAPH 2014
///      §6.1): the vertex's motion along the surface relative to the instrument since the end of
///      the last step is undone while it is ≤ μs × the normal correction (sticking: a sliding
///      instrument drags the surface), else shortened by μk × it. Friction on the velocity
///      instead (Bridson et al. 2002) was tried: it lets the tissue slip round a thin hook.
///  (b) each instrument vertex a that is below a nearby tissue triangle's plane
///      (d = n_out·(a − B1) < 0), above its face (barycentric coordinates w ≥ 0, to a small
///      tolerance) and shallower than the instrument's thickness plus its reach over the step,
///      pushes that triangle away. Nearby triangles: those of this step's contacts and those
///      incident to a tissue vertex within two mean edge lengths of the instrument (a face that
///      has closed over a thin wire no longer intersects it, so the contacts alone miss it).
///      The push: Δx_j = w_j (d − margin) n_out / Σ w² (Σ w_j Δx_j = (d − margin) n_out:
///      the triangle's point under a moves so that a ends `margin` outside), averaged over a
///      vertex's pushes. This keeps a thin tip from poking between coarse tissue vertices.
///      Triangles that the pierce filter discards (top vertex inside their plane) are skipped.
///  Then (a) again, so that the tissue vertices end outside; (b) and (a) repeat
///  `projection_rounds` times (Gauss–Seidel). Each moved vertex's velocity gets
///  Δx/dt (the contact is inelastic along the normal; the instrument's velocity is imposed).
///  Fixed and grasped vertices are never moved. `max_force` plays no part here: it clamps only
///  the force reported to the instrument.
/// `thickness` (m) is the instrument's (InstrumentBody::thickness). No allocation in project()
/// after reset().
class ContactProjector {
 public:
  /// Sizes the per-vertex state for a tissue of `vertex_count` vertices and these triangles
  /// (builds the vertex → triangle lists of pass (b)).
  void reset(std::size_t vertex_count, std::span<const Triangle> triangles, std::size_t instrument_vertices = 0);
  /// Sizes the per-sample buffers for `field`'s instrument (call after reset(), before the first
  /// project(); otherwise the first projection with a contact allocates them).
  void size_for(const InstrumentField& field);
  /// Per instrument vertex: 1 when it pushed a tissue face in the last project() (pass (b)): the
  /// projection found and answered that vertex's contact itself (the tunneling metric counts it as
  /// seen, like a vertex of a detected contact). Sized by reset()'s instrument_vertices.
  std::span<const std::uint8_t> instrument_hits() const { return hits_; }
  /// One step's projection (see the class comment). `contacts` may hold other pairs' contacts
  /// (skipped). dt > 0.
  ProjectionStats project(const Instrument& instrument, const InstrumentField& field, std::span<const Contact> contacts,
                          std::uint32_t instrument_object, std::uint32_t tissue_object, const Grasp& grasp,
                          const ProjectedTissue& tissue, Real thickness, Real dt, const ResponseSettings& settings);

 private:
  /// Pass (a) over the candidates (`first`: the round that applies friction and the
  /// previous-plane rule), or over the vertices the last pass (b) moved.
  void project_vertices(const Instrument& instrument, const InstrumentField& field, const ProjectedTissue& tissue,
                        const ResponseSettings& settings, bool first, ProjectionStats& stats);
  /// The field's samples near this step's tissue candidates, in the world (once per step).
  void place_samples(const Instrument& instrument, const InstrumentField& field, std::span<const Contact> contacts,
                     std::uint32_t instrument_object, std::uint32_t tissue_object, const ProjectedTissue& tissue,
                     Real depth_limit);
  /// Pass (b) over the contacts' and the nearby triangles.
  void push_faces(const Instrument& instrument, const InstrumentField& field, std::span<const Contact> contacts,
                  std::uint32_t instrument_object, std::uint32_t tissue_object, const Grasp& grasp,
                  const ProjectedTissue& tissue, const ResponseSettings& settings, Real depth_limit,
                  ProjectionStats& stats);
  /// Pass (b) for one triangle.
  void push_face(const InstrumentField& field, std::uint32_t triangle, const Grasp& grasp,
                 const ProjectedTissue& tissue, const ResponseSettings& settings, Real depth_limit,
                 ProjectionStats& stats);
  /// One sample against one face (push_face's inner step).
  void push_sample(std::uint32_t sample, const Triangle& tb, const Vec3& n_out, const Vec3& b0, const Vec3& b1,
                   const Vec3& b2, const Aabb& face, const Grasp& grasp, const ProjectedTissue& tissue,
                   const InstrumentField& field, Real margin, Real depth_limit, ProjectionStats& stats);
  /// Records the start position of vertex v the first time it moves this step.
  void mark_moved(std::uint32_t v, const Vec3& x);

  std::uint64_t step_ = 1;  ///< projections so far + 1 (the per-vertex steps start at 0: never)
  Real cull_ = 0;           ///< this step's query distance (m): margin + the step's reach + a cell
  std::vector<std::uint32_t> candidates_;   ///< this step's vertices in reach
  std::vector<std::uint64_t> near_step_;    ///< step at whose end the vertex was last queried
  std::vector<Vec3> last_local_;            ///< its local position then
  std::vector<Vec3> last_point_;            ///< the instrument point nearest to it then (local)
  std::vector<Vec3> last_normal_;           ///< that feature's outward pseudonormal (local)
  std::vector<Real> last_distance_;         ///< its signed distance then (m)
  std::vector<std::uint32_t> hint_;         ///< nearest instrument triangle (query seed)
  std::vector<std::uint64_t> moved_step_;   ///< step in which the vertex was last moved
  std::vector<Vec3> start_;                 ///< its position before this step's projection
  std::vector<std::uint32_t> moved_;        ///< vertices moved this step
  std::vector<Vec3> push_;                  ///< pass (b): Σ w·push per vertex (the direction)
  std::vector<Real> push_length_;           ///< pass (b): the longest push's length (0: none yet)
  std::vector<Vec3> world_samples_;         ///< pass (b): the field's samples in the world
  Aabb grid_box_;                           ///< pass (b): box of the active samples (world)
  Real grid_cell_ = 0;                      ///< pass (b): cell edge of their grid (m)
  std::array<std::size_t, 3> grid_n_{};     ///< pass (b): cells per axis
  std::vector<std::uint32_t> grid_start_;   ///< pass (b): CSR of the samples per cell
  std::vector<std::uint32_t> grid_fill_;    ///< pass (b): fill cursor while sorting
  std::vector<std::uint32_t> grid_samples_; ///< pass (b): sample ids, cell by cell
  /// The grid cell of world point p (inside grid_box_).
  std::size_t grid_cell_of(const Vec3& p) const {
    std::size_t c[3];
    for (int k = 0; k < 3; ++k)
      c[k] = std::min(static_cast<std::size_t>(std::max(Real{0}, (p[k] - grid_box_.min[k]) / grid_cell_)), grid_n_[k] - 1);
    return (c[2] * grid_n_[1] + c[1]) * grid_n_[0] + c[0];
  }
  std::vector<std::uint32_t> active_samples_;  ///< pass (b): samples near the tissue candidates
  std::vector<std::uint32_t> pushed_;       ///< pass (b): vertices with a push
  std::vector<std::uint32_t> round_moved_;  ///< the vertices the last pass (b) moved (rechecked by (a))
  std::vector<std::uint32_t> vertex_first_; ///< CSR: triangles of vertex v are
  std::vector<std::uint32_t> vertex_faces_; ///< vertex_faces_[vertex_first_[v] .. vertex_first_[v+1])
  std::vector<std::uint64_t> face_step_;    ///< face round in which a triangle was last pushed against
  std::uint64_t face_round_ = 0;            ///< push_faces() calls so far
  Real mean_edge_ = -1;                     ///< mean tissue edge at the first projection (m)
  std::vector<std::uint8_t> hits_;          ///< see instrument_hits()
  Vec3 top_ = Vec3::Zero();                 ///< the instrument's top vertex this step (world)
};

}  // namespace trocar
