#include "trocar/render/viewer_input.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "trocar/core/error.h"
#include "trocar/procedure/actions.h"

namespace trocar {

void ViewerInput::mouse_button(int button, bool down, double x, double y, bool over_panel) {
  if (down && over_panel) return;  // a click on the panel is the panel's
  x_ = x;
  y_ = y;
  if (button == 0) left_ = down;
  if (button == 1) right_ = down;
}

void ViewerInput::cursor(double x, double y) {
  const double dx = x - x_, dy = y - y_;
  x_ = x;
  y_ = y;
  have_cursor_ = true;
  if (free_camera) {
    if (left_) {
      orbit.yaw_deg -= dx * 0.3;
      orbit.pitch_deg = std::clamp(orbit.pitch_deg + dy * 0.3, -89.0, 89.0);
    }
    return;
  }
  if (left_) {
    command_.yaw -= dx * kRadiansPerPixel;
    command_.pitch += dy * kRadiansPerPixel;
    changed_ = true;
  }
  if (right_) {
    command_.roll += dx * kRollPerPixel;
    command_.depth -= dy * kDepthPerPixel;  // drag up = deeper
    changed_ = true;
  }
}

void ViewerInput::scroll(double notches, bool over_panel) {
  if (over_panel) return;
  if (free_camera) {
    orbit.distance = std::max(0.01, orbit.distance * (notches > 0 ? 0.9 : 1.1));
    return;
  }
  command_.depth += notches * kDepthPerNotch;
  changed_ = true;
}

ViewerKey ViewerInput::key(ViewerKey k, bool down) {
  const bool was = held_[int(k)];
  held_[int(k)] = down;
  if (k == ViewerKey::kJaw) {  // held: jaws closed
    command_.jaw = down ? 1 : 0;
    changed_ = true;
  }
  // Held: the device's buttons 1 (fire), 2 (exchange), 3 (the electrode's pedal), 5 (suction)
  // and 7 (irrigation); the runtime acts on the press (and on the held ones' release).
  std::uint32_t action = 0;
  if (k == ViewerKey::kFire) action = kActionFire;
  if (k == ViewerKey::kExchange) action = kActionExchange;
  if (k == ViewerKey::kEnergy) action = kActionEnergyOn;
  if (k == ViewerKey::kSuction) action = kActionSuctionOn;
  if (k == ViewerKey::kIrrigate) action = kActionIrrigateOn;
  if (action != 0) {
    const std::uint32_t bit = action << 1;  // button i+1 = action bit i
    command_.buttons = down ? command_.buttons | bit : command_.buttons & ~bit;
    changed_ = true;
  }
  if (down && !was && (k == ViewerKey::kToggleCamera || k == ViewerKey::kPause || k == ViewerKey::kStep ||
                       k == ViewerKey::kReset || k == ViewerKey::kRecord)) {
    if (k == ViewerKey::kToggleCamera) free_camera = !free_camera;
    return k;
  }
  return ViewerKey::kOther;
}

void ViewerInput::advance(double dt) {
  const double a = kKeyRate * dt;
  const auto held = [this](ViewerKey k) { return held_[int(k)] ? 1.0 : 0.0; };
  const double yaw = held(ViewerKey::kYawLeft) - held(ViewerKey::kYawRight);
  const double pitch = held(ViewerKey::kPitchUp) - held(ViewerKey::kPitchDown);
  const double roll = held(ViewerKey::kRollRight) - held(ViewerKey::kRollLeft);
  const double depth = held(ViewerKey::kInsert) - held(ViewerKey::kRetract);
  if (yaw == 0 && pitch == 0 && roll == 0 && depth == 0) return;
  command_.yaw += a * yaw;
  command_.pitch += a * pitch;
  command_.roll += a * roll;
  command_.depth += 0.05 * a * depth;
  changed_ = true;
}

ViewerKey viewer_key_from_name(const std::string& name) {
  static const std::pair<const char*, ViewerKey> names[] = {
      {"insert", ViewerKey::kInsert},       {"retract", ViewerKey::kRetract},     {"yaw-left", ViewerKey::kYawLeft},
      {"yaw-right", ViewerKey::kYawRight},  {"pitch-up", ViewerKey::kPitchUp},    {"pitch-down", ViewerKey::kPitchDown},
      {"roll-left", ViewerKey::kRollLeft},  {"roll-right", ViewerKey::kRollRight}, {"jaw", ViewerKey::kJaw},
      {"camera", ViewerKey::kToggleCamera}, {"pause", ViewerKey::kPause},         {"step", ViewerKey::kStep},
      {"reset", ViewerKey::kReset},         {"record", ViewerKey::kRecord},       {"fire", ViewerKey::kFire},
      {"energy", ViewerKey::kEnergy},       {"exchange", ViewerKey::kExchange},   {"suction", ViewerKey::kSuction},
      {"irrigate", ViewerKey::kIrrigate}};
  for (const auto& [n, k] : names)
    if (name == n) return k;
  return ViewerKey::kOther;
}

std::vector<InjectedEvent> read_injected_events(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw Error(file + ": cannot open the event script");
  std::vector<InjectedEvent> events;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream s(line);
    InjectedEvent e;
    std::string when;
    if (!(s >> when)) continue;  // blank
    const auto fail = [&](const std::string& why) { throw Error(file + ":" + std::to_string(n) + ": " + why); };
    std::istringstream w(when[0] == 'f' ? when.substr(1) : when);
    if (!(w >> e.time) || !(w >> std::ws).eof() || (when[0] == 'f' && (e.time < 0 || e.time != std::floor(e.time))))
      fail("expected a time in seconds or a frame fN first");
    if (when[0] == 'f') e.frame = static_cast<int>(e.time);
    if (!events.empty() && (events.back().frame >= 0) != (e.frame >= 0))
      fail("times must be all seconds or all frames (fN)");
    if (!(s >> e.kind)) fail("expected an event after the time");
    if (e.kind == "down" || e.kind == "up") {
      if (!(s >> e.button >> e.x >> e.y) || e.button < 0 || e.button > 2) fail(e.kind + " needs BUTTON(0-2) X Y");
    } else if (e.kind == "move") {
      if (!(s >> e.x >> e.y)) fail("move needs X Y");
    } else if (e.kind == "scroll") {
      if (!(s >> e.y)) fail("scroll needs NOTCHES");
    } else if (e.kind == "key" || e.kind == "keyup") {
      std::string name;
      if (!(s >> name) || (e.key = viewer_key_from_name(name)) == ViewerKey::kOther) fail("unknown key \"" + name + "\"");
    } else if (e.kind != "settle") {
      fail("unknown event \"" + e.kind + "\" (known: down, up, move, scroll, key, keyup, settle)");
    }
    if (!events.empty() && e.time < events.back().time) fail("times must not decrease");
    events.push_back(e);
  }
  return events;
}

}  // namespace trocar
