#include "trocar/mesh/organ_shapes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>

#include "trocar/core/error.h"

namespace trocar {
namespace {

void require(bool ok, const char* what) {
  if (!ok) throw Error(std::string("organ generator: ") + what);
}

bool positive(Real x) { return x > 0 && std::isfinite(x); }

std::uint32_t u32(std::size_t i) { return static_cast<std::uint32_t>(i); }

/// The 12 unit icosahedron corners (0, ±1, ±φ) and cyclic permutations, and its 20 faces
/// turned outward (the same icosahedron as make_icosphere).
void icosahedron(std::array<Vec3, 12>& corners, std::array<Triangle, 20>& faces) {
  const Real phi = (1 + std::sqrt(5.0)) / 2;
  const Real c[12][3] = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0},
                         {0, -1, phi}, {0, 1, phi}, {0, -1, -phi}, {0, 1, -phi},
                         {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
  for (std::size_t i = 0; i < 12; ++i) corners[i] = Vec3(c[i][0], c[i][1], c[i][2]).normalized();
  faces = {{{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
            {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
            {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
            {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}}};
  for (Triangle& f : faces) {
    const Vec3 &a = corners[f[0]], &b = corners[f[1]], &cc = corners[f[2]];
    if ((b - a).cross(cc - a).dot(a + b + cc) < 0) std::swap(f[1], f[2]);
  }
}

/// Uniform draws from the raw 64-bit words of std::mt19937_64 (whose output sequence the
/// standard fixes), so a seed gives the same numbers with every standard library.
class Uniform {
 public:
  explicit Uniform(std::uint64_t seed) : engine_(seed) {}
  /// In [0, 1): the top 53 bits of one word.
  Real unit() { return static_cast<Real>(engine_() >> 11) * 0x1.0p-53; }
  /// In [a, b).
  Real operator()(Real a, Real b) { return a + (b - a) * unit(); }
  /// An integer in [lo, hi] (the modulo bias is below 2⁻⁶⁰ for small ranges).
  std::size_t integer(std::size_t lo, std::size_t hi) {
    return lo + static_cast<std::size_t>(engine_() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  /// A uniformly distributed unit vector: rejection from the cube (no transcendental function,
  /// so bit-identical across C libraries; sqrt is correctly rounded).
  Vec3 direction() {
    for (;;) {
      const Vec3 v((*this)(-1, 1), (*this)(-1, 1), (*this)(-1, 1));
      const Real n2 = v.squaredNorm();
      if (n2 > 1e-4 && n2 <= 1) return v / std::sqrt(n2);
    }
  }

 private:
  std::mt19937_64 engine_;
};

/// SplitMix64's finaliser: decorrelates the family members' seeds.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// One Gaussian bump on the unit sphere: amplitude · exp(−(1 − w·centre)/width²).
struct Bump {
  Vec3 centre;
  Real width;
  Real amplitude;
};

/// Marks an icosahedron corner pair that is not an edge.
constexpr std::uint32_t kNoEdge = std::numeric_limits<std::uint32_t>::max();

}  // namespace

TriMesh make_geodesic_sphere(Real radius, std::size_t frequency) {
  require(positive(radius), "geodesic sphere radius must be positive");
  require(frequency >= 1 && frequency <= kMaxGeodesicFrequency,
          "geodesic sphere frequency must be in [1, 1024]");
  const std::size_t f = frequency;
  std::array<Vec3, 12> corner;
  std::array<Triangle, 20> faces;
  icosahedron(corner, faces);

  // Vertex numbering by construction: corners 0..11; edge e (its corners lo < hi) holds
  // 12 + e·(f − 1) + (k − 1) for the k-th of its f − 1 inner points counted from lo; face t
  // holds (f − 1)(f − 2)/2 inner points after all the edges.
  std::array<std::array<std::uint32_t, 12>, 12> edge_id;
  for (auto& row : edge_id) row.fill(kNoEdge);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const Triangle& tri : faces)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = std::min(tri[k], tri[(k + 1) % 3]), b = std::max(tri[k], tri[(k + 1) % 3]);
      if (edge_id[a][b] == kNoEdge) {
        edge_id[a][b] = edge_id[b][a] = u32(edges.size());
        edges.emplace_back(a, b);
      }
    }
  const std::size_t edge_base = 12, per_edge = f - 1;
  const std::size_t face_base = edge_base + edges.size() * per_edge, per_face = (f - 1) * (f - 2) / 2;

  TriMesh mesh;
  mesh.positions.reserve(10 * f * f + 2);
  for (const Vec3& c : corner) mesh.positions.push_back(c);
  for (const auto& [a, b] : edges)
    for (std::size_t k = 1; k < f; ++k)
      mesh.positions.push_back((static_cast<Real>(f - k) * corner[a] + static_cast<Real>(k) * corner[b]).normalized());

  // Grid point (i, j), i + j ≤ f, of face (A, B, C) is ((f − i − j)·A + i·B + j·C)/f: i runs
  // along AB, j along AC, i + j = f is BC.
  auto edge_vertex = [&](std::uint32_t from, std::uint32_t to, std::size_t k) -> std::uint32_t {
    const std::size_t e = edge_id[from][to];
    return u32(edge_base + e * per_edge + (from < to ? k - 1 : f - k - 1));
  };
  auto inner_offset = [&](std::size_t j) { return (j - 1) * (f - 1) - (j - 1) * j / 2; };
  for (std::size_t t = 0; t < faces.size(); ++t) {
    const Triangle& tri = faces[t];
    for (std::size_t j = 1; j + 2 <= f; ++j)
      for (std::size_t i = 1; i + j < f; ++i) {
        const Vec3 grid = static_cast<Real>(f - i - j) * corner[tri[0]] + static_cast<Real>(i) * corner[tri[1]] +
                          static_cast<Real>(j) * corner[tri[2]];
        mesh.positions.push_back(grid.normalized());
      }
  }

  mesh.triangles.reserve(20 * f * f);
  for (std::size_t t = 0; t < faces.size(); ++t) {
    const Triangle& tri = faces[t];
    auto vertex = [&](std::size_t i, std::size_t j) -> std::uint32_t {
      if (j == 0) return i == 0 ? tri[0] : i == f ? tri[1] : edge_vertex(tri[0], tri[1], i);
      if (i == 0) return j == f ? tri[2] : edge_vertex(tri[0], tri[2], j);
      if (i + j == f) return edge_vertex(tri[1], tri[2], j);
      return u32(face_base + t * per_face + inner_offset(j) + (i - 1));
    };
    // Counter-clockwise in (i, j) as (A, B, C) is: "up" (i, j), (i+1, j), (i, j+1) and "down"
    // (i+1, j), (i+1, j+1), (i, j+1).
    for (std::size_t j = 0; j < f; ++j)
      for (std::size_t i = 0; i + j < f; ++i) {
        mesh.triangles.push_back({vertex(i, j), vertex(i + 1, j), vertex(i, j + 1)});
        if (i + j + 1 < f) mesh.triangles.push_back({vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
      }
  }
  mesh.normals = mesh.positions;  // unit vectors from the centre
  for (Vec3& p : mesh.positions) p *= radius;
  return mesh;
}

std::size_t nearest_geodesic_frequency(std::size_t target_triangles) {
  auto count = [](std::size_t f) { return 20 * f * f; };
  std::size_t f = 1;
  while (f < kMaxGeodesicFrequency && count(f + 1) <= target_triangles) ++f;
  // Now count(f) ≤ target < count(f + 1), or target < count(1), or f is the largest.
  if (target_triangles <= count(f) || f == kMaxGeodesicFrequency) return f;
  return count(f + 1) - target_triangles < target_triangles - count(f) ? f + 1 : f;
}

TriMesh make_organ_shape(const OrganShapeSpec& spec) {
  require(positive(spec.size), "organ size must be positive");
  require(spec.flatten >= 0 && spec.flatten <= 0.9, "organ flatten must be in [0, 0.9]");
  require(spec.roughness >= 0 && spec.roughness <= 1, "organ roughness must be in [0, 1]");
  require(spec.target_triangles >= 1 && spec.target_triangles <= 20 * kMaxGeodesicFrequency * kMaxGeodesicFrequency,
          "organ target_triangles must be in [1, 20·1024²]");
  TriMesh mesh = make_geodesic_sphere(1.0, nearest_geodesic_frequency(spec.target_triangles));
  mesh.normals.clear();

  // The draws, in this order (the order is part of the seed → mesh contract).
  Uniform rnd(spec.seed);
  const Real ay = rnd(0.6, 0.9);
  const Real az = rnd(0.4, 0.7) * (1 - spec.flatten);
  const Real taper = rnd(-0.15, 0.15);
  std::vector<Bump> bumps(rnd.integer(4, 6));
  for (Bump& b : bumps) {
    b.centre = rnd.direction();
    b.width = rnd(0.4, 0.8);
    b.amplitude = rnd(-0.3, 0.35);
  }
  Mat3 quad;
  quad(0, 0) = rnd(-0.12, 0.12);
  quad(1, 1) = rnd(-0.12, 0.12);
  quad(2, 2) = -(quad(0, 0) + quad(1, 1));  // traceless: the mean over the sphere is 0
  quad(0, 1) = quad(1, 0) = rnd(-0.12, 0.12);
  quad(0, 2) = quad(2, 0) = rnd(-0.12, 0.12);
  quad(1, 2) = quad(2, 1) = rnd(-0.12, 0.12);

  // |wᵀQw| ≤ ‖Q‖₂ ≤ ‖Q‖_F and each bump lies in (0, a_k] or [a_k, 0): r ∈ [0.5, 1.6].
  Real up = quad.norm(), down = quad.norm();
  for (const Bump& b : bumps) (b.amplitude > 0 ? up : down) += std::abs(b.amplitude);
  const Real lambda = spec.roughness * std::min({Real{1}, 0.6 / up, 0.5 / down});
  auto radius = [&](const Vec3& w) {
    Real h = w.dot(quad * w);
    for (const Bump& b : bumps) h += b.amplitude * std::exp(-(1 - w.dot(b.centre)) / (b.width * b.width));
    return 1 + lambda * h;
  };

  const Vec3 aspect(1, ay, az);
  // D^(−e) with e = ½. Smallest angle over the family for seeds 1–40 (240 organs) for
  // e = 0, ¼, ½, ¾, 1: 9.4°, 14.1°, 20.4°, 23.3°, 14.9° (e = 1 puts each vertex on its ray onto
  // the scaled shape, which stretches the flat faces near a thin rim). ½ is close to the best
  // and needs only 1/√ (correctly rounded, unlike std::pow).
  const Vec3 prewarp(1, 1 / std::sqrt(ay), 1 / std::sqrt(az));
  for (Vec3& p : mesh.positions) {
    const Vec3 w = prewarp.cwiseProduct(p).normalized();
    const Vec3 q = aspect.cwiseProduct(radius(w) * w);
    p = q / (1 + taper * q.x());  // |q_x| ≤ 1.6, so the denominator is in [0.76, 1.24]
  }

  // Exact extents size × a_y·size × a_z·size, centred at the origin.
  const Aabb box = mesh.bounds();
  const Vec3 centre = (box.min + box.max) / 2;
  const Vec3 scale = (spec.size * aspect).cwiseQuotient(box.max - box.min);
  for (Vec3& p : mesh.positions) p = (p - centre).cwiseProduct(scale);
  return mesh;
}

std::vector<OrganShapeSpec> organ_family(std::uint64_t seed) {
  struct Slot {
    const char* label;
    std::size_t target;
    Real size;
    bool flat;
  };
  static constexpr Slot kSlots[] = {{"lobe-2k", 2000, 0.06, false},  {"flat-5k", 5000, 0.10, true},
                                    {"lobe-8k", 8000, 0.12, false},  {"flat-12k", 12000, 0.15, true},
                                    {"lobe-18k", 18000, 0.14, false}, {"flat-24.5k", 24500, 0.18, true}};
  std::vector<OrganShapeSpec> family;
  for (std::size_t i = 0; i < std::size(kSlots); ++i) {
    const Slot& slot = kSlots[i];
    OrganShapeSpec spec;
    spec.seed = mix(mix(seed) + i);
    spec.target_triangles = slot.target;
    spec.size = slot.size;
    spec.flatten = slot.flat ? 0.6 : 0.0;
    spec.name = std::string(slot.label) + "-s" + std::to_string(seed);
    family.push_back(std::move(spec));
  }
  return family;
}

}  // namespace trocar
