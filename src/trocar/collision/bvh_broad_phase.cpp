#include "trocar/collision/bvh_broad_phase.h"

namespace trocar {

void BvhBroadPhase::refit(ObjectTree& t, const CollisionObject& object) {
  t.boxes.resize(object.triangles.size());
  const Vec3* p = object.positions.data();
  for (std::size_t k = 0; k < object.triangles.size(); ++k) {
    const Triangle& tri = object.triangles[k];
    t.boxes[k] = triangle_box(p[tri[0]], p[tri[1]], p[tri[2]]);
  }
  const bool same = t.triangles == object.triangles.data() && t.triangle_count == object.triangles.size() &&
                    t.vertex_count == object.positions.size() && t.tree.item_count() == t.boxes.size();
  if (same) {
    t.tree.refit(t.boxes);
  } else {
    t.tree.build(t.boxes);  // first frame or a different object: build (allocates)
    t.triangles = object.triangles.data();
    t.triangle_count = object.triangles.size();
    t.vertex_count = object.positions.size();
  }
  t.refitted = true;
}

void BvhBroadPhase::find_pairs(std::span<const CollisionObject> objects, std::vector<CandidatePair>& out) {
  out.clear();
  node_tests_ = 0;
  const auto n = static_cast<std::uint32_t>(objects.size());
  if (trees_.size() < n) trees_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) trees_[i].refitted = false;
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = i + 1; j < n; ++j) {
      if (!tested(objects[i].role, objects[j].role)) continue;
      if (objects[i].triangles.empty() || objects[j].triangles.empty()) continue;
      const bool i_first = object_first(objects[i].role, i, objects[j].role, j);
      const std::uint32_t oa = i_first ? i : j;
      const std::uint32_t ob = i_first ? j : i;
      ObjectTree& ta = trees_[oa];
      ObjectTree& tb = trees_[ob];
      // Refit lazily: objects that overlap nobody are never touched beyond their box.
      if (!ta.refitted) refit(ta, objects[oa]);
      if (!tb.refitted) refit(tb, objects[ob]);
      const auto na = ta.tree.nodes();
      const auto nb = tb.tree.nodes();
      const auto ia = ta.tree.items();
      const auto ib = tb.tree.items();
      stack_.clear();
      ++node_tests_;
      if (na[0].box.overlaps(nb[0].box)) stack_.push_back({0, 0});
      while (!stack_.empty()) {
        const NodePair np = stack_.back();
        stack_.pop_back();
        const AabbTree::Node& a = na[np.a];
        const AabbTree::Node& b = nb[np.b];
        if (a.count > 0 && b.count > 0) {
          for (std::uint32_t x = a.first; x < a.first + a.count; ++x) {
            const Aabb& box_a = ta.boxes[ia[x]];
            for (std::uint32_t y = b.first; y < b.first + b.count; ++y) {
              if (box_a.overlaps(tb.boxes[ib[y]])) out.push_back({oa, ob, ia[x], ib[y]});
            }
          }
          continue;
        }
        // Descend into the inner node, or the larger one when both are inner.
        const bool split_a = b.count > 0 || (a.count == 0 && a.box.size().sum() >= b.box.size().sum());
        if (split_a) {
          for (std::uint32_t c = a.first; c < a.first + 2; ++c) {
            ++node_tests_;
            if (na[c].box.overlaps(b.box)) stack_.push_back({c, np.b});
          }
        } else {
          for (std::uint32_t c = b.first; c < b.first + 2; ++c) {
            ++node_tests_;
            if (a.box.overlaps(nb[c].box)) stack_.push_back({np.a, c});
          }
        }
      }
    }
  }
}

}  // namespace trocar
