#pragma once
/// The viewer's mouse and keyboard (docs/render.md "Viewer controls"): one place that turns
/// window events into a port command for the driven instrument and into the free camera's orbit.
/// GLFW's callbacks and the test's injected events (--inject) both go through it.
#include <string>
#include <vector>

#include "trocar/device/port_device.h"
#include "trocar/scene/camera_spec.h"

namespace trocar {

/// Mouse buttons and the keys the viewer uses (values independent of GLFW).
enum class ViewerKey { kInsert, kRetract, kYawLeft, kYawRight, kPitchUp, kPitchDown, kRollLeft, kRollRight, kJaw,
                       kToggleCamera, kPause, kStep, kReset, kRecord, kFire, kExchange, kEnergy, kSuction, kIrrigate,
                       kOther };

/// Event-to-motion mapping.
class ViewerInput {
 public:
  static constexpr double kRadiansPerPixel = 0.004;   ///< left drag: yaw (x) and pitch (y)
  static constexpr double kRollPerPixel = 0.01;       ///< right drag x: roll
  static constexpr double kDepthPerPixel = 0.0002;    ///< right drag y: insertion (m/px)
  static constexpr double kDepthPerNotch = 0.002;     ///< wheel: insertion (m per notch)
  static constexpr double kKeyRate = 0.6;             ///< rad/s and (×0.05) m/s while a key is held

  /// button 0 left, 1 right, 2 middle; `over_panel`: the settings panel has the mouse.
  void mouse_button(int button, bool down, double x, double y, bool over_panel = false);
  void cursor(double x, double y);
  /// The pointer's position as the last cursor event gave it (false before the first): the
  /// window system's events arrive in order, and a press belongs where the pointer was then,
  /// not where it is when a slow frame gets to it.
  bool last_cursor(double& x, double& y) const {
    x = x_, y = y_;
    return have_cursor_;
  }
  void scroll(double notches, bool over_panel = false);
  /// A key went down or up; returns the key's action for one-shot keys (pause, step, reset,
  /// record, camera) on the press, kOther otherwise.
  ViewerKey key(ViewerKey k, bool down);
  /// Held keys move the instrument at kKeyRate over dt seconds.
  void advance(double dt);

  /// The command (and whether it changed since the last take_changed()).
  const PortCommand& command() const { return command_; }
  bool take_changed() {
    const bool c = changed_;
    changed_ = false;
    return c;
  }
  void set_command(const PortCommand& c) { command_ = c; changed_ = true; }
  /// Free camera: when on, left drag orbits it and the wheel zooms instead.
  bool free_camera = false;
  /// The free camera's orbit (yaw, pitch, distance), updated by the mouse in free mode.
  CameraSpec orbit;

 private:
  PortCommand command_;
  bool changed_ = false;
  bool left_ = false, right_ = false;
  double x_ = 0, y_ = 0;
  bool have_cursor_ = false;
  bool held_[int(ViewerKey::kOther) + 1] = {};
};

/// One injected event (`--inject FILE`: lines "T down|up|move|scroll|key|keyup|settle ARGS", T
/// in seconds since the viewer started, or fN: before frame N is drawn (frame 0 first; a script's
/// times are all one or all the other); # comments).
struct InjectedEvent {
  double time = 0;            ///< s (a frame script: the frame, as a number)
  int frame = -1;             ///< ≥ 0: the frame it is played before (a frame script)
  std::string kind;           ///< down, up, move, scroll, key, keyup, settle
  int button = 0;             ///< down/up: 0 left, 1 right
  double x = 0, y = 0;        ///< move/down/up: pixels; scroll: y notches
  ViewerKey key = ViewerKey::kOther;  ///< key/keyup
};

/// Reads an event script; throws trocar::Error "FILE:LINE: reason" for a malformed line.
std::vector<InjectedEvent> read_injected_events(const std::string& file);

/// Key names of the scripts: insert, retract, yaw-left, yaw-right, pitch-up, pitch-down,
/// roll-left, roll-right, jaw, camera, pause, step, reset, record, fire, exchange, energy,
/// suction, irrigate.
ViewerKey viewer_key_from_name(const std::string& name);

}  // namespace trocar
