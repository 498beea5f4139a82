// VRML97 reader: parses the scene (vrml_parser.h) and expands it into one mesh.
//
// Every IndexedFaceSet reached from the top-level nodes is instantiated once per path that
// reaches it (a USE'd Shape under a second Transform appears twice), its Coordinate points are
// transformed by the product of the Transforms above it and appended in file order, and its
// polygons are fan-triangulated. For an untransformed set the positions are the file's
// numbers, unchanged. Expansion is bounded (depth and a work budget proportional to the file
// size), so nested USE chains cannot blow up exponentially.
#include <limits>

#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/io/vrml_parser.h"

namespace trocar {
namespace {

using vrml::Node;

class Expander {
 public:
  Expander(std::size_t file_size, const std::string& name)
      : budget_(64 * static_cast<std::uint64_t>(file_size) + 1000000), name_(name) {}

  void visit(const Node& node, const Eigen::Affine3d& m, bool identity, int depth) {
    if (depth > vrml::kMaxDepth)
      throw FileError(name_, FileLocation::line(node.line),
                      "scene nested deeper than " + std::to_string(vrml::kMaxDepth) + " nodes through USE");
    spend(1, node);
    switch (node.kind) {
      case Node::Kind::kTransform: {
        const Eigen::Affine3d child_m = identity ? node.transform : m * node.transform;
        for (const vrml::NodePtr& c : node.children)
          if (c) visit(*c, child_m, identity && node.identity, depth + 1);
        return;
      }
      case Node::Kind::kGroup:
        for (const vrml::NodePtr& c : node.children)
          if (c) visit(*c, m, identity, depth + 1);
        return;
      case Node::Kind::kSwitch:
        if (node.which_choice >= 0 && static_cast<std::size_t>(node.which_choice) < node.children.size() &&
            node.children[static_cast<std::size_t>(node.which_choice)])
          visit(*node.children[static_cast<std::size_t>(node.which_choice)], m, identity, depth + 1);
        return;
      case Node::Kind::kShape:
        if (node.geometry && node.geometry->kind == Node::Kind::kFaceSet) emit(*node.geometry, m, identity);
        return;
      case Node::Kind::kFaceSet:      // only drawn inside a Shape
      case Node::Kind::kCoordinate:
        return;
    }
  }

  TriMesh take() { return std::move(mesh_); }

 private:
  void spend(std::uint64_t amount, const Node& node) {
    if (amount > budget_)
      throw FileError(name_, FileLocation::line(node.line),
                      "scene expands to too much geometry for its size (USE nested too often?)");
    budget_ -= amount;
  }

  void emit(const Node& face_set, const Eigen::Affine3d& m, bool identity) {
    if (!face_set.coord) return;
    const std::vector<Vec3>& points = face_set.coord->points;
    spend(points.size() + face_set.coord_index.size(), face_set);
    const std::size_t base = mesh_.positions.size();
    if (points.size() > std::numeric_limits<std::uint32_t>::max() - base)
      throw FileError(name_, FileLocation::line(face_set.line), "too many vertices");
    for (const Vec3& p : points) mesh_.positions.push_back(identity ? p : Vec3(m * p));
    // A mirroring transform turns the surface inside out; flip to keep the outside outside.
    const bool flip = !face_set.ccw != (!identity && m.linear().determinant() < 0);
    std::size_t start = 0;
    const std::vector<std::int32_t>& idx = face_set.coord_index;
    for (std::size_t i = 0; i <= idx.size(); ++i) {
      if (i < idx.size() && idx[i] >= 0) continue;
      // polygon idx[start, i)
      for (std::size_t k = start + 2; k < i; ++k) {
        const auto a = static_cast<std::uint32_t>(base + static_cast<std::size_t>(idx[start]));
        const auto b = static_cast<std::uint32_t>(base + static_cast<std::size_t>(idx[k - 1]));
        const auto c = static_cast<std::uint32_t>(base + static_cast<std::size_t>(idx[k]));
        if (flip) mesh_.triangles.push_back({a, c, b});
        else mesh_.triangles.push_back({a, b, c});
      }
      start = i + 1;
    }
  }

  std::uint64_t budget_;
  const std::string& name_;
  TriMesh mesh_;
};

}  // namespace

TriMesh read_vrml(std::string_view bytes, const std::string& name) {
  const std::vector<vrml::NodePtr> roots = vrml::parse_scene(bytes, name);
  Expander expander(bytes.size(), name);
  for (const vrml::NodePtr& root : roots)
    if (root) expander.visit(*root, Eigen::Affine3d::Identity(), true, 1);
  TriMesh mesh = expander.take();
  if (mesh.triangles.empty())
    throw FileError(name, FileLocation::none(),
                    "no IndexedFaceSet with faces found (primitives such as Box or Sphere are not read)");
  return mesh;
}

}  // namespace trocar
