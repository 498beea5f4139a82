#pragma once
/// Where fluid that leaves a surface lands (docs/electrosurgery.md, "Bleeding").
///
/// Blood (or irrigation fluid) that runs off a surface's open border or drips from an overhang
/// (BloodFilm's pending drips) falls along gravity. It lands on the first surface under its fall
/// line: of the vertices within `radius` of the line horizontally and at least `clearance` below
/// where it left, and not of the surface it left within 2 `radius` of where it left (so it never
/// lands back where it came from; a pendant drop a few millimetres long touches whatever lies that
/// close under it, so the clearance is small), the one with the least depth plus
/// horizontal distance (the nearest vertex of the highest surface); with none there it falls out of sight
/// into the pool (the pelvis, the lowest point of the cavity). A fall takes time (5 cm in 0.1 s),
/// so landing once per frame, not per physics step, loses nothing that can be seen.
///
/// Cost: the drips are merged into at most `max_columns` fall lines (a drip within `radius` of a
/// line joins it: its volume-weighted place, its lowest start); then one pass over every vertex
/// of every surface tests each line: O(V × lines), no allocation after the first call.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/electrosurgery/bleeding.h"

namespace trocar {

struct LandingSettings {
  /// m: a drop lands on a vertex within this horizontal distance of its fall line (about a mesh
  /// spacing: a surface below is found wherever it has a vertex under the line).
  Real radius = 0.004;
  Real clearance = 1e-4;        ///< m: at least this far below the drip's start
  std::size_t max_columns = 32; ///< fall lines per call (more drips merge into the nearest)
};

/// What one land() did (m³).
struct LandingTally {
  Real landed = 0, landed_blood = 0;  ///< onto a surface below
  Real pooled = 0, pooled_blood = 0;  ///< into the pool (nothing below)
};

class DripLanding {
 public:
  explicit DripLanding(const LandingSettings& settings = {});

  /// Lands every film's pending drips (BloodFilm::pending_drips) and clears them. films[k] is
  /// surface k (null: none), positions[k] its current vertex positions (a span of another size:
  /// the surface neither receives, nor can its drips be placed: they pool). `gravity` (m/s²;
  /// zero: everything pools). The landed fluid is added to its target with its blood
  /// (BloodFilm::add_mixture). No allocation after the first call.
  LandingTally land(std::span<BloodFilm* const> films, std::span<const std::span<const Vec3>> positions,
                    const Vec3& gravity);

  const LandingSettings& settings() const { return settings_; }

 private:
  struct Column {
    Vec3 at;           ///< m: a point of the fall line (volume-weighted over its drips)
    Real start;        ///< m along gravity: the lowest drip's depth
    Real volume, blood;
    Real best = 0;     ///< depth + horizontal distance of the best vertex so far
    std::size_t film = 0;
    std::uint32_t vertex = 0;
    bool found = false;
    Vec3 line = Vec3::Zero();  ///< `at` with its component along gravity removed
    std::size_t source = 0;    ///< the surface of its first drip
    Vec3 from = Vec3::Zero();  ///< where its first drip left
  };
  LandingSettings settings_;
  std::vector<Column> columns_;
};

}  // namespace trocar
