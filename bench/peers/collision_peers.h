#pragma once
/// The collision comparison shared by `bench_collision` and `trocar bench collision`: a scene
/// (a deforming tissue and a tool cutting into its upper surface) and one "peer" per method
/// (trocar's OHC, BVH and brute force, FCL, Bullet) that counts the intersecting triangle pairs
/// of a frame. FCL and Bullet are compiled in when their packages are found (TROCAR_HAVE_FCL,
/// TROCAR_HAVE_BULLET); their headers stay inside collision_peers.cpp. See docs/collision-bench.md.
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/mesh/tri_mesh.h"

namespace trocar {

class CollisionDetector;

/// How the tool is placed and how the tissue deforms.
struct CollisionSceneSettings {
  /// Depth of the tool's lowest point below the tissue's upper surface, as a fraction of the
  /// tool's smallest bounding-box side (dimensionless).
  Real depth_fraction = 0.6;
  /// Angle of the tool's long axis below the horizontal (degrees).
  Real tilt_degrees = 30;
  /// Per-frame perturbation amplitude of every tissue vertex, as a fraction of the tissue's mean
  /// edge length (dimensionless).
  Real amplitude_fraction = 0.05;
};

/// A tissue at rest, its per-vertex perturbation phases, and a tool fixed in the world. Units are
/// those of the meshes (the same for both).
struct CollisionScene {
  TriMesh tissue;               ///< rest shape (world frame)
  TriMesh tool;                 ///< placed tool (world frame), rigid
  std::vector<Vec3> phases;     ///< per tissue vertex: phases of the three sine perturbations
  Real amplitude = 0;           ///< perturbation amplitude (mesh units)
  Vec3 target = Vec3::Zero();   ///< the point of the tissue's upper surface the tool cuts into
};

/// Builds the scene: rotates the tool so that its longest bounding-box axis points down at
/// settings.tilt_degrees, and moves it so that its lowest point lies depth_fraction × its
/// smallest side below the tissue's upper surface (the highest tissue vertex over the central
/// half of the tissue's xy extent). Throws trocar::Error when either mesh has no triangles.
CollisionScene make_collision_scene(TriMesh tissue, TriMesh tool, const CollisionSceneSettings& settings = {});

/// Tissue positions of frame `frame`: every vertex moved from rest by
/// amplitude · (sin(φx + 0.9f), sin(φy + 1.3f), sin(φz + 1.7f)). Writes into `out` (resized).
void tissue_frame(const CollisionScene& scene, std::size_t frame, std::vector<Vec3>& out);

/// Reference count of intersecting (tool, tissue) triangle pairs: every tissue triangle whose box
/// meets the tool's box against every tool triangle, with trocar's exact test
/// (intersect_triangles, touching counts). Independent of the collision module; slow but exact.
std::size_t reference_pair_count(const CollisionScene& scene, std::span<const Vec3> tissue_positions);

/// The methods of the comparison.
enum class PeerKind {
  kOhc,            ///< trocar CollisionDetector, OHC broad phase
  kBvh,            ///< trocar CollisionDetector, BVH broad phase (refit)
  kBrute,          ///< trocar CollisionDetector, brute-force broad phase
  kFclAabb,        ///< FCL BVHModel<AABB>, refitted, collide() with all contacts
  kFclObbrss,      ///< FCL BVHModel<OBBRSS>, refitted, collide() with all contacts
  kBulletGimpact,  ///< Bullet btGImpactMeshShape (refit via postUpdate), BVH pairs + Möller test
  kBulletDbvt,     ///< Bullet btDbvt over triangle leaves (per-frame refit) + Möller test
};

/// Every kind, in the order of the tables.
std::vector<PeerKind> all_peer_kinds();
/// Short name ("ohc", "bvh", "brute", "fcl-aabb", "fcl-obbrss", "bullet-gimpact", "bullet-dbvt").
const char* peer_name(PeerKind kind);
/// True when the method was compiled in (FCL and Bullet are optional).
bool peer_available(PeerKind kind);
/// True when the method is worth running on a scene of this size: brute force only up to 10⁷
/// triangle pairs (about 45 ns each), FCL OBBRSS only up to 10⁵ tissue triangles (seconds per frame beyond).
bool peer_practical(PeerKind kind, std::size_t tissue_triangles, std::size_t tool_triangles);

/// One method of the comparison, set up for one scene (the scene must outlive it).
class CollisionPeer {
 public:
  virtual ~CollisionPeer() = default;
  /// Which method.
  virtual PeerKind kind() const = 0;
  /// Number of intersecting (tool triangle, tissue triangle) pairs with the tissue at
  /// `tissue_positions` (tissue.vertex_count() of them). Refits or rebuilds whatever the method
  /// keeps; the tool does not move.
  virtual std::size_t count_pairs(std::span<const Vec3> tissue_positions) = 0;
  /// trocar's detector behind the ohc / bvh / brute peers (its timings and statistics of the
  /// last frame); null for the other libraries.
  virtual const CollisionDetector* detector() const { return nullptr; }
};

/// The method `kind` set up for `scene` (structures built on the rest shape). Throws
/// trocar::Error when the method was not compiled in.
std::unique_ptr<CollisionPeer> make_peer(PeerKind kind, const CollisionScene& scene);

/// Whether FCL / Bullet (and which precision) were compiled in, for reports.
std::string peers_build_info();

}  // namespace trocar
