#include "collision_command.h"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "collision_peers.h"
#include "trocar/core/error.h"
#include "trocar/core/statistics.h"
#include "trocar/mesh/io/mesh_io.h"

namespace trocar::cli {
namespace {

struct CollisionArgs {
  std::string tissue;
  std::string tool;
  std::size_t frames = 100;
  double tissue_scale = 1;
  double tool_scale = 1;
  bool json = false;
};

/// CPU time of the calling thread (seconds): robust to other processes sharing the core.
double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

TriMesh load_checked(const std::string& file, double scale, const char* what) {
  TriMesh mesh = load_mesh(file);  // FileError names the file
  if (mesh.triangles.empty()) throw Error(file + ": the " + std::string(what) + " mesh has no triangles");
  if (!mesh.indices_valid()) throw Error(file + ": the " + std::string(what) + " mesh has out-of-range indices");
  for (const Vec3& p : mesh.positions) {
    if (!p.allFinite()) throw Error(file + ": the " + std::string(what) + " mesh has non-finite positions");
  }
  if (scale != 1) mesh.scale(scale);
  return mesh;
}

struct MethodResult {
  PeerKind kind;
  std::unique_ptr<CollisionPeer> peer;
  std::vector<double> times_us;
  std::size_t pairs = 0;
};

void run_collision(const CollisionArgs& args, int& exit_code) {
  CollisionScene scene = make_collision_scene(load_checked(args.tissue, args.tissue_scale, "tissue"),
                                              load_checked(args.tool, args.tool_scale, "tool"));
  const std::size_t tissue_t = scene.tissue.triangle_count();
  const std::size_t tool_t = scene.tool.triangle_count();

  std::vector<MethodResult> methods;
  std::vector<std::string> skipped;
  for (PeerKind kind : all_peer_kinds()) {
    if (!peer_available(kind)) {
      skipped.push_back(std::string(peer_name(kind)) + " (not compiled in)");
    } else if (!peer_practical(kind, tissue_t, tool_t)) {
      skipped.push_back(std::string(peer_name(kind)) + " (too slow at this size)");
    } else {
      methods.push_back({kind, make_peer(kind, scene), {}, 0});
    }
  }

  // Each method in turn runs frame 0 untimed (first builds, buffer growth) and then frames
  // 1..N timed. tissue_frame() is deterministic, so every method sees the identical positions;
  // running one method at a time keeps its data in cache as in a simulator's frame loop.
  std::vector<Vec3> positions;
  std::vector<std::vector<std::size_t>> counts(methods.size());
  for (std::size_t i = 0; i < methods.size(); ++i) {
    MethodResult& m = methods[i];
    tissue_frame(scene, 0, positions);
    m.peer->count_pairs(positions);
    for (std::size_t f = 1; f <= args.frames; ++f) {
      tissue_frame(scene, f, positions);
      const double start = thread_cpu_seconds();
      const std::size_t n = m.peer->count_pairs(positions);
      m.times_us.push_back(1e6 * (thread_cpu_seconds() - start));
      counts[i].push_back(n);
      m.pairs = n;
    }
  }
  std::size_t mismatched = 0;
  for (std::size_t f = 0; f < args.frames; ++f) {
    for (std::size_t i = 1; i < methods.size(); ++i) {
      if (counts[i][f] != counts[0][f]) {
        ++mismatched;
        break;
      }
    }
  }

  nlohmann::json all = nlohmann::json::array();
  double ohc_median = 0;
  std::vector<std::pair<double, double>> stats;  // median, p95
  for (MethodResult& m : methods) {
    const double median = trocar::median(m.times_us);
    const double p95 = quantile(m.times_us, 0.95);
    stats.emplace_back(median, p95);
    if (m.kind == PeerKind::kOhc) ohc_median = median;
    all.push_back({{"method", peer_name(m.kind)}, {"median_us", median}, {"p95_us", p95}, {"pairs", m.pairs}});
  }
  if (args.json) {
    std::cout << all.dump(2) << "\n";
  } else {
    std::cout << "tissue  " << args.tissue << ": " << scene.tissue.vertex_count() << " vertices, " << tissue_t
              << " triangles\n"
              << "tool    " << args.tool << ": " << scene.tool.vertex_count() << " vertices, " << tool_t
              << " triangles\n"
              << "frames  " << args.frames << " (every tissue vertex moved each frame; thread CPU time per frame; pairs of the last frame)\n"
              << "peers   " << peers_build_info() << "\n\n";
    char line[160];
    std::snprintf(line, sizeof line, "%-16s %12s %12s %8s %10s\n", "method", "median_us", "p95_us", "pairs", "vs_ohc");
    std::cout << line;
    for (std::size_t i = 0; i < methods.size(); ++i) {
      const double ratio = ohc_median > 0 ? stats[i].first / ohc_median : 0;
      std::snprintf(line, sizeof line, "%-16s %12.1f %12.1f %8zu %9.1fx\n", peer_name(methods[i].kind),
                    stats[i].first, stats[i].second, methods[i].pairs, ratio);
      std::cout << line;
    }
    for (const std::string& s : skipped) std::cout << "skipped " << s << "\n";
  }
  if (mismatched > 0) {
    std::cerr << "trocar: warning: the methods disagree on the pair count in " << mismatched << " of "
              << args.frames << " frames\n";
    exit_code = 1;
  }
}

}  // namespace

void add_collision_command(CLI::App& app, int& exit_code) {
  auto a = std::make_shared<CollisionArgs>();
  CLI::App* col = app.add_subcommand(
      "collision",
      "Collision detection per frame: trocar OHC, BVH, brute force, FCL and Bullet on the same deforming frames");
  col->add_option("--tissue", a->tissue, "Tissue mesh (deformed a little every frame)")->required();
  col->add_option("--tool", a->tool, "Tool mesh (placed to cut into the tissue's upper surface)")->required();
  col->add_option("--frames", a->frames, "Timed frames")->check(CLI::Range(1, 1000000))->capture_default_str();
  col->add_option("--tissue-scale", a->tissue_scale, "Scale applied to the tissue's positions")
      ->check(CLI::PositiveNumber)->capture_default_str();
  col->add_option("--tool-scale", a->tool_scale, "Scale applied to the tool's positions")
      ->check(CLI::PositiveNumber)->capture_default_str();
  col->add_flag("--json", a->json, "Print a JSON list of {method, median_us, p95_us, pairs}");
  col->callback([a, &exit_code] { run_collision(*a, exit_code); });
}

}  // namespace trocar::cli
