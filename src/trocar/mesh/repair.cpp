#include "trocar/mesh/repair.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "trocar/mesh/topology.h"

namespace trocar {
namespace {

bool finite(const Vec3& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

/// Keeps the triangles with keep[t] != 0 (and their texcoords), in order; returns how many
/// were dropped.
std::size_t keep_triangles(TriMesh& mesh, const std::vector<char>& keep) {
  const bool tex = !mesh.texcoords.empty();
  std::size_t out = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!keep[t]) continue;
    if (out != t) {
      mesh.triangles[out] = mesh.triangles[t];
      if (tex)
        for (std::size_t k = 0; k < 3; ++k) mesh.texcoords[3 * out + k] = mesh.texcoords[3 * t + k];
    }
    ++out;
  }
  const std::size_t dropped = mesh.triangles.size() - out;
  mesh.triangles.resize(out);
  if (tex) mesh.texcoords.resize(3 * out);
  return dropped;
}

/// Reverses triangle t's winding by swapping corners 1 and 2 (and their texcoords).
void flip(TriMesh& mesh, std::size_t t) {
  std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
  if (!mesh.texcoords.empty()) std::swap(mesh.texcoords[3 * t + 1], mesh.texcoords[3 * t + 2]);
}

Real triangle_area(const TriMesh& mesh, std::size_t t) { return 0.5 * mesh.triangle_normal_area2(t).norm(); }

void drop_degenerate(TriMesh& mesh, Real min_area, RepairReport& report) {
  std::vector<char> keep(mesh.triangles.size(), 1);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] || triangle_area(mesh, t) < min_area) keep[t] = 0;
  }
  report.degenerate_removed = keep_triangles(mesh, keep);
}

void drop_duplicates(TriMesh& mesh, RepairReport& report) {
  struct Key {
    Triangle sorted;
    std::uint32_t t;
  };
  std::vector<Key> keys(mesh.triangles.size());
  for (std::size_t t = 0; t < keys.size(); ++t) {
    keys[t] = {mesh.triangles[t], static_cast<std::uint32_t>(t)};
    std::sort(keys[t].sorted.begin(), keys[t].sorted.end());
  }
  std::sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
    return a.sorted != b.sorted ? a.sorted < b.sorted : a.t < b.t;
  });
  std::vector<char> keep(mesh.triangles.size(), 1);
  for (std::size_t i = 1; i < keys.size(); ++i)
    if (keys[i].sorted == keys[i - 1].sorted) keep[keys[i].t] = 0;  // first occurrence stays
  report.duplicate_triangles_removed = keep_triangles(mesh, keep);
}

void drop_small_components(TriMesh& mesh, const RepairOptions& options, RepairReport& report) {
  const MeshTopology topo(mesh);
  const std::size_t n = topo.component_count();
  std::vector<Real> area(n, 0);
  Real total = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Real a = triangle_area(mesh, t);
    area[topo.triangle_component(t)] += a;
    total += a;
  }
  std::vector<char> drop_component(n, 0);
  for (std::size_t c = 0; c < n; ++c)
    if (topo.component_triangle_counts()[c] < options.min_component_triangles ||
        area[c] < options.min_component_area_fraction * total) {
      drop_component[c] = 1;
      ++report.components_removed;
    }
  std::vector<char> keep(mesh.triangles.size(), 1);
  for (std::size_t t = 0; t < keep.size(); ++t) keep[t] = !drop_component[topo.triangle_component(t)];
  report.component_triangles_removed = keep_triangles(mesh, keep);
}

/// BFS over edges with exactly two (distinct) triangles: each neighbour is flipped, if
/// needed, so that it traverses the shared edge opposite to the current triangle. Then,
/// optionally, every closed patch (all its edges interior) with negative volume is flipped.
void fix_winding(TriMesh& mesh, const RepairOptions& options, RepairReport& report) {
  const MeshTopology topo(mesh);
  const std::size_t n = mesh.triangles.size();
  constexpr std::uint32_t kUnseen = MeshTopology::kNone;
  std::vector<std::uint32_t> patch(n, kUnseen);
  std::vector<char> flipped(n, 0);
  std::vector<std::uint32_t> queue;
  queue.reserve(n);
  std::size_t patches = 0;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (patch[seed] != kUnseen) continue;
    const auto id = static_cast<std::uint32_t>(patches++);
    patch[seed] = id;
    queue.assign(1, static_cast<std::uint32_t>(seed));
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const std::uint32_t t = queue[head];
      for (std::uint32_t e : topo.triangle_edges(t)) {
        if (e == MeshTopology::kNone || !options.make_winding_consistent) continue;
        const auto et = topo.edge_triangles(e);
        if (et.size() != 2 || et[0] == et[1]) continue;
        const std::uint32_t u = et[0] == t ? et[1] : et[0];
        if (patch[u] != kUnseen) continue;
        const bool t_forward = topo.traverses_forward(mesh, t, e) != static_cast<bool>(flipped[t]);
        flipped[u] = topo.traverses_forward(mesh, u, e) == t_forward;
        patch[u] = id;
        queue.push_back(u);
      }
    }
  }
  report.patches = options.make_winding_consistent ? patches : 0;
  if (options.orient_outward) {
    // Volume of each patch about the box centre (exact for closed patches wherever the
    // origin is; the centre keeps a·(b×c) accurate for meshes far from 0), and whether all
    // of its edges are interior.
    const Aabb box = mesh.bounds();
    const Vec3 origin = box.is_empty() ? Vec3::Zero() : box.center();
    std::vector<Real> volume6(patches, 0);
    std::vector<char> closed(patches, 1);
    for (std::size_t t = 0; t < n; ++t) {
      const Triangle& tri = mesh.triangles[t];
      const Vec3 a = mesh.positions[tri[0]] - origin;
      Vec3 b = mesh.positions[tri[1]] - origin;
      Vec3 c = mesh.positions[tri[2]] - origin;
      if (flipped[t]) std::swap(b, c);
      volume6[patch[t]] += a.dot(b.cross(c));
      for (std::uint32_t e : topo.triangle_edges(t))
        if (e == MeshTopology::kNone || topo.edge_valence(e) != 2) closed[patch[t]] = 0;
    }
    for (std::size_t p = 0; p < patches; ++p)
      if (closed[p] && volume6[p] < 0) ++report.patches_flipped_outward;
    for (std::size_t t = 0; t < n; ++t)
      if (closed[patch[t]] && volume6[patch[t]] < 0) flipped[t] = !flipped[t];
  }
  for (std::size_t t = 0; t < n; ++t)
    if (flipped[t]) flip(mesh, t);
  report.triangles_flipped = static_cast<std::size_t>(std::count(flipped.begin(), flipped.end(), 1));
}

void drop_unused(TriMesh& mesh, RepairReport& report) {
  const std::size_t n = mesh.positions.size();
  std::vector<std::uint32_t> remap(n, MeshTopology::kNone);
  for (const Triangle& tri : mesh.triangles)
    for (std::uint32_t v : tri) remap[v] = 0;
  const bool normals = !mesh.normals.empty();
  std::uint32_t out = 0;
  for (std::size_t v = 0; v < n; ++v) {
    if (remap[v] == MeshTopology::kNone) continue;
    remap[v] = out;
    mesh.positions[out] = mesh.positions[v];
    if (normals) mesh.normals[out] = mesh.normals[v];
    ++out;
  }
  report.unused_vertices_removed = n - out;
  mesh.positions.resize(out);
  if (normals) mesh.normals.resize(out);
  for (Triangle& tri : mesh.triangles)
    for (std::uint32_t& v : tri) v = remap[v];
}

}  // namespace

bool RepairReport::changed() const {
  return invalid_triangles_removed || vertices_merged || degenerate_removed || duplicate_triangles_removed ||
         component_triangles_removed || triangles_flipped || patches_flipped_outward ||
         unused_vertices_removed || normals_dropped || texcoords_dropped;
}

std::vector<std::string> RepairReport::summary() const {
  std::vector<std::string> out;
  auto line = [&](std::size_t n, const std::string& text) {
    if (n != 0) out.push_back(std::to_string(n) + " " + text);
  };
  line(invalid_triangles_removed, "triangles with out-of-range indices or non-finite corners removed");
  if (vertices_merged != 0) {
    std::ostringstream s;
    s << vertices_merged << " vertices merged (tolerance " << merge_tolerance << ")";
    out.push_back(s.str());
  }
  line(degenerate_removed, "degenerate triangles removed");
  line(duplicate_triangles_removed, "duplicate triangles removed");
  if (components_removed != 0)
    out.push_back(std::to_string(components_removed) + " small components removed (" +
                  std::to_string(component_triangles_removed) + " triangles)");
  line(triangles_flipped, "triangles flipped");
  line(patches_flipped_outward, "closed patches turned outward");
  line(unused_vertices_removed, "unused vertices removed");
  if (normals_dropped) out.push_back("normals dropped (count did not match the vertices)");
  if (texcoords_dropped) out.push_back("texcoords dropped (count did not match 3 per triangle)");
  return out;
}

RepairReport repair(TriMesh& mesh, const RepairOptions& options) {
  RepairReport report;
  report.vertices_before = mesh.positions.size();
  report.triangles_before = mesh.triangles.size();
  if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size()) {
    mesh.normals.clear();
    report.normals_dropped = true;
  }
  if (!mesh.texcoords.empty() && mesh.texcoords.size() != 3 * mesh.triangles.size()) {
    mesh.texcoords.clear();
    report.texcoords_dropped = true;
  }

  // Invalid triangles go first, whatever the options: nothing below can index with them.
  {
    const std::size_t n = mesh.positions.size();
    std::vector<char> keep(mesh.triangles.size(), 1);
    for (std::size_t t = 0; t < keep.size(); ++t)
      for (std::uint32_t v : mesh.triangles[t])
        if (v >= n || !finite(mesh.positions[v])) keep[t] = 0;
    const std::size_t bad = static_cast<std::size_t>(std::count(keep.begin(), keep.end(), 0));
    if (bad != 0 && !options.drop_invalid_triangles) {
      // Without the drop the other steps cannot run safely; leave the mesh as it is.
      report.vertices_after = mesh.positions.size();
      report.triangles_after = mesh.triangles.size();
      return report;
    }
    report.invalid_triangles_removed = keep_triangles(mesh, keep);
  }

  Aabb box;
  for (const Vec3& p : mesh.positions)
    if (finite(p)) box.expand(p);
  const Real diagonal = box.diagonal();

  if (options.merge_vertices) {
    report.merge_tolerance = std::max(options.merge_tolerance_abs, options.merge_tolerance_rel * diagonal);
    const std::vector<std::uint32_t> rep = vertex_representatives(mesh.positions, report.merge_tolerance);
    for (std::size_t v = 0; v < rep.size(); ++v)
      if (rep[v] != v) ++report.vertices_merged;
    for (Triangle& tri : mesh.triangles)
      for (std::uint32_t& v : tri) v = rep[v];
  }
  if (options.drop_degenerate) drop_degenerate(mesh, std::pow(options.degenerate_area_rel * diagonal, 2), report);
  if (options.drop_duplicate_triangles) drop_duplicates(mesh, report);
  if (options.min_component_triangles > 0 || options.min_component_area_fraction > 0)
    drop_small_components(mesh, options, report);
  if (options.make_winding_consistent || options.orient_outward) fix_winding(mesh, options, report);
  if (options.drop_unused_vertices) drop_unused(mesh, report);

  report.vertices_after = mesh.positions.size();
  report.triangles_after = mesh.triangles.size();
  return report;
}

}  // namespace trocar
