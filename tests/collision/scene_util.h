#pragma once
// Scenes for the collision tests: owned meshes with roles, views for the detector, and a
// comparison of the three broad phases after the narrow phase.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <tuple>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "trocar/collision/brute_force_broad_phase.h"
#include "trocar/collision/bvh_broad_phase.h"
#include "trocar/collision/detector.h"
#include "trocar/collision/ohc_broad_phase.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/tri_mesh.h"
#include "support/shared_data.h"

namespace trocar::test {

/// Meshes with roles; objects() gives the detector's views (valid while the scene lives).
struct Scene {
  std::vector<TriMesh> meshes;
  std::vector<ObjectRole> roles;

  void add(TriMesh mesh, ObjectRole role) {
    meshes.push_back(std::move(mesh));
    roles.push_back(role);
  }
  std::vector<CollisionObject> objects() const {
    std::vector<CollisionObject> out;
    for (std::size_t i = 0; i < meshes.size(); ++i) out.push_back({roles[i], meshes[i].positions, meshes[i].triangles});
    return out;
  }
};

/// n independent triangles with corners uniform in a cube of side `extent` at `origin`, each
/// triangle spanning at most `size`.
inline TriMesh random_soup(std::mt19937& rng, std::size_t n, const Vec3& origin, double extent, double size) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  TriMesh m;
  for (std::size_t t = 0; t < n; ++t) {
    const Vec3 c = origin + extent * Vec3(u(rng), u(rng), u(rng));
    const auto first = static_cast<std::uint32_t>(m.positions.size());
    for (int k = 0; k < 3; ++k) m.positions.push_back(c + size * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5));
    m.triangles.push_back({first, first + 1, first + 2});
  }
  return m;
}

/// A mesh moved by offset.
inline TriMesh translated(TriMesh m, const Vec3& offset) {
  for (Vec3& p : m.positions) p += offset;
  return m;
}

/// Loads a shared mesh scaled by `scale`, or nothing when the shared folder is absent.
inline std::optional<TriMesh> shared_mesh(const std::string& file, double scale) {
  const std::optional<std::filesystem::path> path = shared_mesh_path(file);
  if (!path) return std::nullopt;
  TriMesh m = load_mesh(*path);
  m.scale(scale);
  return m;
}

/// Contacts of one frame with the given broad phase (fresh detector).
inline std::vector<Contact> contacts_with(BroadPhaseKind kind, std::span<const CollisionObject> objects) {
  CollisionDetector detector(kind);
  const auto found = detector.detect(objects);
  return {found.begin(), found.end()};
}

/// Expects identical contact lists (keys, kinds, segments bit for bit).
inline void expect_same_contacts(const std::vector<Contact>& expected, const std::vector<Contact>& actual,
                                 const std::string& what) {
  ASSERT_EQ(expected.size(), actual.size()) << what;
  for (std::size_t k = 0; k < expected.size(); ++k) {
    const Contact& e = expected[k];
    const Contact& a = actual[k];
    ASSERT_EQ(contact_key(e), contact_key(a)) << what << " contact " << k;
    EXPECT_EQ(e.kind, a.kind) << what << " contact " << k;
    EXPECT_EQ(e.coplanar, a.coplanar) << what << " contact " << k;
    EXPECT_EQ(e.segment_p, a.segment_p) << what << " contact " << k;
    EXPECT_EQ(e.segment_q, a.segment_q) << what << " contact " << k;
  }
}

/// Expects the candidate list has no duplicate pair and only pairs in contact order.
inline void expect_unique_candidates(std::span<const CandidatePair> pairs, std::span<const CollisionObject> objects,
                                     const std::string& what) {
  std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>> keys;
  for (const CandidatePair& p : pairs) {
    keys.emplace_back(p.object_a, p.object_b, p.triangle_a, p.triangle_b);
    ASSERT_NE(p.object_a, p.object_b) << what;
    ASSERT_TRUE(object_first(objects[p.object_a].role, p.object_a, objects[p.object_b].role, p.object_b)) << what;
  }
  std::sort(keys.begin(), keys.end());
  EXPECT_EQ(std::adjacent_find(keys.begin(), keys.end()), keys.end()) << what << ": a pair is returned twice";
}

/// Runs OHC (auto cell; both cascade levels, the object level only, no cascade), BVH and brute force and expects the same contacts;
/// returns the brute-force contacts.
inline std::vector<Contact> expect_all_agree(std::span<const CollisionObject> objects, const std::string& what,
                                             bool with_brute = true) {
  const std::vector<Contact> bvh = contacts_with(BroadPhaseKind::kBvh, objects);
  std::vector<Contact> reference = bvh;
  if (with_brute) {
    reference = contacts_with(BroadPhaseKind::kBruteForce, objects);
    expect_same_contacts(reference, bvh, what + " (bvh vs brute)");
  }
  // 2: both cascade levels (the default), 1: object level only, 0: no cascade; -1: the default
  // with the portable code instead of the AVX2 kernels; 3: both levels, the cell hash always,
  // 4: the cluster-pair path always (when the sweep completes). -1 must give the default's
  // candidates, as a set; 4's are a subset of 3's (the cluster-pair path also tests the
  // triangles' extents along six more directions).
  std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>> simd_candidates;
  std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>> hash_candidates;
  for (const int levels : {2, -1, 3, 4, 1, 0}) {
    OhcSettings settings;
    settings.cascade = levels != 0;
    settings.cluster_cascade = levels != 0 && levels != 1;
    settings.simd = levels != -1;
    if (levels == 3) settings.max_pair_tests_per_primitive = 0;
    if (levels == 4) settings.max_pair_tests_per_primitive = std::numeric_limits<Real>::infinity();
    CollisionDetector ohc(settings);
    const auto found = ohc.detect(objects);
    expect_same_contacts(reference, {found.begin(), found.end()},
                         what + (levels == 2    ? " (ohc)"
                                 : levels == -1 ? " (ohc, portable)"
                                 : levels == 3  ? " (ohc, cell hash)"
                                 : levels == 4  ? " (ohc, cluster pairs)"
                                 : levels == 1  ? " (ohc, object cascade only)"
                                                : " (ohc, no cascade)"));
    expect_unique_candidates(ohc.candidates(), objects, what + " (ohc candidates)");
    if (levels >= 2 || levels == -1) {
      std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>> keys;
      for (const CandidatePair& p : ohc.candidates()) keys.emplace_back(p.object_a, p.object_b, p.triangle_a, p.triangle_b);
      std::sort(keys.begin(), keys.end());
      if (levels == 2) {
        simd_candidates = std::move(keys);
      } else if (levels == -1) {
        EXPECT_EQ(simd_candidates, keys) << what << ": the portable OHC finds other candidates";
      } else if (levels == 3) {
        hash_candidates = std::move(keys);
      } else {
        EXPECT_TRUE(std::includes(hash_candidates.begin(), hash_candidates.end(), keys.begin(), keys.end()))
            << what << ": the cluster-pair path finds candidates the cell hash does not";
      }
    }
  }
  return reference;
}

/// A tool cutting into the upper surface of a deforming tissue, frame by frame: object 0 is the
/// instrument, object 1 the tissue. The tool's lowest vertex starts `depth` below the tissue's
/// highest vertex near the centre of its xy extent; each frame moves the tool by `step` along x
/// and ripples the tissue's z by `ripple` (a fraction of its size), so every structure must refit.
struct CuttingScene {
  TriMesh tissue_rest;
  TriMesh tool_rest;
  Scene scene;
  Vec3 tool_start = Vec3::Zero();
  Vec3 step = Vec3::Zero();
  double ripple = 0;

  CuttingScene(TriMesh tissue, TriMesh tool, double depth, double step_fraction = 0.002, double ripple_fraction = 0.002)
      : tissue_rest(std::move(tissue)), tool_rest(std::move(tool)) {
    const Aabb tb = tissue_rest.bounds();
    const Vec3 c = tb.center();
    const Vec3 size = tb.size();
    Vec3 top = c;
    double best = -1e300;
    for (const Vec3& p : tissue_rest.positions) {
      if (std::abs(p.x() - c.x()) < 0.2 * size.x() && std::abs(p.y() - c.y()) < 0.2 * size.y() && p.z() > best) {
        best = p.z();
        top = p;
      }
    }
    Vec3 low = tool_rest.positions.front();
    for (const Vec3& p : tool_rest.positions) {
      if (p.z() < low.z()) low = p;
    }
    tool_start = top - Vec3(0, 0, depth) - low;
    step = Vec3(step_fraction * size.maxCoeff(), 0, 0);
    ripple = ripple_fraction * size.maxCoeff();
    scene.add(tool_rest, ObjectRole::kInstrument);
    scene.add(tissue_rest, ObjectRole::kTissue);
    set_frame(0);
  }

  /// Positions of frame k (no allocation).
  void set_frame(int k) {
    const Vec3 offset = tool_start + static_cast<double>(k) * step;
    auto& tool = scene.meshes[0].positions;
    for (std::size_t v = 0; v < tool.size(); ++v) tool[v] = tool_rest.positions[v] + offset;
    auto& tissue = scene.meshes[1].positions;
    for (std::size_t v = 0; v < tissue.size(); ++v) {
      const Vec3& p = tissue_rest.positions[v];
      const double phase = 0.7 * static_cast<double>(k) + 3.1 * static_cast<double>(v % 17);
      tissue[v] = p + Vec3(0, 0, ripple * std::sin(phase));
    }
  }
};

}  // namespace trocar::test
