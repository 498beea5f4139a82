#pragma once
/// Instrument contact inside the XPBD solver (tissue/xpbd.h): every substep, each tissue vertex
/// near a rigid instrument is projected out of the instrument's signed distance with friction,
/// each instrument surface sample under a tissue face pushes the face away (a wire thinner than
/// the tissue's edges), and grasped vertices follow the jaws as attachments.
/// docs/response.md "Contact inside the solver".
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/aabb.h"
#include "trocar/core/pose.h"
#include "trocar/core/types.h"
#include "trocar/instrument/instrument.h"
#include "trocar/response/instrument_field.h"
#include "trocar/response/settings.h"
#include "trocar/tissue/xpbd.h"

namespace trocar {

/// One instrument as the solver's contact sees it (not owned; must outlive the handler).
struct SolverInstrument {
  const Instrument* instrument = nullptr;
  const InstrumentField* field = nullptr;
  Real thickness = 0;  ///< InstrumentBody::thickness (m): deepest a sample may sit under a face
};

/// A contact the solver answered: where (world, m) and the tissue's outward normal there.
struct SolverContactPoint {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::Zero();
};

/// A tissue vertex held by closed jaws: its place in the instrument's frame.
struct HeldVertex {
  std::uint32_t vertex = 0;
  Vec3 local = Vec3::Zero();
};

/// The contact handler of one tissue against every instrument.
///
/// Per step (begin_step): the instrument's pose is interpolated over the substeps from its
/// previous to its current pose (slerp and lerp), so a fast instrument sweeps through the step
/// instead of jumping. Candidates: free tissue vertices in the box of the instrument's box at
/// both poses, grown by `kReach`; the instrument's surface samples (InstrumentField::samples)
/// near them; and (sample, triangle) pairs of the triangles around the candidates. Jaws at or
/// above `grasp_closure` hold the candidates within `kGrabDistance` of a jaw triangle; below it
/// they let go.
///
/// Per substep s of n (solve), with the pose P_s at (s+1)/n of the way:
///  (b) faces: for each pair, a = P_s(sample); n the face's outward unit normal (for an open
///      sheet, the side the sample was on at the start of the step); d = n·(a − x₀). When
///      −(thickness + reach) < d < margin and a projects inside the face (barycentric w ≥ −tol),
///      C = d − margin ≥ 0 is solved with gradient −w_j n at the face's vertices:
///      Δx_j = −W_j w_j (margin − d) n / Σ w_k² W_k (W the inverse masses).
///  (a) vertices: for each candidate vertex x, q = P_s⁻¹(x), cull by the field's grid bound,
///      exact distance d and outward normal n; when d < margin: x += (margin − d) n, then
///      position-based friction (Müller et al., "Detailed rigid body simulation with extended
///      position based dynamics", SCA 2020, §3.5; Macklin et al. 2014 §6.1): the vertex's slip
///      over the substep relative to the instrument, tangential part t, is undone while
///      |t| ≤ μs·|Δx_n|, else shortened by μk·|Δx_n|.
///  Neither acts beyond the instrument's port (Instrument::set_port): a vertex beyond it at P_s,
///  or a sample beyond it at both poses, is outside the body.
///  Grasped vertices are placed at P_s(local) first (an attachment of zero compliance, after the
///  tissue's constraints moved them; its correction is their pull on the jaws).
/// Force on the instrument: −Σ m Δx / h² over the corrections of all substeps, divided by n
/// (the mean constraint force over the step); torque about the current pose's origin.
class InstrumentContacts final : public XpbdContacts {
 public:
  /// How far outside the instrument's boxes a tissue vertex may start a step and still reach it
  /// within the step (m): 3 m/s for 1 ms.
  static constexpr Real kReach = 0.003;
  /// Jaws hold tissue vertices within this distance of a jaw triangle (m).
  static constexpr Real kGrabDistance = 0.001;
  /// A face is pushed off an instrument sample only if the sample starts the step above it or
  /// at most this far under it (m): a shallow penetration left by an earlier step is repaired,
  /// a deep one (the far side of the organ, a tool started inside) is left to the vertices.
  static constexpr Real kRecover = 0.0005;
  /// (sample, face) pairs one instrument may hold in a step: the bound on a step's face pushes
  /// (a tissue crumpled around a long shaft would otherwise pair thousands of faces with
  /// thousands of samples). Pairs beyond it are left out.
  static constexpr std::size_t kMaxPairs = 8192;
  /// Contact points kept per instrument for display (points()).
  static constexpr std::size_t kMaxPoints = 1024;

  /// Sizes everything for a tissue (its rest positions, triangles, closed or open) and the
  /// instruments.
  void reset(std::span<const Vec3> positions, std::span<const Triangle> triangles, bool closed,
             std::span<const SolverInstrument> instruments, const ResponseSettings& settings);

  /// The tissue changed (a cut): its side is rebuilt for the new rest positions and triangles as
  /// reset() builds it (the instruments' sample grids, which do not depend on it, are kept);
  /// every copy (vertex_origin: new → old vertex) of a held vertex stays held. Allocates.
  void remodel(std::span<const Vec3> positions, std::span<const Triangle> triangles, bool closed,
               std::span<const std::uint32_t> vertex_origin);

  void begin_step(const XpbdView& view, int substeps) override;
  void solve(const XpbdView& view, int substep, int substeps, Real h) override;
  /// Each vertex a contact moved this substep keeps at most the instrument's speed along the
  /// contact normal (inelastic: the correction adds no separating speed).
  void solve_velocities(std::span<XpbdParticle> velocities) override;

  /// Force on instrument i over the last step (N, unclamped) and its torque about the pose
  /// origin (N·m).
  const Vec3& force(std::size_t i) const { return per_[i].force; }
  const Vec3& torque(std::size_t i) const { return per_[i].torque; }
  /// Per instrument vertex: 1 when it took part in a contact in the last step.
  std::span<const std::uint8_t> hits(std::size_t i) const { return per_[i].hits; }
  /// The contacts instrument i's last substep answered (at most kMaxPoints), for display.
  std::span<const SolverContactPoint> points(std::size_t i) const { return per_[i].points; }
  /// The vertices instrument i holds.
  std::span<const HeldVertex> held(std::size_t i) const { return per_[i].held; }
  /// Tissue vertices moved by a contact in the last step (all instruments).
  std::uint32_t contacts() const { return contacts_; }

 private:
  struct Pair {
    std::uint32_t sample, triangle;
    float side;  ///< +1: the face's outward side is free; −1 (open sheet): its inner side
  };
  struct PerInstrument {
    SolverInstrument in;
    std::vector<std::uint32_t> candidates;      ///< free tissue vertices in the box
    std::vector<std::uint32_t> near;            ///< vertices within the longest edge of the box
    Aabb box;                                   ///< the instrument's boxes over the step, grown
    std::vector<std::uint32_t> hint;            ///< per tissue vertex: nearest instrument triangle
    std::vector<std::uint32_t> samples;         ///< active sample ids
    std::vector<Vec3> sample_world;             ///< their world positions this substep
    std::vector<Pair> pairs;                    ///< (active sample index, triangle)
    std::vector<HeldVertex> held;
    std::vector<SolverContactPoint> points;     ///< the last substep's contacts (capacity kMaxPoints)
    std::vector<std::uint8_t> hits;             ///< per instrument vertex
    Pose from, to;                              ///< poses at the start and end of the step
    Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
    Real depth_limit = 0;
    /// Samples further along the shaft than this (local, m) are beyond the port at both poses of
    /// the step: outside the body (+∞ without a port).
    Real port_limit = 0;
    // The instrument's samples in a uniform grid of its own frame (built once: it is rigid).
    Aabb grid_box;
    Real grid_cell = 0;
    Real sample_radius = 0;  ///< the farthest sample from the frame's origin (m)
    std::array<std::size_t, 3> grid_n{};
    std::vector<std::uint32_t> grid_start, grid_samples;  ///< CSR: sample ids cell by cell
    std::vector<std::uint32_t> sample_stamp, sample_index;  ///< per sample: round listed, index in samples
    std::uint32_t sample_round = 0;
    /// Per sample: its world position at the step's two poses, computed once a round (stamp).
    std::vector<Vec3> sample_from, sample_to;
    std::vector<std::uint32_t> sample_placed;
  };
  /// A face's bounding sphere: no point of the face is further than `radius` from `centre`.
  struct FaceSphere {
    Vec3 centre;
    Real radius;
  };
  void build_sample_grid(PerInstrument& p);
  /// The tissue's part of reset(): its faces around each vertex, the stamps, the longest edge and
  /// the per-vertex flags (every instrument's per-vertex scratch sized to it, nothing held).
  void set_surface(std::span<const Vec3> positions, std::span<const Triangle> triangles, bool closed);
  void add_pair(PerInstrument& p, std::uint32_t sample, std::uint32_t triangle, const Aabb& face, const Vec3& n,
                const Vec3& x0, const Vec3& x1, const Vec3& x2, const FaceSphere& sphere,
                std::span<const Vec3> samples);
  void find_candidates(PerInstrument& p, const XpbdView& view);
  void update_grasp(PerInstrument& p, const XpbdView& view);
  void find_pairs(PerInstrument& p, const XpbdView& view);
  void push_faces(PerInstrument& p, const XpbdView& view, Real inv_h2);
  void project_vertices(PerInstrument& p, const XpbdView& view, const Pose& pose, const Pose& before, Real inv_h2);

  std::vector<PerInstrument> per_;
  std::span<const Triangle> triangles_;
  Real longest_edge_ = 0;  ///< of the tissue at rest (m)
  Real tissue_reach_ = 0;  ///< how far a tissue vertex may move this step (m; begin_step)
  bool closed_ = true;
  ResponseSettings settings_;
  std::vector<std::uint32_t> vertex_first_, vertex_faces_;  ///< CSR: triangles around a vertex
  std::vector<std::uint32_t> triangle_stamp_;              ///< de-duplicates candidate triangles
  std::uint32_t stamp_ = 0;
  std::vector<std::uint8_t> is_held_;                      ///< per tissue vertex
  int substeps_ = 1;
  std::uint32_t contacts_ = 0;
  std::vector<std::uint32_t> touched_stamp_;                ///< per tissue vertex: counted this step
  /// This substep's contact corrections for the velocity pass: vertex, unit normal (the way the
  /// correction moved it), the instrument's speed along it there.
  struct Moved {
    std::uint32_t vertex;
    float nx, ny, nz, speed;
  };
  std::vector<Moved> moved_;
};

/// The pose a fraction f ∈ [0, 1] of the way from a to b (slerp of the rotation, lerp of the
/// translation).
Pose interpolate_pose(const Pose& a, const Pose& b, Real f);

}  // namespace trocar
