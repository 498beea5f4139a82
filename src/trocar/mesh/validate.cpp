#include "trocar/mesh/validate.h"

#include <algorithm>
#include <cmath>

#include "trocar/mesh/repair.h"
#include "trocar/mesh/topology.h"

namespace trocar {
namespace {

bool finite(const Vec3& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

const char* orientation_name(Orientation orientation) {
  switch (orientation) {
    case Orientation::kOutward: return "outward";
    case Orientation::kInward: return "inward";
    case Orientation::kUndefined: break;
  }
  return "undefined";
}

std::vector<std::string> MeshReport::defects() const {
  std::vector<std::string> out;
  auto add = [&](std::size_t n, const char* one, const char* many) {
    if (n != 0) out.push_back(plural(n, one, many));
  };
  if (triangles == 0) out.push_back("no triangles");
  add(out_of_range_triangles, "triangle with an out-of-range index", "triangles with an out-of-range index");
  add(nonfinite_vertices, "vertex with a non-finite coordinate", "vertices with a non-finite coordinate");
  add(boundary_edges, "boundary edge (open surface)", "boundary edges (open surface)");
  add(nonmanifold_edges, "non-manifold edge (more than 2 triangles)", "non-manifold edges (more than 2 triangles)");
  add(nonmanifold_vertices, "non-manifold vertex (more than one fan)", "non-manifold vertices (more than one fan)");
  add(degenerate_triangles, "degenerate triangle", "degenerate triangles");
  add(duplicate_triangles, "duplicate triangle", "duplicate triangles");
  add(duplicate_vertices, "duplicate vertex (same position as an earlier one)", "duplicate vertices (same position as an earlier one)");
  add(near_duplicate_vertices, "near-duplicate vertex", "near-duplicate vertices");
  add(unused_vertices, "unused vertex", "unused vertices");
  add(inconsistent_edges, "inconsistently wound edge", "inconsistently wound edges");
  if (closed && inconsistent_edges == 0 && orientation == Orientation::kInward)
    out.push_back("inside out (negative volume)");
  return out;
}

bool MeshReport::is_clean_open() const {
  return triangles > 0 && out_of_range_triangles == 0 && nonfinite_vertices == 0 &&
         nonmanifold_edges == 0 && nonmanifold_vertices == 0 && degenerate_triangles == 0 &&
         duplicate_triangles == 0 && duplicate_vertices == 0 && near_duplicate_vertices == 0 &&
         unused_vertices == 0 && inconsistent_edges == 0 && orientation != Orientation::kInward;
}

bool MeshReport::is_clean() const {
  return is_clean_open() && closed && boundary_edges == 0 && orientation == Orientation::kOutward;
}

MeshReport validate(const TriMesh& mesh, const ValidateOptions& options) {
  MeshReport r;
  r.vertices = mesh.positions.size();
  r.triangles = mesh.triangles.size();

  // 1. Indices and coordinates, before anything indexes with them.
  std::vector<char> vertex_ok(r.vertices, 1);
  for (std::size_t v = 0; v < r.vertices; ++v)
    if (!finite(mesh.positions[v])) {
      vertex_ok[v] = 0;
      ++r.nonfinite_vertices;
    } else {
      r.bounds.expand(mesh.positions[v]);
    }
  TriMesh sane;  // positions shared by copy only when something must be left out
  const TriMesh* m = &mesh;
  {
    std::vector<std::size_t> keep;
    bool all = true;
    for (std::size_t t = 0; t < r.triangles; ++t) {
      const Triangle& tri = mesh.triangles[t];
      if (tri[0] >= r.vertices || tri[1] >= r.vertices || tri[2] >= r.vertices) {
        ++r.out_of_range_triangles;
        all = false;
      } else if (!vertex_ok[tri[0]] || !vertex_ok[tri[1]] || !vertex_ok[tri[2]]) {
        ++r.nonfinite_triangles;
        all = false;
      } else {
        keep.push_back(t);
      }
    }
    if (!all) {
      sane.positions = mesh.positions;
      sane.triangles.reserve(keep.size());
      for (std::size_t t : keep) sane.triangles.push_back(mesh.triangles[t]);
      m = &sane;
    }
  }
  const std::vector<Triangle>& tris = m->triangles;

  // 2. Geometry: area, volume about the box centre (accurate far from the origin),
  //    degenerate triangles.
  const Real diagonal = r.bounds.diagonal();
  const Real min_area = std::pow(options.degenerate_area_rel * diagonal, 2);
  const Vec3 origin = r.bounds.is_empty() ? Vec3::Zero() : r.bounds.center();
  Real volume6 = 0;
  for (const Triangle& tri : tris) {
    const Vec3 a = m->positions[tri[0]] - origin;
    const Vec3 b = m->positions[tri[1]] - origin;
    const Vec3 c = m->positions[tri[2]] - origin;
    const Real area = 0.5 * (b - a).cross(c - a).norm();
    r.area += area;
    volume6 += a.dot(b.cross(c));
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] || area < min_area) ++r.degenerate_triangles;
  }
  r.signed_volume = volume6 / 6.0;

  // 3. Duplicate triangles: sorted index triples, sorted; extra copies counted.
  {
    std::vector<Triangle> keys(tris);
    for (Triangle& k : keys) std::sort(k.begin(), k.end());
    std::sort(keys.begin(), keys.end());
    for (std::size_t i = 1; i < keys.size(); ++i)
      if (keys[i] == keys[i - 1]) ++r.duplicate_triangles;
  }

  // 4. Duplicate and near-duplicate vertices.
  {
    const std::vector<std::uint32_t> exact = vertex_representatives(mesh.positions, 0);
    for (std::size_t v = 0; v < exact.size(); ++v)
      if (exact[v] != v) ++r.duplicate_vertices;
    r.near_duplicate_tolerance = options.near_duplicate_rel * diagonal;
    if (r.near_duplicate_tolerance > 0) {
      const std::vector<std::uint32_t> near = vertex_representatives(mesh.positions, r.near_duplicate_tolerance);
      for (std::size_t v = 0; v < near.size(); ++v)
        if (near[v] != v && exact[v] == v) ++r.near_duplicate_vertices;
    }
  }

  // 5. Topology.
  const MeshTopology topo(*m);
  r.edges = topo.edge_count();
  r.boundary_edges = topo.boundary_edges().size();
  r.nonmanifold_edges = topo.nonmanifold_edges().size();
  r.nonmanifold_vertices = topo.nonmanifold_vertices().size();
  r.unused_vertices = r.vertices - topo.used_vertex_count();
  r.components = topo.component_count();
  r.euler_characteristic = topo.euler_characteristic();
  for (std::size_t e = 0; e < topo.edge_count(); ++e) {
    const auto et = topo.edge_triangles(e);
    if (et.size() == 2 && et[0] != et[1] &&
        topo.traverses_forward(*m, et[0], e) == topo.traverses_forward(*m, et[1], e))
      ++r.inconsistent_edges;
  }
  r.closed = !tris.empty() && r.boundary_edges == 0 && r.nonmanifold_edges == 0 && r.degenerate_triangles == 0;
  r.manifold = r.nonmanifold_edges == 0 && r.nonmanifold_vertices == 0;
  if (r.closed && r.inconsistent_edges == 0 && r.signed_volume != 0)
    r.orientation = r.signed_volume > 0 ? Orientation::kOutward : Orientation::kInward;
  return r;
}

}  // namespace trocar
