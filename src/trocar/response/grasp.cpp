#include "trocar/response/grasp.h"

#include <algorithm>

namespace trocar {

void Grasp::reset(std::size_t vertex_count) {
  flags_.assign(vertex_count, 0);
  held_.clear();
  held_.reserve(vertex_count);
}

void Grasp::remodel(std::span<const std::uint32_t> vertex_origin) {
  std::vector<std::int64_t> slot(flags_.size(), -1);
  for (std::size_t k = 0; k < held_.size(); ++k) slot[held_[k].vertex] = static_cast<std::int64_t>(k);
  std::vector<GraspedVertex> held;
  held.reserve(vertex_origin.size());
  std::vector<std::uint8_t> flags(vertex_origin.size(), 0);
  for (std::uint32_t v = 0; v < vertex_origin.size(); ++v) {
    const std::uint32_t old = vertex_origin[v];
    if (old >= slot.size() || slot[old] < 0) continue;
    GraspedVertex g = held_[static_cast<std::size_t>(slot[old])];
    g.vertex = v;
    held.push_back(g);
    flags[v] = 1;
  }
  held_ = std::move(held);
  flags_ = std::move(flags);
}

void Grasp::grab(std::uint32_t v, const Vec3& x, std::uint32_t triangle, const Instrument& instrument) {
  if (v >= flags_.size() || flags_[v] != 0) return;
  flags_[v] = 1;
  const Pose& pose = instrument.pose();
  // local = R⁻¹(x − t)
  held_.push_back({v, triangle, pose.rotation.conjugate() * (x - pose.translation)});
}

void Grasp::release_all() {
  for (const GraspedVertex& g : held_) flags_[g.vertex] = 0;
  held_.clear();
}

void Grasp::apply(const Instrument& instrument, std::span<Vec3> positions, std::span<Vec3> velocities) const {
  const Mat3 r = instrument.pose().rotation_matrix();
  const Vec3 t = instrument.pose().translation;
  for (const GraspedVertex& g : held_) {
    if (g.vertex >= positions.size()) continue;
    const Vec3 x = r * g.local + t;
    positions[g.vertex] = x;
    if (g.vertex < velocities.size()) velocities[g.vertex] = instrument.velocity_at(x);
  }
}

}  // namespace trocar
