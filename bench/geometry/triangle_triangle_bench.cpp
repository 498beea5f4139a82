// Triangle–triangle test per pair, on random intersecting and non-intersecting pairs.
#include <benchmark/benchmark.h>

#include <array>
#include <random>
#include <vector>

#include "trocar/geometry/triangle_triangle.h"

namespace trocar {
namespace {

using Pair = std::array<Vec3, 6>;

// 1024 pairs of random triangles in [−1,1]³ (the second shifted by up to ±1), kept when their
// intersection status equals `want`.
std::vector<Pair> make_pairs(bool want) {
  std::mt19937_64 rng(want ? 1 : 2);
  std::uniform_real_distribution<Real> u(-1, 1);
  const auto vec = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  std::vector<Pair> pairs;
  while (pairs.size() < 1024) {
    const Vec3 shift = vec();
    const Pair p = {vec(), vec(), vec(), vec() + shift, vec() + shift, vec() + shift};
    if (intersect_triangles(p[0], p[1], p[2], p[3], p[4], p[5]).intersects == want) {
      pairs.push_back(p);
    }
  }
  return pairs;
}

void run(benchmark::State& state, bool want) {
  const std::vector<Pair> pairs = make_pairs(want);
  std::size_t i = 0;
  for (auto _ : state) {
    const Pair& p = pairs[i++ & 1023];
    benchmark::DoNotOptimize(intersect_triangles(p[0], p[1], p[2], p[3], p[4], p[5]));
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

void BM_TriTriIntersecting(benchmark::State& state) { run(state, true); }
void BM_TriTriDisjoint(benchmark::State& state) { run(state, false); }

// Coplanar overlapping pairs (z = 0), the clipping path.
void BM_TriTriCoplanar(benchmark::State& state) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<Real> u(-1, 1);
  std::vector<Pair> pairs;
  while (pairs.size() < 1024) {
    Pair p;
    for (Vec3& v : p) v = Vec3(u(rng), u(rng), 0);
    if (intersect_triangles(p[0], p[1], p[2], p[3], p[4], p[5]).intersects) pairs.push_back(p);
  }
  std::size_t i = 0;
  for (auto _ : state) {
    const Pair& p = pairs[i++ & 1023];
    benchmark::DoNotOptimize(intersect_triangles(p[0], p[1], p[2], p[3], p[4], p[5]));
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

BENCHMARK(BM_TriTriIntersecting);
BENCHMARK(BM_TriTriDisjoint);
BENCHMARK(BM_TriTriCoplanar);

}  // namespace
}  // namespace trocar
