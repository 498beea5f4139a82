#include "collision_peers.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "trocar/collision/collision_object.h"
#include "trocar/collision/detector.h"
#include "trocar/core/aabb.h"
#include "trocar/core/error.h"
#include "trocar/geometry/triangle_triangle.h"

#ifdef TROCAR_HAVE_FCL
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>
#endif

#ifdef TROCAR_HAVE_BULLET
#include <BulletCollision/BroadphaseCollision/btDbvt.h>
#include <BulletCollision/CollisionShapes/btTriangleIndexVertexArray.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#endif

namespace trocar {
namespace {

/// Box of a triangle inflated by 1e-9 of its largest side, so that touching pairs pass.
Aabb inflated_triangle_box(const Vec3& a, const Vec3& b, const Vec3& c) {
  Aabb box;
  box.expand(a);
  box.expand(b);
  box.expand(c);
  return box.inflated(1e-9 * box.size().maxCoeff());
}

/// The exact test every peer without its own uses: tool triangle first, as in the detector.
bool pair_intersects(const TriMesh& tool, std::size_t tool_triangle, std::span<const Vec3> tissue,
                     const Triangle& tissue_triangle) {
  const Triangle& a = tool.triangles[tool_triangle];
  return intersect_triangles(tool.positions[a[0]], tool.positions[a[1]], tool.positions[a[2]],
                             tissue[tissue_triangle[0]], tissue[tissue_triangle[1]],
                             tissue[tissue_triangle[2]])
      .intersects;
}

Real mean_edge_length(const TriMesh& mesh) {
  Real sum = 0;
  for (const Triangle& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) sum += (mesh.positions[t[k]] - mesh.positions[t[(k + 1) % 3]]).norm();
  }
  return mesh.triangles.empty() ? 0 : sum / static_cast<Real>(3 * mesh.triangles.size());
}

/// A reproducible value in [0, 1) from an integer (splitmix64).
Real unit_hash(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  x ^= x >> 31;
  return static_cast<Real>(x >> 11) * 0x1.0p-53;
}

// ---- trocar ---------------------------------------------------------------------------------

class TrocarPeer final : public CollisionPeer {
 public:
  TrocarPeer(PeerKind kind, BroadPhaseKind broad_phase, const CollisionScene& scene)
      : kind_(kind), detector_(broad_phase) {
    objects_[0] = {ObjectRole::kInstrument, scene.tool.positions, scene.tool.triangles};
    objects_[1] = {ObjectRole::kTissue, scene.tissue.positions, scene.tissue.triangles};
  }
  PeerKind kind() const override { return kind_; }
  std::size_t count_pairs(std::span<const Vec3> tissue_positions) override {
    objects_[1].positions = tissue_positions;
    return detector_.detect(objects_).size();
  }
  const CollisionDetector* detector() const override { return &detector_; }

 private:
  PeerKind kind_;
  CollisionDetector detector_;
  CollisionObject objects_[2];
};

// ---- FCL ------------------------------------------------------------------------------------

#ifdef TROCAR_HAVE_FCL
/// FCL's mesh–mesh collide() with all contacts (no contact geometry): its own BVH traversal and
/// its own triangle test. The tissue model is refitted every frame (beginUpdateModel,
/// updateSubModel, endUpdateModel(refit, bottom-up)); converting the positions is part of the cost.
template <class BV>
class FclPeer final : public CollisionPeer {
 public:
  using Model = fcl::BVHModel<BV>;
  FclPeer(PeerKind kind, const CollisionScene& scene) : kind_(kind) {
    tool_ = build(scene.tool.positions, scene.tool.triangles);
    tissue_ = build(scene.tissue.positions, scene.tissue.triangles);
    tool_object_ = std::make_unique<fcl::CollisionObjectd>(tool_);
    tissue_object_ = std::make_unique<fcl::CollisionObjectd>(tissue_);
    points_.resize(scene.tissue.positions.size());
    request_ = fcl::CollisionRequestd(std::size_t{1} << 40, false);
  }
  PeerKind kind() const override { return kind_; }
  std::size_t count_pairs(std::span<const Vec3> tissue_positions) override {
    for (std::size_t i = 0; i < points_.size(); ++i) {
      points_[i] = fcl::Vector3d(tissue_positions[i].x(), tissue_positions[i].y(), tissue_positions[i].z());
    }
    tissue_->beginUpdateModel();
    tissue_->updateSubModel(points_);
    tissue_->endUpdateModel(true, true);
    tissue_object_->computeAABB();
    result_.clear();
    fcl::collide(tool_object_.get(), tissue_object_.get(), request_, result_);
    return result_.numContacts();
  }

 private:
  static std::shared_ptr<Model> build(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles) {
    std::vector<fcl::Vector3d> points;
    points.reserve(positions.size());
    for (const Vec3& p : positions) points.emplace_back(p.x(), p.y(), p.z());
    std::vector<fcl::Triangle> tris;
    tris.reserve(triangles.size());
    for (const Triangle& t : triangles) tris.emplace_back(t[0], t[1], t[2]);
    auto model = std::make_shared<Model>();
    model->beginModel(static_cast<int>(tris.size()), static_cast<int>(points.size()));
    model->addSubModel(points, tris);
    model->endModel();
    model->computeLocalAABB();
    return model;
  }

  PeerKind kind_;
  std::shared_ptr<Model> tool_, tissue_;
  std::unique_ptr<fcl::CollisionObjectd> tool_object_, tissue_object_;
  std::vector<fcl::Vector3d> points_;
  fcl::CollisionRequestd request_;
  fcl::CollisionResultd result_;
};
#endif

// ---- Bullet ---------------------------------------------------------------------------------

#ifdef TROCAR_HAVE_BULLET
/// A btTriangleIndexVertexArray over our arrays (no copy): int indices, btScalar positions with
/// the stride of Vec3 (Bullet is built in double precision when the float64 libraries exist).
class BulletMesh {
 public:
  explicit BulletMesh(const TriMesh& mesh) : indices_(3 * mesh.triangles.size()) {
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) indices_[3 * t + k] = static_cast<int>(mesh.triangles[t][k]);
    }
    btIndexedMesh part;
    part.m_numTriangles = static_cast<int>(mesh.triangles.size());
    part.m_triangleIndexBase = reinterpret_cast<const unsigned char*>(indices_.data());
    part.m_triangleIndexStride = 3 * static_cast<int>(sizeof(int));
    part.m_numVertices = static_cast<int>(mesh.positions.size());
    part.m_vertexStride = static_cast<int>(sizeof(Vec3));
    part.m_indexType = PHY_INTEGER;
#ifdef BT_USE_DOUBLE_PRECISION
    part.m_vertexType = PHY_DOUBLE;
#else
    // Single precision Bullet cannot read our doubles in place: keep a float copy.
    floats_.resize(3 * mesh.positions.size());
    part.m_vertexStride = 3 * static_cast<int>(sizeof(float));
    part.m_vertexType = PHY_FLOAT;
#endif
    array_.addIndexedMesh(part, PHY_INTEGER);
    set_positions(mesh.positions);
  }
  /// Points the mesh at this frame's positions.
  void set_positions(std::span<const Vec3> positions) {
#ifdef BT_USE_DOUBLE_PRECISION
    array_.getIndexedMeshArray()[0].m_vertexBase = reinterpret_cast<const unsigned char*>(positions.data());
#else
    for (std::size_t i = 0; i < positions.size(); ++i) {
      for (int k = 0; k < 3; ++k) floats_[3 * i + k] = static_cast<float>(positions[i][k]);
    }
    array_.getIndexedMeshArray()[0].m_vertexBase = reinterpret_cast<const unsigned char*>(floats_.data());
#endif
  }
  btTriangleIndexVertexArray& array() { return array_; }

 private:
  std::vector<int> indices_;
  std::vector<float> floats_;
  btTriangleIndexVertexArray array_;
};

/// btGImpactMeshShape for both meshes (margin 0); the tissue's is refitted every frame
/// (postUpdate, updateBound); btGImpactQuantizedBvh::find_collision gives the box-overlapping
/// triangle pairs (what btGImpactCollisionAlgorithm does first), and each pair is tested exactly
/// with the Möller test (intersect_triangles) so the pair set is comparable.
class BulletGimpactPeer final : public CollisionPeer {
 public:
  explicit BulletGimpactPeer(const CollisionScene& scene)
      : scene_(scene), tool_mesh_(scene.tool), tissue_mesh_(scene.tissue),
        tool_shape_(&tool_mesh_.array()), tissue_shape_(&tissue_mesh_.array()) {
    tool_shape_.setMargin(0);
    tissue_shape_.setMargin(0);
    tool_shape_.updateBound();
    tissue_shape_.updateBound();
  }
  PeerKind kind() const override { return PeerKind::kBulletGimpact; }
  std::size_t count_pairs(std::span<const Vec3> tissue_positions) override {
    tissue_mesh_.set_positions(tissue_positions);
    tissue_shape_.postUpdate();
    tissue_shape_.updateBound();
    pairs_.resize(0, GIM_PAIR(0, 0));  // keeps the capacity (clear() would free it)
    btTransform identity;
    identity.setIdentity();
    btGImpactBoxSet::find_collision(tool_shape_.getMeshPart(0)->getBoxSet(), identity,
                                    tissue_shape_.getMeshPart(0)->getBoxSet(), identity, pairs_);
    std::size_t count = 0;
    for (int i = 0; i < pairs_.size(); ++i) {
      const GIM_PAIR& p = pairs_[i];
      count += pair_intersects(scene_.tool, static_cast<std::size_t>(p.m_index1), tissue_positions,
                               scene_.tissue.triangles[static_cast<std::size_t>(p.m_index2)]);
    }
    return count;
  }

 private:
  const CollisionScene& scene_;
  BulletMesh tool_mesh_, tissue_mesh_;
  btGImpactMeshShape tool_shape_, tissue_shape_;
  btPairSet pairs_;
};

btDbvtVolume triangle_volume(const Vec3& a, const Vec3& b, const Vec3& c) {
  const btVector3 points[3] = {btVector3(a.x(), a.y(), a.z()), btVector3(b.x(), b.y(), b.z()),
                               btVector3(c.x(), c.y(), c.z())};
  return btDbvtVolume::FromPoints(points, 3);
}

/// btDbvt (Bullet's dynamic AABB tree, the one its btDbvtBroadphase uses) with one leaf per
/// triangle, built top-down once. Every frame the tissue tree is refitted: each leaf gets its
/// triangle's new box and the internal boxes are merged bottom-up (the tree's topology stays,
/// like our BVH; btDbvt::update() would remove and re-insert every moved leaf, several times
/// slower); then collideTT(tool, tissue) and the Möller test on each leaf pair.
class BulletDbvtPeer final : public CollisionPeer {
 public:
  explicit BulletDbvtPeer(const CollisionScene& scene) : scene_(scene) {
    insert_all(tool_tree_, scene.tool, nullptr);
    insert_all(tissue_tree_, scene.tissue, &tissue_leaves_);
    tool_tree_.optimizeTopDown();
    tissue_tree_.optimizeTopDown();
  }
  PeerKind kind() const override { return PeerKind::kBulletDbvt; }
  std::size_t count_pairs(std::span<const Vec3> tissue_positions) override {
    const std::vector<Triangle>& tris = scene_.tissue.triangles;
    for (std::size_t t = 0; t < tris.size(); ++t) {
      tissue_leaves_[t]->volume = triangle_volume(tissue_positions[tris[t][0]], tissue_positions[tris[t][1]],
                                                  tissue_positions[tris[t][2]]);
    }
    refit(tissue_tree_.m_root);
    Collector collector(scene_, tissue_positions);
    tissue_tree_.collideTTpersistentStack(tool_tree_.m_root, tissue_tree_.m_root, collector);
    return collector.count;
  }

 private:
  struct Collector : btDbvt::ICollide {
    Collector(const CollisionScene& s, std::span<const Vec3> p) : scene(s), tissue(p) {}
    void Process(const btDbvtNode* a, const btDbvtNode* b) override {
      const auto ta = reinterpret_cast<std::uintptr_t>(a->data);
      const auto tb = reinterpret_cast<std::uintptr_t>(b->data);
      count += pair_intersects(scene.tool, ta, tissue, scene.tissue.triangles[tb]);
    }
    const CollisionScene& scene;
    std::span<const Vec3> tissue;
    std::size_t count = 0;
  };

  /// Internal boxes from the children's, bottom-up (the leaves are set already).
  static void refit(btDbvtNode* node) {
    if (node == nullptr || node->isleaf()) return;
    refit(node->childs[0]);
    refit(node->childs[1]);
    Merge(node->childs[0]->volume, node->childs[1]->volume, node->volume);
  }

  static void insert_all(btDbvt& tree, const TriMesh& mesh, std::vector<btDbvtNode*>* leaves) {
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto [a, b, c] = mesh.corners(t);
      btDbvtNode* leaf = tree.insert(triangle_volume(a, b, c), reinterpret_cast<void*>(static_cast<std::uintptr_t>(t)));
      if (leaves != nullptr) leaves->push_back(leaf);
    }
  }

  const CollisionScene& scene_;
  btDbvt tool_tree_, tissue_tree_;
  std::vector<btDbvtNode*> tissue_leaves_;
};
#endif

}  // namespace

CollisionScene make_collision_scene(TriMesh tissue, TriMesh tool, const CollisionSceneSettings& settings) {
  if (tissue.triangles.empty()) throw Error("collision scene: the tissue mesh has no triangles");
  if (tool.triangles.empty()) throw Error("collision scene: the tool mesh has no triangles");
  CollisionScene scene;

  // The upper surface: the highest tissue vertex over the central half of the xy extent.
  const Aabb tb = tissue.bounds();
  const Vec3 centre = tb.center();
  const Vec3 half = 0.25 * tb.size();
  bool found = false;
  for (const Vec3& p : tissue.positions) {
    const bool central = std::abs(p.x() - centre.x()) <= half.x() && std::abs(p.y() - centre.y()) <= half.y();
    if (central && (!found || p.z() > scene.target.z())) {
      scene.target = p;
      found = true;
    }
  }
  if (!found) scene.target = *std::max_element(tissue.positions.begin(), tissue.positions.end(),
                                               [](const Vec3& a, const Vec3& b) { return a.z() < b.z(); });

  // The tool: longest axis pointing down at the tilt, lowest point `depth` below the target.
  const Aabb ob = tool.bounds();
  const Vec3 size = ob.size();
  int longest = 0;
  size.maxCoeff(&longest);
  const Real tilt = settings.tilt_degrees * std::numbers::pi / 180;
  const Vec3 axis = Vec3::Unit(longest);
  const Vec3 direction(std::cos(tilt), 0, -std::sin(tilt));
  const Mat3 rotation = Quat::FromTwoVectors(axis, direction).toRotationMatrix();
  const Vec3 tool_centre = ob.center();
  for (Vec3& p : tool.positions) p = rotation * (p - tool_centre);
  tool.normals.clear();
  const Vec3 lowest = *std::min_element(tool.positions.begin(), tool.positions.end(),
                                        [](const Vec3& a, const Vec3& b) { return a.z() < b.z(); });
  const Real depth = settings.depth_fraction * size.minCoeff();
  const Vec3 shift = scene.target - Vec3(0, 0, depth) - lowest;
  for (Vec3& p : tool.positions) p += shift;

  scene.amplitude = settings.amplitude_fraction * mean_edge_length(tissue);
  scene.phases.resize(tissue.positions.size());
  for (std::size_t i = 0; i < scene.phases.size(); ++i) {
    for (int k = 0; k < 3; ++k) scene.phases[i][k] = 2 * std::numbers::pi * unit_hash(3 * i + static_cast<std::size_t>(k));
  }
  scene.tissue = std::move(tissue);
  scene.tool = std::move(tool);
  return scene;
}

void tissue_frame(const CollisionScene& scene, std::size_t frame, std::vector<Vec3>& out) {
  const std::vector<Vec3>& rest = scene.tissue.positions;
  out.resize(rest.size());
  const Real f = static_cast<Real>(frame);
  const Vec3 speed(0.9 * f, 1.3 * f, 1.7 * f);
  for (std::size_t i = 0; i < rest.size(); ++i) {
    const Vec3& ph = scene.phases[i];
    out[i] = rest[i] + scene.amplitude * Vec3(std::sin(ph.x() + speed.x()), std::sin(ph.y() + speed.y()),
                                              std::sin(ph.z() + speed.z()));
  }
}

std::size_t reference_pair_count(const CollisionScene& scene, std::span<const Vec3> tissue_positions) {
  const TriMesh& tool = scene.tool;
  std::vector<Aabb> tool_boxes(tool.triangles.size());
  Aabb tool_box;
  for (std::size_t t = 0; t < tool.triangles.size(); ++t) {
    const auto [a, b, c] = tool.corners(t);
    tool_boxes[t] = inflated_triangle_box(a, b, c);
    tool_box.expand(tool_boxes[t]);
  }
  std::size_t count = 0;
  for (const Triangle& tri : scene.tissue.triangles) {
    const Aabb box = inflated_triangle_box(tissue_positions[tri[0]], tissue_positions[tri[1]], tissue_positions[tri[2]]);
    if (!box.overlaps(tool_box)) continue;
    for (std::size_t t = 0; t < tool.triangles.size(); ++t) {
      if (box.overlaps(tool_boxes[t]) && pair_intersects(tool, t, tissue_positions, tri)) ++count;
    }
  }
  return count;
}

std::vector<PeerKind> all_peer_kinds() {
  return {PeerKind::kOhc,       PeerKind::kBvh,           PeerKind::kBrute,     PeerKind::kFclAabb,
          PeerKind::kFclObbrss, PeerKind::kBulletGimpact, PeerKind::kBulletDbvt};
}

const char* peer_name(PeerKind kind) {
  switch (kind) {
    case PeerKind::kOhc: return "ohc";
    case PeerKind::kBvh: return "bvh";
    case PeerKind::kBrute: return "brute";
    case PeerKind::kFclAabb: return "fcl-aabb";
    case PeerKind::kFclObbrss: return "fcl-obbrss";
    case PeerKind::kBulletGimpact: return "bullet-gimpact";
    case PeerKind::kBulletDbvt: return "bullet-dbvt";
  }
  return "?";
}

bool peer_available(PeerKind kind) {
  switch (kind) {
    case PeerKind::kFclAabb:
    case PeerKind::kFclObbrss:
#ifdef TROCAR_HAVE_FCL
      return true;
#else
      return false;
#endif
    case PeerKind::kBulletGimpact:
    case PeerKind::kBulletDbvt:
#ifdef TROCAR_HAVE_BULLET
      return true;
#else
      return false;
#endif
    default:
      return true;
  }
}

bool peer_practical(PeerKind kind, std::size_t tissue_triangles, std::size_t tool_triangles) {
  if (kind == PeerKind::kBrute) return static_cast<double>(tissue_triangles) * static_cast<double>(tool_triangles) <= 1e7;
  if (kind == PeerKind::kFclObbrss) return tissue_triangles <= 100000;
  return true;
}

std::unique_ptr<CollisionPeer> make_peer(PeerKind kind, const CollisionScene& scene) {
  switch (kind) {
    case PeerKind::kOhc: return std::make_unique<TrocarPeer>(kind, BroadPhaseKind::kOhc, scene);
    case PeerKind::kBvh: return std::make_unique<TrocarPeer>(kind, BroadPhaseKind::kBvh, scene);
    case PeerKind::kBrute: return std::make_unique<TrocarPeer>(kind, BroadPhaseKind::kBruteForce, scene);
#ifdef TROCAR_HAVE_FCL
    case PeerKind::kFclAabb: return std::make_unique<FclPeer<fcl::AABBd>>(kind, scene);
    case PeerKind::kFclObbrss: return std::make_unique<FclPeer<fcl::OBBRSSd>>(kind, scene);
#endif
#ifdef TROCAR_HAVE_BULLET
    case PeerKind::kBulletGimpact: return std::make_unique<BulletGimpactPeer>(scene);
    case PeerKind::kBulletDbvt: return std::make_unique<BulletDbvtPeer>(scene);
#endif
    default: break;
  }
  throw Error(std::string("collision peer '") + peer_name(kind) + "' was not compiled in");
}

std::string peers_build_info() {
  std::string info;
#ifdef TROCAR_HAVE_FCL
  info += "fcl: yes";
#else
  info += "fcl: no";
#endif
#ifdef TROCAR_HAVE_BULLET
#ifdef BT_USE_DOUBLE_PRECISION
  info += ", bullet: yes (double)";
#else
  info += ", bullet: yes (float)";
#endif
#else
  info += ", bullet: no";
#endif
  return info;
}

}  // namespace trocar
