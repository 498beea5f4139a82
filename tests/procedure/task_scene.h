#pragma once
// A hand-built world for the procedure tests: a flat 12 × 12 cm wall sheet at z = 0 (corners
// fixed; the cavity is +z), a 9 × 9 cm mesh sheet 1 mm above it centred at the origin (5 mm
// cells), a 2 cm cube for the sac (z ∈ [0.005, 0.025]: all beyond the wall), and a capsule tacker
// (radius 2.5 mm, shaft along +z from its local origin, so its tip is 2.5 mm below the origin).
// No gravity: nothing moves unless a test moves it. Landmarks: the wall plane, the defect at the
// origin, three tack landmarks; `extra` is spliced into the root object (zones, task...).
#include <string>

#include "trocar/scene/scene.h"

namespace trocar::test {

inline std::string task_scene_text(const std::string& extra, const std::string& instrument_position = "[0, 0, 0.05]") {
  return R"({
  "schema": 1, "name": "task-test", "timestep": 0.001, "duration": 0.01, "gravity": [0, 0, 0],
  "tissues": [
    { "name": "wall", "mesh": {"generate": "sheet", "width": 0.12, "height": 0.12, "nx": 12, "ny": 12},
      "material": {"preset": "peritoneum"}, "fixed": {"indices": [0, 12, 156, 168]}, "integrator": "implicit-euler" },
    { "name": "mesh", "mesh": {"generate": "sheet", "width": 0.09, "height": 0.09, "nx": 18, "ny": 18},
      "translate": [0, 0, 0.001], "material": {"preset": "peritoneum"}, "integrator": "implicit-euler" },
    { "name": "sac", "mesh": {"generate": "box", "size": [0.02, 0.02, 0.02]}, "translate": [0, 0, 0.015],
      "material": {"preset": "peritoneum"}, "integrator": "implicit-euler" }],
  "instruments": [{ "name": "tacker", "mesh": {"generate": "capsule", "radius": 0.0025, "length": 0.05,
                                               "segments": 12, "rings": 3},
                    "top_vertex": "auto", "motion": {"keyframes": [{"t": 0, "position": )" +
         instrument_position + R"(}]}}],
  "landmarks": {"wall_point": [0, 0, 0], "wall_normal": [0, 0, 1], "defect_centre": [0, 0, 0],
                "tack_cooper": [-0.02, 0, 0], "tack_medial": [0.02, 0, 0], "tack_lateral": [0, 0.02, 0]})" +
         (extra.empty() ? std::string() : ",\n  " + extra) + "\n}";
}

inline Scene task_scene(const std::string& extra = R"("task": {"sac": "sac", "mesh": "mesh"})") {
  return parse_scene(task_scene_text(extra), "task-test.json", ".");
}

}  // namespace trocar::test
