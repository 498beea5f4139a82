#pragma once
/// A rigid laparoscopic instrument: mesh, pose, velocity, OBB, top vertex and jaws
/// (docs/response.md "The instrument").
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/obb.h"
#include "trocar/core/pose.h"
#include "trocar/core/types.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

/// A rigid instrument. The mesh is kept in its local frame (metres); a pose places it in the
/// world. Everything the response needs per step is precomputed here:
///  - world-space vertex positions, rewritten in place by move_to()/reset_pose() (no allocation);
///  - the oriented bounding box, fitted ONCE at construction by Obb::fit_pca in the local frame
///    and carried by the pose (world_obb() = pose ∘ local box; no box is built at run time);
///  - linear and angular velocity, derived from the last two poses and the time between them;
///  - the top vertex (seed Fig. 3.12): the vertex farthest back along the shaft, away from the tip;
///  - the jaws: a closure in [0, 1] and the set of triangles that grasp.
///
/// Top-vertex rule. With a shaft direction u given (local frame, pointing from the tip toward
/// the handle), the top vertex is argmax_i u·x_i. With none (`auto`, u = 0), u is the OBB's long
/// axis a_0, signed so that the tip is the end of the long axis nearer the mesh's local origin
/// (instrument meshes put the working tip at or near their origin and the shaft behind it):
/// with c the box centre, u = +a_0 when a_0·(0 − c) ≤ 0, else −a_0. Ties (vertices within
/// 1e-9 of the box's length of the maximum, e.g. a flat cap) go to the vertex nearest the line
/// through the box centre along u (the cap's centre vertex when there is one), then the lowest
/// index.
class Instrument {
 public:
  /// An instrument with no mesh (zero box, top vertex 0).
  Instrument() = default;
  /// Takes the mesh in its local frame (metres). `shaft_direction` (local frame, tip → handle)
  /// chooses the top vertex; zero means `auto` (see the class comment). Pose = identity, at rest,
  /// jaws open, no jaw triangles.
  explicit Instrument(TriMesh local_mesh, const Vec3& shaft_direction = Vec3::Zero());

  /// The mesh in the local frame.
  const TriMesh& local_mesh() const { return mesh_; }
  /// Triangles (indices into world_positions()).
  std::span<const Triangle> triangles() const { return mesh_.triangles; }
  /// Vertex positions in the world for the current pose (metres).
  std::span<const Vec3> world_positions() const { return world_; }

  /// The box fitted at construction, in the local frame.
  const Obb& local_obb() const { return local_obb_; }
  /// The same box carried by the current pose (world frame).
  const Obb& world_obb() const { return world_obb_; }

  /// Index of the top vertex.
  std::uint32_t top_vertex() const { return top_; }
  /// The top vertex in the world (metres).
  const Vec3& top_world() const { return world_[top_]; }
  /// Overrides the top vertex (an index < vertex count; out-of-range indices are ignored).
  void set_top_vertex(std::uint32_t vertex);

  /// The shaft's direction in the local frame, unit, tip → handle: the constructor's
  /// `shaft_direction`, or the `auto` rule's (see the class comment).
  const Vec3& local_shaft() const { return shaft_; }
  /// The trocar port the shaft enters the body through (world, m; scene "ports"). What lies
  /// beyond it along the shaft, toward the handle, is outside the body and touches no tissue: a
  /// real shaft is sealed in its cannula there, so nothing it catches inside can be drawn out
  /// with it. A non-finite point is ignored.
  void set_port(const Vec3& world_point);
  bool has_port() const { return has_port_; }
  const Vec3& port() const { return port_; }
  /// Where the port lies along the local shaft axis at `pose`: a local point q is outside the
  /// body when local_shaft()·q > port_height(pose), i.e. (R u)·(x − port) > 0 in the world.
  /// +∞ without a port (nothing is outside).
  Real port_height(const Pose& pose) const;
  /// True when the world point x lies beyond the port at the current pose (outside the body).
  bool outside_body(const Vec3& x) const {
    return has_port_ && (pose_.rotation * shaft_).dot(x - port_) > 0;
  }

  /// Places the instrument at `pose` with zero velocity (a teleport; previous pose = pose).
  void reset_pose(const Pose& pose);
  /// Moves to `pose`, `dt` seconds after the current one: previous ← current, current ← pose,
  /// velocities from the difference (see linear_velocity(), angular_velocity()). dt ≤ 0 or a
  /// non-finite dt gives zero velocities. No allocation.
  void move_to(const Pose& pose, Real dt);

  /// The current pose (local → world).
  const Pose& pose() const { return pose_; }
  /// The pose before the last move_to().
  const Pose& previous_pose() const { return previous_; }
  /// Velocity of the pose origin (m/s): (t₁ − t₀)/dt.
  const Vec3& linear_velocity() const { return linear_velocity_; }
  /// Angular velocity in the world frame (rad/s): the rotation q₁·q₀⁻¹ as axis·angle / dt
  /// (shortest way round, angle ∈ [0, π]).
  const Vec3& angular_velocity() const { return angular_velocity_; }
  /// Velocity of the material point now at world point x (m/s): v + ω × (x − t₁), t₁ the pose
  /// origin. Affine in x, so interpolating it barycentrically over a triangle is exact.
  Vec3 velocity_at(const Vec3& x) const {
    return linear_velocity_ + angular_velocity_.cross(x - pose_.translation);
  }

  /// Jaw closure, dimensionless: 0 open, 1 closed (scene keyframe key `jaw`, docs/scene.md
  /// "Instruments").
  Real jaw() const { return jaw_; }
  /// Sets the jaw closure, clamped to [0, 1] (NaN gives 0).
  void set_jaw(Real closure);
  /// Marks the triangles of the grasping surfaces (indices < triangle count; others ignored).
  /// Replaces the previous set.
  void set_jaw_triangles(std::span<const std::uint32_t> triangles);
  /// True when triangle t belongs to a jaw's grasping surface.
  bool is_jaw_triangle(std::uint32_t t) const { return t < jaw_flags_.size() && jaw_flags_[t] != 0; }
  /// True when any triangle is marked as a jaw triangle.
  bool has_jaws() const { return jaw_count_ > 0; }

 private:
  void update_world();

  TriMesh mesh_;                       ///< local frame
  std::vector<Vec3> world_;            ///< world positions (size = vertex count)
  std::vector<std::uint8_t> jaw_flags_;  ///< 1 for jaw triangles (size = triangle count)
  std::size_t jaw_count_ = 0;          ///< number of jaw triangles
  Obb local_obb_;                      ///< fitted once
  Obb world_obb_;                      ///< local_obb_ carried by pose_
  Pose pose_;                          ///< current pose
  Pose previous_;                      ///< pose before the last move
  Vec3 linear_velocity_ = Vec3::Zero();   ///< m/s
  Vec3 angular_velocity_ = Vec3::Zero();  ///< rad/s
  Real jaw_ = 0;                       ///< closure 0..1
  std::uint32_t top_ = 0;              ///< top vertex index
  Vec3 shaft_ = Vec3::UnitZ();         ///< local, unit, tip → handle
  Vec3 port_ = Vec3::Zero();           ///< world (m)
  bool has_port_ = false;
};

/// The unit shaft direction (tip → handle) for `shaft_direction` and box `box`: the direction
/// normalised, or for zero (auto) the box's long axis signed so that the local origin is at the
/// tip end (see Instrument's class comment).
Vec3 shaft_axis(const Obb& box, const Vec3& shaft_direction);

/// The top vertex of `points` for shaft direction u (tip → handle) and box `box` (see
/// Instrument's class comment); u = 0 means auto. Returns 0 for no points.
std::uint32_t find_top_vertex(std::span<const Vec3> points, const Obb& box, const Vec3& shaft_direction);

/// Angular velocity (rad/s, world frame) taking rotation q0 to q1 in dt seconds: axis·angle/dt
/// of q1·q0⁻¹, the shorter way round. Zero for dt ≤ 0 or non-finite input.
Vec3 angular_velocity_between(const Quat& q0, const Quat& q1, Real dt);

}  // namespace trocar
