#pragma once
/// The viewer's settings panel (Dear ImGui): what the original simulator's settings dialog set —
/// material, response method, broad phase, integrator, time step, force scale — edited on a copy
/// of the scene's JSON and applied by restarting the scene (a session recording then starts from
/// the scene it replays); plus overlays, live timing graphs and the run controls.
#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trocar/render/renderer.h"

namespace trocar {

/// One tissue's editable material (the effective values: preset, then explicit keys).
struct MaterialEdit {
  std::string name;
  float k_structural = 0, k_bending = 0, damping = 0, k_area = 0, k_volume = 0;
  int integrator = 3;  ///< 0 explicit, 1 semi-implicit, 2 implicit Euler, 3 xpbd (the default)
};

/// Everything the panel edits in the scene.
struct SceneEdits {
  std::vector<MaterialEdit> tissues;
  int method = 0;           ///< index into kMethods
  int broad_phase = 0;      ///< index into kBroadPhases
  float timestep = 1e-3f;   ///< s
  float force_scale = 1;    ///< the driven instrument's device force scale
  float stiffness = 0;      ///< response stiffness K (N/m)
};

/// The effective settings of a scene document (throws trocar::Error for an unknown preset).
SceneEdits edits_from(const nlohmann::json& doc, int drive);
/// Writes the edits into the document's keys.
void apply_edits(nlohmann::json& doc, const SceneEdits& edits, int drive);

/// A ring of the last values of one series, for ImGui's plots.
struct Series {
  static constexpr int kLength = 240;
  std::array<float, kLength> values{};
  int next = 0;
  void add(float v) {
    values[std::size_t(next)] = v;
    next = (next + 1) % kLength;
  }
  float last() const { return values[std::size_t((next + kLength - 1) % kLength)]; }
};

/// What the panel shows live.
struct PanelLive {
  Series step_us, broad_us, narrow_us, response_us, deformation_us, haptic_khz, frame_ms;
  double haptic_rate_hz = 0;
  double deadline_miss_fraction = 0;
  double physics_rate_hz = 0;
  double sim_time = 0;
  double fps = 0;
  bool paused = false;
  bool recording = false;
  std::string recording_path;
  std::string status;       ///< last message (an error of a rejected edit, a saved file)
  std::string device;       ///< the driven instrument's device
  std::string surgery;      ///< electrosurgery and bleeding now (surgery_status), empty: nothing
  bool free_camera = false;
};

/// What the user asked for this frame.
struct PanelActions {
  bool apply = false, pause = false, step = false, reset = false, record = false, screenshot = false, camera = false;
};

/// What the trainee is doing with energy and fluid, and what bleeds, one line each: every
/// instrument in the body whose pedal is down ("hook: energy on", "burning" while it touches
/// tissue), whose suction or irrigation valve is open, then the blood lost (ml, all wounds) and
/// how many wounds still bleed. Empty when nothing of it is going on and nothing has bled.
/// `names` are the instruments' (snapshot order; a missing one is "instrument i").
std::string surgery_status(const ViewSnapshot& snap, const std::vector<std::string>& names);

/// Draws the panel (between ImGui::NewFrame and ImGui::Render).
PanelActions draw_panel(SceneEdits& edits, RenderOptions& render, const PanelLive& live);

}  // namespace trocar
