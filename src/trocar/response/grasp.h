#pragma once
/// Grasping (step 10 of the seed's response, docs/response.md "The step"): tissue vertices held by
/// closed jaws follow the instrument.
#include <cstdint>
#include <span>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/instrument/instrument.h"

namespace trocar {

/// A tissue vertex held by the jaws.
struct GraspedVertex {
  std::uint32_t vertex = 0;               ///< tissue vertex index
  std::uint32_t instrument_triangle = 0;  ///< the jaw triangle that grasped it
  /// Its position in the instrument's local frame when grasped (m). The instrument is rigid, so
  /// a fixed position relative to the grasping triangle is a fixed position in this frame.
  Vec3 local = Vec3::Zero();
};

/// The set of grasped vertices of one tissue by one instrument. Sized once by reset(); grab()
/// never allocates after the first few grasps (capacity = vertex count).
class Grasp {
 public:
  /// Sizes for a tissue of `vertex_count` vertices and releases everything.
  void reset(std::size_t vertex_count);
  /// True when vertex v is held.
  bool is_grasped(std::uint32_t v) const { return v < flags_.size() && flags_[v] != 0; }
  /// Holds vertex v (at world position x) by `instrument`'s triangle `triangle`; no-op if held.
  void grab(std::uint32_t v, const Vec3& x, std::uint32_t triangle, const Instrument& instrument);
  /// Releases every vertex.
  void release_all();
  /// The tissue's vertices were renumbered (a cut): new vertex v copies old vertex
  /// vertex_origin[v]. Every copy of a held vertex stays held where it was. Allocates.
  void remodel(std::span<const std::uint32_t> vertex_origin);
  /// The held vertices.
  std::span<const GraspedVertex> held() const { return held_; }
  /// Writes every held vertex's position (pose ∘ local) and velocity (the instrument's velocity
  /// there) into the tissue's arrays. Call after the integrator moved the tissue (grasped
  /// vertices are kinematic). Empty `velocities` is allowed.
  void apply(const Instrument& instrument, std::span<Vec3> positions, std::span<Vec3> velocities) const;

 private:
  std::vector<std::uint8_t> flags_;   ///< 1 when held (size = tissue vertex count)
  std::vector<GraspedVertex> held_;   ///< held vertices in grasp order
};

}  // namespace trocar
