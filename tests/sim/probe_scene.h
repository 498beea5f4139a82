#pragma once
// A small probe–sphere scene shared by the simulation tests: a capsule probe (radius 3 mm, its
// tip's hemisphere centred on its local origin, so the tip is 3 mm below the keyframe position;
// shaft along +z) moves down onto an icosphere tissue (radius 30 mm, bottom fixed) and then
// holds still.
#include <string>

#include "trocar/scene/scene.h"

namespace trocar::test {

/// Scene text with the probe's keyframes given as JSON objects ("{"t": 0, "position": [...]}, ...").
inline std::string probe_scene_text_with_keyframes(const std::string& keyframes, const std::string& extra = "") {
  return R"({
  "schema": 1, "name": "probe-sphere", "timestep": 0.001, "duration": 0.2, "gravity": [0, 0, 0],
  "tissues": [{ "name": "ball", "mesh": {"generate": "icosphere", "radius": 0.03, "subdivisions": 3},
                "material": {"mass": 0.1, "k_structural": 200, "k_bending": 20, "damping": 2,
                             "spring_damping": 0.05, "k_volume": 500, "k_home": 20},
                "fixed": {"below_plane": {"point": [0, 0, -0.015], "normal": [0, 0, 1]}},
                "integrator": "implicit-euler" }],
  "instruments": [{ "name": "probe", "mesh": {"generate": "capsule", "radius": 0.003, "length": 0.05,
                                              "segments": 12, "rings": 3},
                    "top_vertex": "auto",
                    "motion": {"keyframes": [)" + keyframes + R"(]}}],
  "collision": {"broad_phase": "ohc", "cell_size": "auto"},
  "response": {"method": "obb", "stiffness": 200, "damping": 10, "max_force": 10})" + extra + R"(
})";
}

/// Scene text: the probe's keyframe position goes from z = `z_start` to `z_end` (m) between t = 0
/// and t = `t_end` (s), then holds.
inline std::string probe_scene_text(double z_start, double z_end, double t_end, const std::string& extra = "") {
  return probe_scene_text_with_keyframes(R"({"t": 0, "position": [0, 0, )" + std::to_string(z_start) + R"(]},
                      {"t": )" + std::to_string(t_end) + R"(, "position": [0, 0, )" + std::to_string(z_end) + "]}",
                                         extra);
}

/// The probe scene, loaded.
inline Scene probe_scene(double z_start, double z_end, double t_end) {
  return parse_scene(probe_scene_text(z_start, z_end, t_end), "probe.json", ".");
}

}  // namespace trocar::test
