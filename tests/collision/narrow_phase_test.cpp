// The narrow phase's rejection tests change nothing but the time: the AVX2 path (where the CPU
// has it), the portable path and the exact test alone on every candidate give the same contacts.
#include <gtest/gtest.h>

#include <random>

#include "scene_util.h"
#include "trocar/collision/narrow_phase.h"
#include "trocar/geometry/triangle_triangle.h"
#include "trocar/mesh/generate.h"

namespace trocar {
namespace {

// Every candidate straight into intersect_triangles: what the rejection tests must reproduce.
std::vector<Contact> exact_only(std::span<const CollisionObject> objects, std::span<const CandidatePair> pairs) {
  std::vector<Contact> out;
  for (const CandidatePair& p : pairs) {
    const CollisionObject& oa = objects[p.object_a];
    const CollisionObject& ob = objects[p.object_b];
    const Triangle& ta = oa.triangles[p.triangle_a];
    const Triangle& tb = ob.triangles[p.triangle_b];
    const TriTriResult r = intersect_triangles(oa.positions[ta[0]], oa.positions[ta[1]], oa.positions[ta[2]],
                                               ob.positions[tb[0]], ob.positions[tb[1]], ob.positions[tb[2]]);
    if (!r.intersects) continue;
    Contact c;
    c.object_a = p.object_a;
    c.object_b = p.object_b;
    c.triangle_a = p.triangle_a;
    c.triangle_b = p.triangle_b;
    c.kind = contact_kind(oa.role, ob.role);
    c.coplanar = r.coplanar;
    c.segment_p = r.p;
    c.segment_q = r.q;
    out.push_back(c);
  }
  std::sort(out.begin(), out.end(), contact_less);
  return out;
}

// All three on the brute-force candidates of `objects`; returns the number of contacts.
std::size_t expect_paths_agree(std::span<const CollisionObject> objects, const std::string& what) {
  BruteForceBroadPhase brute;
  std::vector<CandidatePair> pairs;
  brute.find_pairs(objects, pairs);
  const std::vector<Contact> reference = exact_only(objects, pairs);
  std::vector<Contact> simd;
  std::vector<Contact> portable;
  narrow_phase(objects, pairs, simd, true);
  narrow_phase(objects, pairs, portable, false);
  test::expect_same_contacts(reference, simd, what + " (simd)");
  test::expect_same_contacts(reference, portable, what + " (portable)");
  return reference.size();
}

TEST(NarrowPhase, RandomSoupsSeveralObjects) {
  // Several object pairs, so that groups of four candidates mix object pairs at their borders.
  std::mt19937 rng(4242);
  std::size_t total = 0;
  for (int trial = 0; trial < 6; ++trial) {
    test::Scene scene;
    scene.add(test::random_soup(rng, 120, Vec3::Zero(), 1.0, 0.3), ObjectRole::kInstrument);
    scene.add(test::random_soup(rng, 150, Vec3(0.2, 0.1, 0.0), 1.0, 0.3), ObjectRole::kTissue);
    scene.add(test::random_soup(rng, 37, Vec3(0.1, 0.3, 0.2), 1.0, 0.3), ObjectRole::kRigid);
    const auto objects = scene.objects();
    total += expect_paths_agree(objects, "soup " + std::to_string(trial));
  }
  EXPECT_GT(total, 300u);
}

TEST(NarrowPhase, TouchingNearMissAndCoplanarPairs) {
  // Triangle B moved off A's plane, along it and across its edge by distances from far below
  // to far above the tolerances (1e-12 of the size for touching, 1e-9 for the rejection
  // margins), tilted and coplanar, at a large offset from the origin.
  test::Scene scene;
  TriMesh a;
  TriMesh b;
  const Vec3 far_origin(1e3, -2e3, 5e2);
  for (const Vec3& origin : {Vec3(Vec3::Zero()), far_origin}) {
    for (const double gap : {0.0, 1e-14, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-6, 1e-3}) {
      for (const double tilt : {0.0, 1e-6, 0.3}) {
        for (const double sign : {-1.0, 1.0}) {
          const auto ia = static_cast<std::uint32_t>(a.positions.size());
          a.positions.push_back(origin + Vec3(0, 0, 0));
          a.positions.push_back(origin + Vec3(1, 0, 0));
          a.positions.push_back(origin + Vec3(0, 1, 0));
          a.triangles.push_back({ia, ia + 1, ia + 2});
          // Above the plane (gap), tilted about x, and across the edge x + y = 1 (touching it
          // from outside at the same gap).
          const auto ib = static_cast<std::uint32_t>(b.positions.size());
          b.positions.push_back(origin + Vec3(0.2, 0.2, sign * gap));
          b.positions.push_back(origin + Vec3(0.8, 0.3, sign * (gap + tilt)));
          b.positions.push_back(origin + Vec3(0.3, 0.9, sign * (gap + 2 * tilt)));
          b.triangles.push_back({ib, ib + 1, ib + 2});
          const auto ic = static_cast<std::uint32_t>(b.positions.size());
          b.positions.push_back(origin + Vec3(0.5 + gap, 0.5 + gap, -0.5));
          b.positions.push_back(origin + Vec3(0.5 + gap, 0.5 + gap, 0.5 + tilt));
          b.positions.push_back(origin + Vec3(1.5, 1.5, 0.0));
          b.triangles.push_back({ic, ic + 1, ic + 2});
        }
      }
    }
  }
  scene.add(std::move(a), ObjectRole::kInstrument);
  scene.add(std::move(b), ObjectRole::kTissue);
  const auto objects = scene.objects();
  EXPECT_GT(expect_paths_agree(objects, "touching"), 20u);
}

TEST(NarrowPhase, IdenticalMeshesAndSlivers) {
  test::Scene scene;
  scene.add(make_icosphere(1.0, 2), ObjectRole::kInstrument);
  TriMesh sphere = make_icosphere(1.0, 2);
  // Slivers: a few triangles squashed to near-zero height (their planes are not trusted).
  for (std::size_t t = 0; t < sphere.triangles.size(); t += 17) {
    const Triangle& tri = sphere.triangles[t];
    sphere.positions[tri[2]] = 0.5 * (sphere.positions[tri[0]] + sphere.positions[tri[1]]) +
                               1e-9 * (sphere.positions[tri[2]] - sphere.positions[tri[0]]);
  }
  scene.add(std::move(sphere), ObjectRole::kTissue);
  const auto objects = scene.objects();
  EXPECT_GT(expect_paths_agree(objects, "identical"), 320u * 4u);
}

TEST(NarrowPhase, ToolCuttingIntoSharedMesh) {
  auto tissue = test::shared_mesh("liver_sofa_smooth.obj", 0.015);
  auto tool = test::shared_mesh("grasper_jaw_maryland_left_lapgym.stl", 0.001);
  if (!tissue || !tool) GTEST_SKIP() << test::shared_absent("the tissue or tool mesh");
  test::CuttingScene cut(std::move(*tissue), std::move(*tool), 0.004, 0.003);
  CollisionDetector ohc;
  std::size_t total = 0;
  for (int frame = 0; frame < 4; ++frame) {
    cut.set_frame(frame);
    const auto objects = cut.scene.objects();
    ohc.detect(objects);
    const std::vector<CandidatePair> pairs(ohc.candidates().begin(), ohc.candidates().end());
    const std::vector<Contact> reference = exact_only(objects, pairs);
    std::vector<Contact> simd;
    std::vector<Contact> portable;
    narrow_phase(objects, pairs, simd, true);
    narrow_phase(objects, pairs, portable, false);
    test::expect_same_contacts(reference, simd, "frame " + std::to_string(frame) + " (simd)");
    test::expect_same_contacts(reference, portable, "frame " + std::to_string(frame) + " (portable)");
    total += reference.size();
  }
  EXPECT_GT(total, 20u);
}

}  // namespace
}  // namespace trocar
