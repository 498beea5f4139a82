#include "trocar/geometry/aabb_tree.h"

#include <algorithm>
#include <numeric>
#include <string>

#include "trocar/core/error.h"

namespace trocar {

void AabbTree::build(std::span<const Aabb> item_boxes) {
  nodes_.clear();
  items_.resize(item_boxes.size());
  std::iota(items_.begin(), items_.end(), std::uint32_t{0});
  if (item_boxes.empty()) return;
  std::vector<Vec3> centroids(item_boxes.size());
  for (std::size_t i = 0; i < item_boxes.size(); ++i) centroids[i] = item_boxes[i].center();
  nodes_.reserve(2 * item_boxes.size());
  nodes_.emplace_back();
  build_node(0, 0, static_cast<std::uint32_t>(item_boxes.size()), item_boxes, centroids);
}

void AabbTree::build_node(std::uint32_t index, std::uint32_t begin, std::uint32_t end,
                          std::span<const Aabb> boxes, const std::vector<Vec3>& centroids) {
  Aabb box;
  Aabb centre_box;
  for (std::uint32_t i = begin; i < end; ++i) {
    box.expand(boxes[items_[i]]);
    centre_box.expand(centroids[items_[i]]);
  }
  if (end - begin <= kLeafSize) {
    nodes_[index] = {box, begin, end - begin};
    return;
  }
  // Median split along the longest axis of the centroids' bounds; ties broken by item id so the
  // tree is the same on every platform.
  Eigen::Index axis = 0;
  centre_box.size().maxCoeff(&axis);
  const std::uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(items_.begin() + begin, items_.begin() + mid, items_.begin() + end,
                   [&](std::uint32_t x, std::uint32_t y) {
                     const Real cx = centroids[x][axis];
                     const Real cy = centroids[y][axis];
                     return cx < cy || (cx == cy && x < y);
                   });
  const auto left = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  nodes_.emplace_back();
  nodes_[index] = {box, left, 0};
  build_node(left, begin, mid, boxes, centroids);
  build_node(left + 1, mid, end, boxes, centroids);
}

void AabbTree::refit(std::span<const Aabb> item_boxes) {
  if (item_boxes.size() != items_.size()) {
    throw Error("AabbTree::refit: got " + std::to_string(item_boxes.size()) +
                " item boxes, but the tree was built over " + std::to_string(items_.size()));
  }
  // Children are stored after their parent, so a reverse sweep sees children first. A node's
  // box starts from its first item or child instead of the empty box (one merge fewer).
  for (std::size_t k = nodes_.size(); k-- > 0;) {
    Node& n = nodes_[k];
    if (n.count > 0) {
      Vec3 lo = item_boxes[items_[n.first]].min;
      Vec3 hi = item_boxes[items_[n.first]].max;
      for (std::uint32_t i = n.first + 1; i < n.first + n.count; ++i) {
        lo = lo.cwiseMin(item_boxes[items_[i]].min);
        hi = hi.cwiseMax(item_boxes[items_[i]].max);
      }
      n.box = Aabb{lo, hi};
    } else {
      const Aabb& l = nodes_[n.first].box;
      const Aabb& r = nodes_[n.first + 1].box;
      n.box = Aabb{l.min.cwiseMin(r.min), l.max.cwiseMax(r.max)};
    }
  }
}

}  // namespace trocar
