#pragma once
// The developer scene with the real meshes of ../shared/data/meshes: the shared hook probe
// (mm → m, turned so the shaft points up and the hook down) presses on the shared liver (cm → m,
// bottom 12 % fixed, preset "liver"). Used by tests/sim and bench/sim; absent meshes → nullopt.
#include <filesystem>
#include <optional>
#include <string>

#include "trocar/scene/scene.h"
#include "support/shared_data.h"

namespace trocar::test {

/// The scene text, or nothing when the shared meshes are absent. The probe's hook tip starts
/// 1 cm above the liver's top and goes down 2 cm in `press_time` seconds, then holds.
/// `method`: the response method (docs/response.md "Baselines").
inline std::optional<std::string> probe_liver_scene_text(double press_time = 1.0, const std::string& method = "obb") {
  const std::optional<std::filesystem::path> liver_found = test::shared_mesh_path("liver_sofa_smooth.obj");
  const std::optional<std::filesystem::path> probe_found = test::shared_mesh_path("probe_hook_electrode_lapgym.stl");
  if (!liver_found || !probe_found) return std::nullopt;
  const std::filesystem::path& liver = *liver_found;
  const std::filesystem::path& probe = *probe_found;
  // Liver in metres: x ∈ [−0.047, 0.017], y ∈ [0.003, 0.052], z ∈ [−0.017, 0.027]. The probe's
  // hook spans z ∈ [0, 15] mm in its file; rotated 180° about x it points down from the origin.
  return R"({"schema": 1, "name": "probe-liver", "timestep": 0.001, "duration": 1.5, "gravity": [0, 0, -9.81],
  "tissues": [{"name": "liver", "mesh": ")" + liver.string() + R"(", "scale": 0.01,
               "material": {"preset": "liver"},
               "fixed": {"below_plane": {"point": [0, 0, -0.0115], "normal": [0, 0, 1]}},
               "integrator": "implicit-euler"}],
  "instruments": [{"name": "probe", "mesh": ")" + probe.string() + R"(", "scale": 0.001, "top_vertex": "auto",
                   "motion": {"keyframes": [
                     {"t": 0, "position": [-0.012, 0.027, 0.052], "rotate_deg": [180, 0, 0]},
                     {"t": )" + std::to_string(press_time) + R"(, "position": [-0.012, 0.027, 0.032], "rotate_deg": [180, 0, 0]}]}}],
  "collision": {"broad_phase": "ohc", "cell_size": "auto"},
  "response": {"method": ")" + method + R"(", "stiffness": 2000, "damping": 5, "max_force": 10}
})";
}

}  // namespace trocar::test
