#pragma once
/// Scene files (JSON, schema 1, docs/scene.md) → a World and its settings.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/geometry/zone.h"
#include "trocar/procedure/actions.h"
#include "trocar/procedure/task.h"
#include "trocar/scene/appearance.h"
#include "trocar/scene/camera_spec.h"
#include "trocar/scene/device_spec.h"
#include "trocar/sim/simulation.h"
#include "trocar/sim/world.h"

namespace trocar {

/// The current scene schema version.
inline constexpr int kSceneSchema = 1;

/// A loaded scene: what to simulate and how.
struct Scene {
  std::string name;                 ///< "name", default the file's stem
  Real timestep = 1e-3;             ///< s, "timestep"
  Real duration = 1.0;              ///< s, "duration"
  Vec3 gravity = Vec3(0, 0, -9.81); ///< m/s², "gravity"
  World world;                      ///< tissues, instruments, rigid obstacles (built)
  SimulationSettings settings;      ///< collision and response
  /// Per instrument (same index): its "device", for the real-time runtime (given = false when
  /// the scene has only "motion"; the runtime then plays the motion as a scripted device).
  std::vector<DeviceSpec> devices;
  /// "camera": one object or a list of them (empty: the renderer frames the scene itself).
  std::vector<CameraSpec> cameras;
  /// Per tissue (same index): its "texture" image (PNG, resolved against the scene's folder), or
  /// empty for the renderer's procedural tissue texture. Used only where the mesh has UVs.
  std::vector<std::filesystem::path> textures;
  /// Per tissue and per rigid (same index): how it looks ("appearance", or the anatomy's).
  std::vector<Appearance> tissue_appearance;
  std::vector<Appearance> rigid_appearance;
  /// Named regions a trainee must not injure ("zones", or the anatomy's).
  std::vector<NamedZone> zones;
  /// Named points of the anatomy (m): where tacks belong, the defect's centre, the wall's plane...
  std::map<std::string, Vec3> landmarks;
  /// Scripted actions ("events"): fire the tacker, exchange an instrument, at given times.
  std::vector<ScriptedAction> actions;
  /// "task": what the trainee must do (none: the scene is a free simulation).
  std::optional<TaskSpec> task;
};

/// Reads and validates a scene file. Every key is checked: an unknown key, a wrong type, a
/// missing file or a bad value throws trocar::Error "FILE: KEY.PATH: reason". Mesh paths are
/// relative to the scene file's folder.
Scene load_scene(const std::filesystem::path& file);

/// The scene file's text (what a session recording stores). Throws trocar::Error naming the
/// file when it cannot be read.
std::string read_scene_text(const std::filesystem::path& file);

/// The same from text; `file` names it in errors, `dir` resolves relative mesh paths.
Scene parse_scene(std::string_view text, const std::string& file, const std::filesystem::path& dir);

}  // namespace trocar
