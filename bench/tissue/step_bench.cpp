// One time step of each tissue integrator on the shared organs, with Bullet stepping the same
// mesh in the same binary as the peer (docs/tissue.md, "Benchmarks").
//
// Scenario, the same for every row: the organ in metres, its vertices renumbered for locality as
// the scene loader does (mesh/renumber.h; Bullet gets the same mesh), the vertices in its bottom
// 12 % (by z) fixed, gravity (0, 0, −9.81), dt = 1 ms, one step per benchmark iteration.
//  * Ours: the state starts from rest plus a deterministic ±0.5 mm jitter of every free vertex
//    (so the step has real forces to resolve) and is put back there every 64 steps; the copy
//    is inside the timing (two memcpy's of V·24 bytes, amortised over 64 steps).
//  * explicit-euler / semi-implicit-euler run the organ's preset with every stiffness and the
//    spring damping scaled down until every vertex has h²·Σk/m ≤ 1e-3 (explicit Euler, which
//    gains energy at every step unless h²ω² is tiny) or ≤ 1 (semi-implicit; its limit is 4),
//    so they stay finite; the per-step work depends on the mesh, not on the values.
//  * xpbd runs the organ's preset as is, with its default substeps (4); xpbd-scalar forces the
//    portable passes.
//  * implicit-euler runs the organ's preset as is. The setup runs explicit Euler for 300
//    steps on the same material and reports `explicit_diverged` = 1 when it blew up (non-finite
//    or a vertex more than 5 cm from rest), so each row shows that it is at a stiffness
//    where explicit Euler diverges.
//  * Bullet btSoftBody: CreateFromTriMesh (links on edges), generateBendingConstraints(2),
//    one position iteration, link stiffness 1, total mass from the preset, same fixed nodes,
//    stepped with btSoftRigidDynamicsWorld::stepSimulation(dt, 0) (one internal step).
//  * Bullet deformable: btDeformableMultiBodyDynamicsWorld, implicit (backward Euler, Newton +
//    CG, no line search), btDeformableMassSpringForce(k_structural, spring_damping, bending
//    k_bending) + btDeformableGravityForce, same mesh, mass and fixed nodes; stepped with
//    stepSimulation(dt, 0). Bullet's state is not reset (it keeps sagging and settling).
//
// Counters: ns_per_vertex (CPU ns per vertex per step), vertices, and for ours simd (1 when the
// AVX2 passes ran; the -scalar row forces the portable ones), sweep (explicit: 1 when the step ran
// as one sweep over blocks of vertices, explicit_sweep.h; the -passes and -sweep rows force
// each), cg_iterations
// (mean per step, implicit) and finite (1 when the state stayed finite).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/renumber.h"
#include "trocar/tissue/forces.h"
#include "trocar/tissue/integrator.h"
#include "trocar/tissue/material.h"
#include "trocar/tissue/settings.h"
#include "trocar/tissue/state.h"

#ifdef TROCAR_HAVE_BULLET
// Bullet's headers are SYSTEM includes, but g++ 12 still reports a -Wmaybe-uninitialized from
// Bullet's inlined btAlignedObjectArray copy (btModifiedGramSchmidt); silence it for them only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <btBulletDynamicsCommon.h>
#include <BulletSoftBody/btDeformableBodySolver.h>
#include <BulletSoftBody/btDeformableGravityForce.h>
#include <BulletSoftBody/btDeformableMassSpringForce.h>
#include <BulletSoftBody/btDeformableMultiBodyConstraintSolver.h>
#include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#pragma GCC diagnostic pop
#endif

namespace trocar {
namespace {

constexpr Real kDt = 1e-3;               ///< s
constexpr Real kSupportFraction = 0.12;  ///< bottom fraction of the height that is fixed
constexpr int kResetPeriod = 64;         ///< steps between resets of our state
const Vec3 kGravity(0, 0, -9.81);

/// A shared organ: file, scale into metres, preset.
struct Organ {
  const char* label;
  const char* file;
  Real scale;
  const char* preset;
};

constexpr Organ kOrgans[] = {
    {"liver", "liver_sofa_smooth.obj", 0.01, "liver"},
    {"gallbladder", "gallbladder_lapgym.stl", 0.001, "gallbladder"},
    {"abdominal_wall", "abdominal_wall_openhelp.stl", 0.001, "abdominal_wall"},
};

/// The organ's mesh in metres, loaded once; nullptr when the shared file is absent or unreadable.
const TriMesh* organ_mesh(const Organ& organ) {
  static std::map<std::string, std::optional<TriMesh>> cache;
  auto it = cache.find(organ.file);
  if (it == cache.end()) {
    std::optional<TriMesh> mesh;
    const auto path = std::filesystem::path(TROCAR_SHARED_MESHES) / organ.file;
    if (std::filesystem::exists(path)) {
      try {
        mesh = load_mesh(path);
        for (Vec3& p : mesh->positions) p *= organ.scale;
        mesh = renumber_vertices(*mesh, locality_vertex_order(*mesh));
      } catch (const std::exception&) {
        mesh.reset();
      }
    }
    it = cache.emplace(organ.file, std::move(mesh)).first;
  }
  return it->second ? &*it->second : nullptr;
}

/// Fixes every vertex in the bottom kSupportFraction of the mesh's height.
FixedSelection bottom_support(const TriMesh& mesh) {
  const Aabb box = mesh.bounds();
  const Real z = box.min.z() + kSupportFraction * (box.max.z() - box.min.z());
  FixedSelection fixed;
  fixed.below_plane = Plane{Vec3(0, 0, z), Vec3::UnitZ()};
  return fixed;
}

/// The preset with stiffness and spring damping scaled so that h²·Σ_springs k / m ≤ `bound` at
/// every vertex.
MassSpringMaterial explicit_stable(const TriMesh& mesh, const MassSpringMaterial& preset, Real bound) {
  const MassSpringSettings s = MassSpringSettings::build(mesh, preset);
  std::vector<Real> k_sum(s.vertex_count(), preset.k_home);
  for (const Spring& sp : s.springs) {
    k_sum[sp.i] += sp.stiffness;
    k_sum[sp.j] += sp.stiffness;
  }
  Real worst = 0;
  for (std::size_t i = 0; i < s.vertex_count(); ++i) worst = std::max(worst, kDt * kDt * k_sum[i] / s.masses[i]);
  MassSpringMaterial m = preset;
  if (worst > bound) {
    const Real f = bound / worst;
    m.k_structural *= f;
    m.k_bending *= f;
    m.k_area *= f;
    m.k_volume *= f;
    m.k_home *= f;
    m.spring_damping *= f;
  }
  return m;
}

/// Rest plus a deterministic ±0.5 mm jitter on every free vertex.
MassSpringState jittered(const MassSpringSettings& s) {
  MassSpringState state = MassSpringState::at_rest(s);
  std::mt19937 rng(12345);
  std::uniform_real_distribution<Real> u(-5e-4, 5e-4);
  for (std::size_t i = 0; i < s.vertex_count(); ++i)
    if (!s.fixed[i]) state.positions[i] += Vec3(u(rng), u(rng), u(rng));
  return state;
}

/// Runs explicit Euler for 300 steps on `s` from the jittered state; true when it diverged.
bool explicit_diverges(const MassSpringSettings& s) {
  MassSpringIntegrator integrator(s, IntegratorKind::kExplicitEuler);
  MassSpringState state = jittered(s);
  TissueLoads loads;
  loads.reset(s.vertex_count(), 0);
  for (int n = 0; n < 300; ++n) {
    const StepStats st = integrator.step(state, loads, kDt);
    if (!st.finite) return true;
  }
  for (std::size_t i = 0; i < s.vertex_count(); ++i)
    if (!state.positions[i].allFinite() || (state.positions[i] - s.rest_positions[i]).norm() > 0.05) return true;
  return false;
}

/// CPU ns per vertex per iteration, as a Google Benchmark counter.
benchmark::Counter ns_per_vertex(std::size_t vertices) {
  return benchmark::Counter(static_cast<double>(vertices) * 1e-9,
                            benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void bm_ours(benchmark::State& bs, const Organ& organ, IntegratorKind kind, bool simd,
             std::optional<bool> sweep = std::nullopt) {
  const TriMesh* mesh = organ_mesh(organ);
  if (mesh == nullptr) {
    bs.SkipWithError("shared mesh not available");
    return;
  }
  const MassSpringMaterial preset = material_preset(organ.preset);
  const MassSpringMaterial material =
      kind == IntegratorKind::kImplicitEuler || kind == IntegratorKind::kXpbd
          ? preset
          : explicit_stable(*mesh, preset, kind == IntegratorKind::kExplicitEuler ? 1e-3 : 1.0);
  const MassSpringSettings settings = MassSpringSettings::build(*mesh, material, bottom_support(*mesh), kGravity);
  if (kind == IntegratorKind::kImplicitEuler) bs.counters["explicit_diverged"] = explicit_diverges(settings) ? 1 : 0;
  MassSpringIntegrator integrator(settings, kind);
  integrator.set_simd(simd);
  if (integrator.xpbd() != nullptr) integrator.xpbd()->set_simd(simd);
  if (sweep) integrator.set_explicit_sweep(*sweep);
  TissueLoads loads;
  loads.reset(settings.vertex_count(), 0);
  const MassSpringState start = jittered(settings);
  MassSpringState state = start;
  integrator.step(state, loads, kDt);  // first step outside the timing (scratch warm-up)
  state = start;
  int since_reset = 0;
  std::int64_t cg = 0;
  bool finite = true;
  for (auto _ : bs) {
    if (++since_reset == kResetPeriod) {
      std::copy(start.positions.begin(), start.positions.end(), state.positions.begin());
      std::copy(start.velocities.begin(), start.velocities.end(), state.velocities.begin());
      since_reset = 0;
    }
    const StepStats st = integrator.step(state, loads, kDt);
    cg += st.cg_iterations;
    finite = finite && st.finite;
    benchmark::DoNotOptimize(state.positions.data());
  }
  bs.counters["vertices"] = static_cast<double>(settings.vertex_count());
  bs.counters["simd"] = (integrator.xpbd() != nullptr ? integrator.xpbd()->simd() : integrator.simd()) ? 1 : 0;
  if (integrator.xpbd() != nullptr) bs.counters["substeps"] = integrator.xpbd()->options().substeps;
  if (kind != IntegratorKind::kImplicitEuler && kind != IntegratorKind::kXpbd) bs.counters["sweep"] = integrator.explicit_sweep() ? 1 : 0;
  bs.counters["ns_per_vertex"] = ns_per_vertex(settings.vertex_count());
  bs.counters["finite"] = finite ? 1 : 0;
  bs.counters["k_structural"] = material.k_structural;
  if (kind == IntegratorKind::kImplicitEuler)
    bs.counters["cg_iterations"] = static_cast<double>(cg) / static_cast<double>(std::max<std::int64_t>(1, bs.iterations()));
}

#ifdef TROCAR_HAVE_BULLET

/// The mesh as Bullet's flat arrays.
struct BulletMesh {
  std::vector<btScalar> vertices;
  std::vector<int> triangles;
  explicit BulletMesh(const TriMesh& mesh) {
    for (const Vec3& p : mesh.positions)
      for (int c = 0; c < 3; ++c) vertices.push_back(static_cast<btScalar>(p[c]));
    for (const Triangle& t : mesh.triangles)
      for (std::uint32_t v : t) triangles.push_back(static_cast<int>(v));
  }
};

/// Fixes Bullet nodes below the support plane (mass 0), after the total mass is set.
void fix_bottom(btSoftBody& body, const TriMesh& mesh) {
  const FixedSelection fixed = bottom_support(mesh);
  for (std::size_t i = 0; i < mesh.vertex_count(); ++i)
    if (fixed.below_plane->normal.dot(mesh.positions[i] - fixed.below_plane->point) < 0)
      body.setMass(static_cast<int>(i), 0);
}

void bm_bullet_softbody(benchmark::State& bs, const Organ& organ) {
  const TriMesh* mesh = organ_mesh(organ);
  if (mesh == nullptr) {
    bs.SkipWithError("shared mesh not available");
    return;
  }
  const MassSpringMaterial preset = material_preset(organ.preset);
  const BulletMesh arrays(*mesh);
  auto config = std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>();
  auto dispatcher = std::make_unique<btCollisionDispatcher>(config.get());
  auto broadphase = std::make_unique<btDbvtBroadphase>();
  auto solver = std::make_unique<btSequentialImpulseConstraintSolver>();
  auto world = std::make_unique<btSoftRigidDynamicsWorld>(dispatcher.get(), broadphase.get(), solver.get(), config.get());
  world->setGravity(btVector3(0, 0, static_cast<btScalar>(kGravity.z())));
  world->getWorldInfo().m_gravity = world->getGravity();
  btSoftBody* body = btSoftBodyHelpers::CreateFromTriMesh(world->getWorldInfo(), arrays.vertices.data(),
                                                         arrays.triangles.data(),
                                                         static_cast<int>(mesh->triangle_count()), true);
  body->m_materials[0]->m_kLST = 1;
  body->generateBendingConstraints(2, body->m_materials[0]);
  body->m_cfg.piterations = 1;
  body->m_cfg.kDP = static_cast<btScalar>(0.01);
  body->getCollisionShape()->setMargin(static_cast<btScalar>(0.001));
  const Real mass = preset.mass > 0 ? preset.mass : preset.density * std::abs(mesh->signed_volume());
  body->setTotalMass(static_cast<btScalar>(mass), true);
  fix_bottom(*body, *mesh);
  world->addSoftBody(body);
  world->stepSimulation(static_cast<btScalar>(kDt), 0);  // first step outside the timing
  for (auto _ : bs) {
    world->stepSimulation(static_cast<btScalar>(kDt), 0);
    benchmark::DoNotOptimize(body->m_nodes[0].m_x);
  }
  bool finite = true;
  for (int i = 0; i < body->m_nodes.size(); ++i)
    finite = finite && std::isfinite(static_cast<double>(body->m_nodes[i].m_x.length2()));
  bs.counters["vertices"] = static_cast<double>(mesh->vertex_count());
  bs.counters["ns_per_vertex"] = ns_per_vertex(mesh->vertex_count());
  bs.counters["finite"] = finite ? 1 : 0;
  world->removeSoftBody(body);
  delete body;
}

void bm_bullet_deformable(benchmark::State& bs, const Organ& organ) {
  const TriMesh* mesh = organ_mesh(organ);
  if (mesh == nullptr) {
    bs.SkipWithError("shared mesh not available");
    return;
  }
  const MassSpringMaterial preset = material_preset(organ.preset);
  const BulletMesh arrays(*mesh);
  auto config = std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>();
  auto dispatcher = std::make_unique<btCollisionDispatcher>(config.get());
  auto broadphase = std::make_unique<btDbvtBroadphase>();
  auto deformable_solver = std::make_unique<btDeformableBodySolver>();
  auto solver = std::make_unique<btDeformableMultiBodyConstraintSolver>();
  solver->setDeformableSolver(deformable_solver.get());
  auto world = std::make_unique<btDeformableMultiBodyDynamicsWorld>(dispatcher.get(), broadphase.get(), solver.get(),
                                                                    config.get(), deformable_solver.get());
  const btVector3 gravity(0, 0, static_cast<btScalar>(kGravity.z()));
  world->setGravity(gravity);
  world->getWorldInfo().m_gravity = gravity;
  btSoftBody* body = btSoftBodyHelpers::CreateFromTriMesh(world->getWorldInfo(), arrays.vertices.data(),
                                                         arrays.triangles.data(),
                                                         static_cast<int>(mesh->triangle_count()), true);
  body->getCollisionShape()->setMargin(static_cast<btScalar>(0.001));
  body->generateBendingConstraints(2);
  const Real mass = preset.mass > 0 ? preset.mass : preset.density * std::abs(mesh->signed_volume());
  body->setTotalMass(static_cast<btScalar>(mass), true);
  fix_bottom(*body, *mesh);
  body->m_cfg.kKHR = 1;
  body->m_cfg.kCHR = 1;
  body->m_cfg.kDF = 0;
  body->m_cfg.collisions = btSoftBody::fCollision::SDF_RD;
  world->addSoftBody(body);
  auto springs = std::make_unique<btDeformableMassSpringForce>(static_cast<btScalar>(preset.k_structural),
                                                               static_cast<btScalar>(preset.spring_damping), true,
                                                               preset.k_bending);
  auto weight = std::make_unique<btDeformableGravityForce>(gravity);
  world->addForce(body, springs.get());
  world->addForce(body, weight.get());
  world->setImplicit(true);
  world->setLineSearch(false);
  world->stepSimulation(static_cast<btScalar>(kDt), 0);  // first step outside the timing
  for (auto _ : bs) {
    world->stepSimulation(static_cast<btScalar>(kDt), 0);
    benchmark::DoNotOptimize(body->m_nodes[0].m_x);
  }
  bool finite = true;
  for (int i = 0; i < body->m_nodes.size(); ++i)
    finite = finite && std::isfinite(static_cast<double>(body->m_nodes[i].m_x.length2()));
  bs.counters["vertices"] = static_cast<double>(mesh->vertex_count());
  bs.counters["ns_per_vertex"] = ns_per_vertex(mesh->vertex_count());
  bs.counters["finite"] = finite ? 1 : 0;
  world->removeForce(body, springs.get());
  world->removeForce(body, weight.get());
  world->removeSoftBody(body);
  delete body;
}

#endif  // TROCAR_HAVE_BULLET

/// Registers every row: BM_Tissue/<organ>/<integrator> (and xpbd-scalar, semi-implicit-euler-scalar,
/// -passes and -sweep), BM_BulletSoftBody/<organ>,
/// BM_BulletDeformable/<organ>.
bool register_all() {
  constexpr IntegratorKind kKinds[] = {IntegratorKind::kExplicitEuler, IntegratorKind::kSemiImplicitEuler,
                                       IntegratorKind::kImplicitEuler, IntegratorKind::kXpbd};
  constexpr const char* kKindNames[] = {"explicit-euler", "semi-implicit-euler", "implicit-euler", "xpbd"};
#ifdef TROCAR_HAVE_BULLET
  benchmark::AddCustomContext("bullet_precision", TROCAR_BULLET_PRECISION);
#else
  benchmark::AddCustomContext("bullet_precision", "none (libbullet-dev not found)");
#endif
  for (const Organ& organ : kOrgans) {
    for (std::size_t k = 0; k < 4; ++k) {
      const IntegratorKind kind = kKinds[k];
      benchmark::RegisterBenchmark((std::string("BM_Tissue/") + organ.label + "/" + kKindNames[k]).c_str(),
                                   [&organ, kind](benchmark::State& bs) { bm_ours(bs, organ, kind, true); })
          ->Unit(benchmark::kMicrosecond);
    }
    // The portable scalar passes, for the speed-up of the AVX2 ones.
    benchmark::RegisterBenchmark((std::string("BM_Tissue/") + organ.label + "/xpbd-scalar").c_str(),
                                 [&organ](benchmark::State& bs) { bm_ours(bs, organ, IntegratorKind::kXpbd, false); })
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((std::string("BM_Tissue/") + organ.label + "/semi-implicit-euler-scalar").c_str(),
                                 [&organ](benchmark::State& bs) {
                                   bm_ours(bs, organ, IntegratorKind::kSemiImplicitEuler, false);
                                 })
        ->Unit(benchmark::kMicrosecond);
    // Both AVX2 explicit steps whichever the default picks: pass by pass, and the sweep.
    for (const bool sweep : {false, true})
      benchmark::RegisterBenchmark(
          (std::string("BM_Tissue/") + organ.label + "/semi-implicit-euler-" + (sweep ? "sweep" : "passes")).c_str(),
          [&organ, sweep](benchmark::State& bs) { bm_ours(bs, organ, IntegratorKind::kSemiImplicitEuler, true, sweep); })
          ->Unit(benchmark::kMicrosecond);
#ifdef TROCAR_HAVE_BULLET
    benchmark::RegisterBenchmark((std::string("BM_BulletSoftBody/") + organ.label).c_str(),
                                 [&organ](benchmark::State& bs) { bm_bullet_softbody(bs, organ); })
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((std::string("BM_BulletDeformable/") + organ.label).c_str(),
                                 [&organ](benchmark::State& bs) { bm_bullet_deformable(bs, organ); })
        ->Unit(benchmark::kMicrosecond);
#endif
  }
  return true;
}

[[maybe_unused]] const bool registered = register_all();

}  // namespace
}  // namespace trocar
