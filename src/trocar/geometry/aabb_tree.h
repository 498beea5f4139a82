#pragma once
/// A static bounding-volume hierarchy of axis-aligned boxes, refittable for deforming meshes.
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "trocar/core/aabb.h"
#include "trocar/core/types.h"

namespace trocar {

/// Binary tree over items given by their boxes (e.g. one box per triangle). Built once by median
/// splits of the item centroids along the longest axis of their bounds (so the depth is at most
/// ⌈log2(n)⌉ + 1); the topology is then fixed and refit() only recomputes the boxes, bottom-up,
/// for items that moved (deforming tissue). Nodes are stored flat, children after their parent.
class AabbTree {
 public:
  /// Most items in one leaf.
  static constexpr std::uint32_t kLeafSize = 4;
  /// Bound on the traversal stack (depth ≤ 33 for 2³² items, so never reached).
  static constexpr std::size_t kMaxStack = 64;

  /// One node: a leaf holds items()[first, first + count); an inner node (count = 0) has its
  /// children at nodes()[first] and nodes()[first + 1].
  struct Node {
    Aabb box;                 ///< bounds of every item below (item units)
    std::uint32_t first = 0;  ///< first item (leaf) or left child (inner node)
    std::uint32_t count = 0;  ///< number of items in a leaf; 0 for an inner node
  };

  AabbTree() = default;
  /// Builds the tree over item_boxes (item i has box item_boxes[i]).
  explicit AabbTree(std::span<const Aabb> item_boxes) { build(item_boxes); }

  /// Rebuilds from scratch (allocates).
  void build(std::span<const Aabb> item_boxes);
  /// Recomputes every node box from new item boxes, keeping the topology; no allocation. The
  /// number of items must equal the one built with (throws trocar::Error otherwise).
  void refit(std::span<const Aabb> item_boxes);

  std::span<const Node> nodes() const { return nodes_; }            ///< nodes, root first
  std::span<const std::uint32_t> items() const { return items_; }  ///< item ids in leaf order
  bool empty() const { return nodes_.empty(); }                     ///< built over no items
  std::size_t item_count() const { return items_.size(); }          ///< items built with

  /// Squared distance from p to box (0 inside), in item units squared.
  static Real distance_squared(const Aabb& box, const Vec3& p) {
    const Vec3 below = (box.min - p).cwiseMax(0.0);
    const Vec3 above = (p - box.max).cwiseMax(0.0);
    return (below + above).squaredNorm();
  }

  /// Nearest-item search: visits, nearer child first, every leaf whose box is closer to p than
  /// best_squared, calling item_distance(item, best_squared) for each of its items; the callback
  /// lowers best_squared when it finds a closer item. No allocation (fixed stack).
  template <class ItemDistance>
  void nearest(const Vec3& p, Real& best_squared, ItemDistance&& item_distance) const;

  /// Squared distance between two boxes (0 when they overlap), in item units squared.
  static Real distance_squared(const Aabb& a, const Aabb& b) {
    const Vec3 below = (a.min - b.max).cwiseMax(0.0);
    const Vec3 above = (b.min - a.max).cwiseMax(0.0);
    return (below + above).squaredNorm();
  }

  /// Calls visit(item) for every item in a leaf whose box is nearer to `region` than
  /// √radius_squared (squared box–box distance < radius_squared). No allocation (fixed stack).
  template <class Visit>
  void for_each_near(const Aabb& region, Real radius_squared, Visit&& visit) const;

 private:
  void build_node(std::uint32_t index, std::uint32_t begin, std::uint32_t end,
                  std::span<const Aabb> boxes, const std::vector<Vec3>& centroids);

  std::vector<Node> nodes_;
  std::vector<std::uint32_t> items_;
};

template <class ItemDistance>
void AabbTree::nearest(const Vec3& p, Real& best_squared, ItemDistance&& item_distance) const {
  if (nodes_.empty()) return;
  struct Entry {
    std::uint32_t node;
    Real d2;
  };
  // Depth-first, nearer child first: the walk goes straight down the nearer child and stacks the
  // farther one. The pushes are branch-free (write, then advance when the child is within the
  // bound): whether a child is kept is data-dependent, and mispredicted branches there were most
  // of a query's time. The stack holds at most one entry per level, so depth ≤ 33 fits.
  std::array<Entry, kMaxStack> stack;
  std::size_t top = 0;
  stack[top++] = {0, distance_squared(nodes_[0].box, p)};
  while (top > 0) {
    const Entry e = stack[--top];
    if (!(e.d2 < best_squared)) continue;
    std::uint32_t node = e.node;
    for (;;) {
      const Node& n = nodes_[node];
      if (n.count > 0) {
        for (std::uint32_t i = n.first; i < n.first + n.count; ++i) item_distance(items_[i], best_squared);
        break;
      }
      const Real dl = distance_squared(nodes_[n.first].box, p);
      const Real dr = distance_squared(nodes_[n.first + 1].box, p);
      const bool left_nearer = dl <= dr;
      const std::uint32_t near = left_nearer ? n.first : n.first + 1;
      const Real near_d2 = left_nearer ? dl : dr;
      stack[top] = {left_nearer ? n.first + 1 : n.first, left_nearer ? dr : dl};
      top += stack[top].d2 < best_squared ? 1 : 0;
      if (!(near_d2 < best_squared)) break;
      node = near;
    }
  }
}

template <class Visit>
void AabbTree::for_each_near(const Aabb& region, Real radius_squared, Visit&& visit) const {
  if (nodes_.empty() || !(distance_squared(nodes_[0].box, region) < radius_squared)) return;
  std::array<std::uint32_t, kMaxStack> stack;
  std::size_t top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (n.count > 0) {
      for (std::uint32_t i = n.first; i < n.first + n.count; ++i) visit(items_[i]);
      continue;
    }
    // Children are tested before they are stacked, so the stack holds one entry per level.
    for (std::uint32_t c = n.first; c < n.first + 2; ++c) {
      stack[top] = c;
      top += distance_squared(nodes_[c].box, region) < radius_squared ? 1 : 0;
    }
  }
}

}  // namespace trocar
