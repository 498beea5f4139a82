#pragma once
/// An instrument's `"device"` (docs/scene.md "Instruments", docs/devices.md): which driver moves it
/// in real-time mode, where the device's frame sits in the world, and the coupling and force
/// limits. Plain data: the runtime builds the driver (the core never links a device library).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "trocar/core/pose.h"
#include "trocar/core/types.h"

namespace trocar {

/// Scene key `instruments[i].device`.
struct DeviceSpec {
  bool given = false;          ///< the scene has a "device" for this instrument
  std::string driver = "scripted";  ///< null | scripted | replay | openigtlink | spacemouse | mouse
  std::string where;           ///< "FILE: instruments[i].device", for errors found later
  int port = 18944;            ///< openigtlink: TCP port (0 = any free port)
  std::filesystem::path recording;  ///< replay: the recording (relative to the scene file)
  Pose device_to_world;        ///< "translate" (m) and "rotate_deg": the device frame in the world
  Real scale = 1;              ///< "scale": device metres → world metres
  Real coupling_stiffness = 1000;  ///< "coupling.stiffness" (N/m)
  Real coupling_damping = 0.5;     ///< "coupling.damping" (N·s/m)
  Real max_force = 3.3;        ///< "max_force" (N), also ≤ the driver's own maximum
  Real force_scale = 1;        ///< "force_scale": simulated force → device force
  Real slew_rate = 2000;       ///< "slew_rate" (N/s)
  Real engage_below = 0.2;     ///< "engage_below" (N): safe-start threshold
  Real ramp_time = 0.25;       ///< "ramp_time" (s): safe-start ramp
  Real damping = 2.0;          ///< "damping": the device's own b (N·s/m), for the passivity bound
  Real stale_after = 0.1;      ///< "stale_after" (s): openigtlink, silence that counts as stale
  /// scripted: the scene's "events" on this instrument as button presses, so that the real-time
  /// runtime plays them too: at `t` (s), `buttons` = action << 1 (button 1 fires, 2 exchanges; 3,
  /// 5 and 7, the pedal and the valves, held `until` their off).
  struct Press {
    double t = 0;
    std::uint32_t buttons = 0;
    double until = -1;  ///< s: held until then (the pedal); < 0: a short press
  };
  std::vector<Press> presses;
  bool has_pivot = false;      ///< mouse: "pivot" given
  Vec3 pivot = Vec3::Zero();   ///< mouse: "pivot", the trocar port the shaft turns about (world, m)
};

}  // namespace trocar
