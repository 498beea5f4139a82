// Collision detection per frame, side by side on identical frames: trocar's OHC, BVH and brute
// force against FCL and Bullet (bench/peers). One benchmark iteration = one frame: the tissue's
// vertices are all perturbed (frames precomputed and cycled), every method refits what it keeps
// and counts the intersecting (tool, tissue) triangle pairs. Each benchmark first runs its method
// on every frame and skips with an error when a count differs from the reference
// (reference_pair_count). Scenes, all in mm, against the Maryland grasper jaw (952 T):
//   a_duodenum    duodenum_openhelp.stl, 6,946 T (the thesis-sized scene)
//   b_abdominal   abdominal_wall_openhelp.stl, 31,934 T
//   c_sheet720k   make_sheet 300 × 300 mm, 600 × 600 cells, 30 mm bulge: 720,000 T
// Run with --benchmark_repetitions=5 --benchmark_report_aggregates_only=true for medians.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "collision_peers.h"
#include "trocar/collision/detector.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/io/mesh_io.h"

namespace {

using namespace trocar;

/// The shared meshes: the TROCAR_SHARED_MESHES environment variable when set (a copy of the
/// folder elsewhere), else the path compiled in.
const std::filesystem::path kMeshes = [] {
  const char* env = std::getenv("TROCAR_SHARED_MESHES");
  return std::filesystem::path(env != nullptr && *env != 0 ? env : TROCAR_SHARED_MESHES);
}();

enum class SceneId { kDuodenum, kAbdominal, kSheet720k };

struct SceneData {
  CollisionScene scene;
  std::vector<std::vector<Vec3>> frames;  // precomputed tissue positions, cycled
  std::vector<std::size_t> reference;     // reference pair count per frame
  double mean_pairs = 0;
  std::string error;                      // set when the scene could not be built
};

const char* scene_name(SceneId id) {
  switch (id) {
    case SceneId::kDuodenum: return "a_duodenum";
    case SceneId::kAbdominal: return "b_abdominal";
    case SceneId::kSheet720k: return "c_sheet720k";
  }
  return "?";
}

SceneData& scene_data(SceneId id) {
  static std::map<SceneId, std::unique_ptr<SceneData>> cache;
  std::unique_ptr<SceneData>& slot = cache[id];
  if (slot) return *slot;
  slot = std::make_unique<SceneData>();
  SceneData& d = *slot;
  try {
    TriMesh tool = load_mesh(kMeshes / "grasper_jaw_maryland_left_lapgym.stl");
    TriMesh tissue;
    std::size_t frames = 16;
    switch (id) {
      case SceneId::kDuodenum: tissue = load_mesh(kMeshes / "duodenum_openhelp.stl"); break;
      case SceneId::kAbdominal: tissue = load_mesh(kMeshes / "abdominal_wall_openhelp.stl"); break;
      case SceneId::kSheet720k:
        tissue = make_sheet(300, 300, 600, 600, 30);
        frames = 4;
        break;
    }
    d.scene = make_collision_scene(std::move(tissue), std::move(tool));
    d.frames.resize(frames);
    d.reference.resize(frames);
    for (std::size_t k = 0; k < frames; ++k) {
      tissue_frame(d.scene, k, d.frames[k]);
      d.reference[k] = reference_pair_count(d.scene, d.frames[k]);
      d.mean_pairs += static_cast<double>(d.reference[k]) / static_cast<double>(frames);
    }
  } catch (const std::exception& e) {
    d.error = e.what();
  }
  return d;
}

void bm_collision(benchmark::State& state, SceneId id, PeerKind kind) {
  SceneData& d = scene_data(id);
  if (!d.error.empty()) {
    state.SkipWithError(d.error.c_str());
    return;
  }
  std::unique_ptr<CollisionPeer> peer;
  try {
    peer = make_peer(kind, d.scene);
    for (std::size_t k = 0; k < d.frames.size(); ++k) {
      const std::size_t n = peer->count_pairs(d.frames[k]);
      if (n != d.reference[k]) {
        const std::string message = std::string(peer_name(kind)) + " finds " + std::to_string(n) +
                                    " pairs in frame " + std::to_string(k) + ", the reference " +
                                    std::to_string(d.reference[k]);
        state.SkipWithError(message.c_str());
        return;
      }
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  std::size_t k = 0;
  for (auto _ : state) {
    std::size_t n = peer->count_pairs(d.frames[k]);
    benchmark::DoNotOptimize(n);
    if (++k == d.frames.size()) k = 0;
  }
  state.counters["pairs"] = d.mean_pairs;
  state.counters["tissue_T"] = static_cast<double>(d.scene.tissue.triangle_count());
  state.counters["tool_T"] = static_cast<double>(d.scene.tool.triangle_count());
  if (const CollisionDetector* detector = peer->detector()) {
    // The last frame's split (wall clock) and the broad phase's candidates, for diagnosis.
    state.counters["candidates"] = static_cast<double>(detector->timings().candidate_pairs);
    state.counters["broad_us"] = detector->timings().broad_phase_us;
    state.counters["narrow_us"] = detector->timings().narrow_phase_us;
    if (const OhcStats* ohc = detector->ohc_stats()) {
      state.counters["hashed"] = ohc->primitives_hashed;
      state.counters["entries"] = static_cast<double>(ohc->entries);
      state.counters["clusters"] = ohc->clusters_opened;
      state.counters["cl_pairs"] = ohc->cluster_pairs;
    }
  }
}

/// Registers every compiled-in, practical method on every scene (triangle counts are known up
/// front, so impractical pairs such as brute force at 720K are not registered at all).
const bool registered = [] {
  benchmark::AddCustomContext("collision_peers", peers_build_info());
  const std::size_t tool_t = 952;
  const struct {
    SceneId id;
    std::size_t tissue_t;
  } scenes[] = {{SceneId::kDuodenum, 6946}, {SceneId::kAbdominal, 31934}, {SceneId::kSheet720k, 720000}};
  for (const auto& s : scenes) {
    for (PeerKind kind : all_peer_kinds()) {
      if (!peer_available(kind) || !peer_practical(kind, s.tissue_t, tool_t)) continue;
      const std::string name = std::string("collision/") + scene_name(s.id) + "/" + peer_name(kind);
      benchmark::RegisterBenchmark(name.c_str(), bm_collision, s.id, kind)->Unit(benchmark::kMicrosecond);
    }
  }
  return true;
}();

}  // namespace
