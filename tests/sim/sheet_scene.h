#pragma once
// A capsule probe (radius 2 mm, shaft along +z from its local origin, the centre of its lower
// hemisphere, so its tip is 2 mm below the origin; 2·3·12 + 2 = 74 vertices) and a flat
// 60 × 60 mm peritoneum sheet (z = 0, normals +z, corners fixed), for the open-tissue metrics
// tests.
#include <string>

namespace trocar::test {

/// The probe's origin moves in a straight line from `from` to `to` over `seconds`, then holds;
/// detection every `period` s; penalty stiffness `stiffness` (N/m; 0: the sheet is not pushed);
/// `back_seconds` > 0: then back to `from` over that time.
inline std::string sheet_scene(const std::string& from, const std::string& to, double seconds, double period,
                               double stiffness = 200, double back_seconds = 0) {
  const std::string back = back_seconds > 0 ? R"(,
                      {"t": )" + std::to_string(seconds + back_seconds) + R"(, "position": )" + from + "}"
                                            : std::string();
  return R"({
  "schema": 1, "name": "probe-sheet", "timestep": 0.001, "duration": 0.2, "gravity": [0, 0, 0],
  "tissues": [{ "name": "sheet", "mesh": {"generate": "sheet", "width": 0.06, "height": 0.06, "nx": 20, "ny": 20},
                "material": {"preset": "peritoneum", "k_home": 20},
                "fixed": {"indices": [0, 20, 420, 440]},
                "integrator": "implicit-euler" }],
  "instruments": [{ "name": "probe", "mesh": {"generate": "capsule", "radius": 0.002, "length": 0.04,
                                              "segments": 12, "rings": 3},
                    "top_vertex": "auto",
                    "motion": {"keyframes": [
                      {"t": 0, "position": )" + from + R"(},
                      {"t": )" + std::to_string(seconds) + R"(, "position": )" + to + "}" + back + R"(]}}],
  "collision": {"broad_phase": "ohc", "cell_size": "auto", "period": )" + std::to_string(period) + R"(},
  "response": {"method": "obb", "stiffness": )" + std::to_string(stiffness) + R"(, "damping": )" +
         std::string(stiffness > 0 ? "5" : "0") + R"(, "max_force": 10}
})";
}

}  // namespace trocar::test
