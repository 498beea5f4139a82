// libFuzzer target for the scene parser (scene/scene.h, parse_scene): any text must either give
// a scene or throw trocar::Error, and a scene that loads must hold finite numbers only.
//
// The fuzzer explores the parser, not the cost of the mesh generators at their largest sizes
// (a sheet may have 1000 × 1000 cells: docs/scene.md): inputs asking for more than
// kMaxCount cells, segments, rings or subdivisions, or more than kMaxBodies bodies, are skipped
// before parsing. Mesh files are looked for in a folder that does not exist.
#include <cmath>
#include <cstdint>
#include <string_view>

#include <nlohmann/json.hpp>

#include "trocar/core/error.h"
#include "trocar/scene/scene.h"

namespace {

constexpr std::int64_t kMaxCount = 48;
constexpr std::size_t kMaxBodies = 4;

void check(bool ok) {
  if (!ok) __builtin_trap();
}

bool finite(const trocar::Vec3& v) { return v.allFinite(); }

// True when the document asks for more work than the fuzzer should spend on one input. The
// schema is never deeper than a few levels, so the walk stops at 16.
bool too_costly(const nlohmann::json& v, int depth = 0) {
  if (depth > 16) return false;
  if (v.is_array()) {
    for (const auto& e : v)
      if (too_costly(e, depth + 1)) return true;
    return false;
  }
  if (!v.is_object()) return false;
  for (const auto& [key, e] : v.items()) {
    if ((key == "tissues" || key == "instruments" || key == "rigids") && e.is_array() && e.size() > kMaxBodies)
      return true;
    const bool count = key == "nx" || key == "ny" || key == "segments" || key == "rings" || key == "sac_rings" ||
                       key == "sheet_rings" || key == "subdivisions";
    if (count && e.is_number() && !(e.get<double>() <= double(kMaxCount))) return true;
    if (too_costly(e, depth + 1)) return true;
  }
  return false;
}

void check_scene(const trocar::Scene& s) {
  check(std::isfinite(s.timestep) && s.timestep > 0 && std::isfinite(s.duration) && s.duration >= 0);
  check(finite(s.gravity));
  check(s.devices.size() == s.world.instruments.size() && s.textures.size() == s.world.tissues.size());
  for (const auto& t : s.world.tissues) {
    const trocar::MassSpringSettings& m = t->settings;
    check(!m.triangles.empty() && m.masses.size() == m.rest_positions.size());
    for (const trocar::Vec3& p : t->state.positions) check(finite(p));
    for (trocar::Real x : m.masses) check(std::isfinite(x) && x >= 0);
    for (trocar::Real x : m.inverse_masses) check(std::isfinite(x) && x >= 0);
    for (trocar::Real x : m.rest_areas) check(std::isfinite(x));
    for (const trocar::Spring& k : m.springs)
      check(std::isfinite(k.rest_length) && std::isfinite(k.stiffness) && std::isfinite(k.damping));
    check(std::isfinite(m.rest_volume) && std::isfinite(m.mean_rest_area));
  }
  for (const auto& i : s.world.instruments) {
    check(!i.instrument.local_mesh().triangles.empty() && std::isfinite(i.thickness));
    for (const trocar::Vec3& p : i.instrument.local_mesh().positions) check(finite(p));
    // The motion between and beyond its keyframes.
    trocar::Real before = -1;
    for (const trocar::Keyframe& k : i.motion.keyframes()) {
      for (trocar::Real t : {k.t, (before + k.t) / 2}) {
        const trocar::MotionSample m = i.motion.sample(t);
        check(finite(m.pose.translation) && m.pose.rotation.coeffs().allFinite() && std::isfinite(m.jaw));
      }
      before = k.t;
    }
  }
  for (const auto& r : s.world.rigids) {
    check(!r.mesh.triangles.empty());
    for (const trocar::Vec3& p : r.mesh.positions) check(finite(p));
  }
  for (const auto& c : s.cameras) check(finite(c.port) && finite(c.target) && finite(c.up));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  if (!doc.is_discarded() && too_costly(doc)) return 0;
  try {
    check_scene(trocar::parse_scene(text, "fuzz.json", "/nonexistent/trocar-fuzz"));
  } catch (const trocar::Error&) {
    // malformed or invalid scene, reported properly
  }
  return 0;
}
