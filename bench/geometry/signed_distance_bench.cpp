// Signed distance queries on an icosphere of 5120 triangles: AABB tree vs brute force; plus the
// closest-point kernel and the refit of a deforming mesh.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "trocar/mesh/generate.h"
#include "trocar/geometry/closest_point.h"
#include "trocar/geometry/signed_distance.h"

namespace trocar {
namespace {

// Query points uniform in [−1.5, 1.5]³ around the unit sphere.
std::vector<Vec3> query_points() {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<Real> u(-1.5, 1.5);
  std::vector<Vec3> pts(1024);
  for (Vec3& p : pts) p = Vec3(u(rng), u(rng), u(rng));
  return pts;
}

// Query points within ±0.05 of the surface, where contacts are.
std::vector<Vec3> near_surface_points() {
  std::mt19937_64 rng(10);
  std::uniform_real_distribution<Real> u(-1, 1);
  std::uniform_real_distribution<Real> r(0.95, 1.05);
  std::vector<Vec3> pts(1024);
  for (Vec3& p : pts) {
    Vec3 d;
    do d = Vec3(u(rng), u(rng), u(rng)); while (d.squaredNorm() > 1 || d.squaredNorm() < 1e-4);
    p = d.normalized() * r(rng);
  }
  return pts;
}

const TriMesh& sphere() {
  static const TriMesh m = make_icosphere(1.0, 4);  // 5120 triangles
  return m;
}

void BM_SignedDistanceTree(benchmark::State& state) {
  const MeshDistance md(sphere().positions, sphere().triangles);
  const std::vector<Vec3> pts = state.range(0) == 0 ? query_points() : near_surface_points();
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(md.signed_distance(pts[i++ & 1023]));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  state.SetLabel(state.range(0) == 0 ? "box [-1.5,1.5]^3" : "near surface");
}

void BM_SignedDistanceBruteForce(benchmark::State& state) {
  const MeshDistance md(sphere().positions, sphere().triangles);
  const std::vector<Vec3> pts = query_points();
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(md.signed_distance_brute_force(pts[i++ & 1023]));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

void BM_MeshDistanceRefit(benchmark::State& state) {
  MeshDistance md(sphere().positions, sphere().triangles);
  std::vector<Vec3> moved = sphere().positions;
  Real s = 1.0;
  for (auto _ : state) {
    s = s > 1.1 ? 1.0 : s + 1e-3;
    for (Vec3& p : moved) p.x() *= s;
    md.refit(moved);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

void BM_ClosestPointOnTriangle(benchmark::State& state) {
  const std::vector<Vec3> pts = query_points();
  const Vec3 a(0.1, -0.3, 0.2), b(0.9, 0.1, -0.1), c(-0.2, 0.7, 0.3);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(closest_point_on_triangle(pts[i++ & 1023], a, b, c));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

BENCHMARK(BM_SignedDistanceTree)->Arg(0)->Arg(1);
BENCHMARK(BM_SignedDistanceBruteForce);
BENCHMARK(BM_MeshDistanceRefit);
BENCHMARK(BM_ClosestPointOnTriangle);

}  // namespace
}  // namespace trocar
