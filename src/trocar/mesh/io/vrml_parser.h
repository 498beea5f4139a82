#pragma once
/// VRML97 scene parser for the mesh reader: builds the part of the scene graph that carries
/// triangle geometry (grouping nodes, Transform, Switch, Shape, IndexedFaceSet, Coordinate).
/// Everything else is parsed structurally and dropped. DEF/USE share nodes, so the result is
/// a DAG; USE of a name refers to the node DEF'd before it (no cycles are possible).
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "trocar/core/types.h"

namespace trocar::vrml {

/// Deepest node nesting accepted, both in the file and through USE when the scene is expanded.
inline constexpr int kMaxDepth = 256;

struct Node;
/// Nodes are shared between their DEF and every USE.
using NodePtr = std::shared_ptr<const Node>;

/// One parsed node of a kind that matters for geometry.
struct Node {
  enum class Kind { kGroup, kTransform, kSwitch, kShape, kFaceSet, kCoordinate };
  Kind kind = Kind::kGroup;
  std::uint64_t line = 0;          ///< line of the node's type name
  std::vector<NodePtr> children;   ///< grouping nodes' children, Switch's choice (may hold nulls)
  int which_choice = -1;           ///< Switch only
  Eigen::Affine3d transform = Eigen::Affine3d::Identity();  ///< Transform only: child → parent
  bool identity = true;            ///< Transform only: transform is exactly the identity
  NodePtr geometry;                ///< Shape only
  NodePtr coord;                   ///< IndexedFaceSet only: a kCoordinate node or null
  std::vector<std::int32_t> coord_index;  ///< IndexedFaceSet only: validated against coord
  bool ccw = true;                 ///< IndexedFaceSet only
  std::vector<Vec3> points;        ///< Coordinate only
};

/// Parses a whole VRML97 file into its top-level nodes (those that matter for geometry).
/// Throws FileError with the line for malformed input.
std::vector<NodePtr> parse_scene(std::string_view bytes, const std::string& name);

}  // namespace trocar::vrml
