#include "trocar/render/viewer_panel.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

#include "trocar/tissue/material.h"

namespace trocar {
namespace {

constexpr const char* kMethods[] = {"obb", "sdf", "primitive", "normal", "project"};
constexpr const char* kBroadPhases[] = {"ohc", "bvh", "brute"};
constexpr const char* kIntegrators[] = {"explicit-euler", "semi-implicit-euler", "implicit-euler", "xpbd"};

template <std::size_t N>
int index_of(const char* const (&names)[N], const std::string& name, int fallback) {
  for (std::size_t i = 0; i < N; ++i)
    if (name == names[i]) return int(i);
  return fallback;
}

float number_or(const nlohmann::json& obj, const char* key, double fallback) {
  return obj.is_object() && obj.contains(key) && obj[key].is_number() ? obj[key].get<float>() : float(fallback);
}

void plot(const char* label, const Series& s, const char* unit) {
  float hi = 0;
  for (float v : s.values) hi = std::max(hi, v);
  char overlay[64];
  std::snprintf(overlay, sizeof overlay, "%.1f %s (max %.1f)", s.last(), unit, hi);
  ImGui::PlotLines(label, s.values.data(), Series::kLength, s.next, overlay, 0.0f, hi * 1.15f + 1e-3f, ImVec2(0, 42));
}

}  // namespace

SceneEdits edits_from(const nlohmann::json& doc, int drive) {
  SceneEdits e;
  if (doc.contains("tissues"))
    for (const nlohmann::json& t : doc["tissues"]) {
      const nlohmann::json m = t.value("material", nlohmann::json::object());
      MassSpringMaterial base;
      if (m.contains("preset") && m["preset"].is_string()) base = material_preset(m["preset"].get<std::string>());
      MaterialEdit me;
      me.name = t.value("name", "tissue" + std::to_string(e.tissues.size()));
      me.k_structural = number_or(m, "k_structural", base.k_structural);
      me.k_bending = number_or(m, "k_bending", base.k_bending);
      me.damping = number_or(m, "damping", base.damping);
      me.k_area = number_or(m, "k_area", base.k_area);
      me.k_volume = number_or(m, "k_volume", base.k_volume);
      me.integrator = index_of(kIntegrators, t.value("integrator", std::string("xpbd")), 3);
      e.tissues.push_back(me);
    }
  const nlohmann::json response = doc.value("response", nlohmann::json::object());
  e.method = index_of(kMethods, response.value("method", std::string("obb")), 0);
  e.stiffness = number_or(response, "stiffness", 500);
  const nlohmann::json collision = doc.value("collision", nlohmann::json::object());
  e.broad_phase = index_of(kBroadPhases, collision.value("broad_phase", std::string("ohc")), 0);
  e.timestep = number_or(doc, "timestep", 1e-3);
  if (drive >= 0 && doc.contains("instruments") && std::size_t(drive) < doc["instruments"].size()) {
    const nlohmann::json& inst = doc["instruments"][std::size_t(drive)];
    if (inst.contains("device")) e.force_scale = number_or(inst["device"], "force_scale", 1);
  }
  return e;
}

void apply_edits(nlohmann::json& doc, const SceneEdits& e, int drive) {
  for (std::size_t i = 0; i < e.tissues.size() && doc.contains("tissues") && i < doc["tissues"].size(); ++i) {
    nlohmann::json& t = doc["tissues"][i];
    nlohmann::json& m = t["material"];
    const MaterialEdit& me = e.tissues[i];
    m["k_structural"] = me.k_structural;
    m["k_bending"] = me.k_bending;
    m["damping"] = me.damping;
    m["k_area"] = me.k_area;
    m["k_volume"] = me.k_volume;
    t["integrator"] = kIntegrators[me.integrator];
    if (t["integrator"] != "xpbd") t.erase("substeps");  // an xpbd-only key
  }
  doc["response"]["method"] = kMethods[e.method];
  doc["response"]["stiffness"] = e.stiffness;
  doc["collision"]["broad_phase"] = kBroadPhases[e.broad_phase];
  doc["timestep"] = e.timestep;
  // The collision period follows the time step unless the scene set its own.
  if (doc["collision"].contains("period")) doc["collision"]["period"] = e.timestep;
  if (drive >= 0 && doc.contains("instruments") && std::size_t(drive) < doc["instruments"].size()) {
    nlohmann::json& inst = doc["instruments"][std::size_t(drive)];
    if (inst.contains("device")) inst["device"]["force_scale"] = e.force_scale;
  }
}

std::string surgery_status(const ViewSnapshot& snap, const std::vector<std::string>& names) {
  std::string out;
  const auto line = [&](const std::string& text) { out += (out.empty() ? "" : "\n") + text; };
  for (std::size_t i = 0; i < snap.instruments.size(); ++i) {
    const InstrumentView& v = snap.instruments[i];
    if (!v.energy && !v.suction && !v.irrigation) continue;
    std::string what = i < names.size() ? names[i] : "instrument " + std::to_string(i);
    what += ":";
    if (v.energy) what += i < snap.vapour.size() && snap.vapour[i].burning ? " energy on, burning" : " energy on";
    if (v.suction) what += v.energy ? ", suction" : " suction";
    if (v.irrigation) what += v.energy || v.suction ? ", irrigation" : " irrigation";
    line(what);
  }
  if (!snap.wounds.empty()) {
    Real lost = 0;
    std::size_t open = 0;
    for (const ViewSnapshot::WoundView& w : snap.wounds) {
      lost += w.emitted;
      open += w.open ? 1 : 0;
    }
    char text[96];
    std::snprintf(text, sizeof text, "blood lost %.1f ml; %zu of %zu wound%s bleeding", lost * 1e6, open,
                  snap.wounds.size(), snap.wounds.size() == 1 ? "" : "s");
    line(text);
  }
  return out;
}

PanelActions draw_panel(SceneEdits& e, RenderOptions& render, const PanelLive& live) {
  PanelActions a;
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.82f);
  ImGui::Begin("trocar");
  ImGui::Text("t = %.2f s   %.0f fps   %s", live.sim_time, live.fps, live.paused ? "PAUSED" : "");
  ImGui::Text("haptic %.0f Hz, misses %.3f %%", live.haptic_rate_hz, 100 * live.deadline_miss_fraction);
  ImGui::Text("physics %.0f Hz   device: %s", live.physics_rate_hz, live.device.c_str());
  if (ImGui::Button(live.paused ? "Run" : "Pause")) a.pause = true;
  ImGui::SameLine();
  if (ImGui::Button("Step")) a.step = true;
  ImGui::SameLine();
  if (ImGui::Button("Reset")) a.reset = true;
  ImGui::SameLine();
  if (ImGui::Button(live.recording ? "Stop rec." : "Record")) a.record = true;
  ImGui::SameLine();
  if (ImGui::Button("Shot")) a.screenshot = true;
  if (live.recording) ImGui::TextWrapped("recording %s", live.recording_path.c_str());
  if (!live.status.empty()) ImGui::TextWrapped("%s", live.status.c_str());
  if (!live.surgery.empty()) ImGui::TextColored(ImVec4(1.0f, 0.75f, 0.35f, 1.0f), "%s", live.surgery.c_str());

  if (ImGui::CollapsingHeader("Timing", ImGuiTreeNodeFlags_DefaultOpen)) {
    plot("step", live.step_us, "us");
    plot("broad", live.broad_us, "us");
    plot("narrow", live.narrow_us, "us");
    plot("response", live.response_us, "us");
    plot("deform", live.deformation_us, "us");
    plot("haptic", live.haptic_khz, "kHz");
    plot("frame", live.frame_ms, "ms");
  }
  if (ImGui::CollapsingHeader("Simulation (Apply restarts)")) {
    for (std::size_t i = 0; i < e.tissues.size(); ++i) {
      MaterialEdit& m = e.tissues[i];
      ImGui::PushID(int(i));
      ImGui::TextUnformatted(m.name.c_str());
      ImGui::SliderFloat("k structural N/m", &m.k_structural, 1, 20000, "%.0f", ImGuiSliderFlags_Logarithmic);
      ImGui::SliderFloat("k bending N/m", &m.k_bending, 0, 5000, "%.1f", ImGuiSliderFlags_Logarithmic);
      ImGui::SliderFloat("damping 1/s", &m.damping, 0, 100, "%.2f", ImGuiSliderFlags_Logarithmic);
      ImGui::SliderFloat("k area N/m", &m.k_area, 0, 5000, "%.1f", ImGuiSliderFlags_Logarithmic);
      ImGui::SliderFloat("k volume Pa", &m.k_volume, 0, 1e6f, "%.0f", ImGuiSliderFlags_Logarithmic);
      ImGui::Combo("integrator", &m.integrator, kIntegrators, IM_ARRAYSIZE(kIntegrators));
      ImGui::PopID();
    }
    ImGui::Combo("response", &e.method, kMethods, IM_ARRAYSIZE(kMethods));
    ImGui::SliderFloat("K N/m", &e.stiffness, 10, 20000, "%.0f", ImGuiSliderFlags_Logarithmic);
    ImGui::Combo("broad phase", &e.broad_phase, kBroadPhases, IM_ARRAYSIZE(kBroadPhases));
    ImGui::SliderFloat("time step s", &e.timestep, 2e-4f, 5e-3f, "%.4f", ImGuiSliderFlags_Logarithmic);
    ImGui::SliderFloat("force scale", &e.force_scale, 0, 4, "%.2f");
    if (ImGui::Button("Apply")) a.apply = true;
  }
  if (ImGui::CollapsingHeader("View")) {
    ImGui::Checkbox("contacts", &render.contacts);
    ImGui::SameLine();
    ImGui::Checkbox("forces", &render.forces);
    ImGui::SameLine();
    ImGui::Checkbox("OBB", &render.obb);
    ImGui::Checkbox("hash cells", &render.cells);
    ImGui::SameLine();
    ImGui::Checkbox("gauge", &render.gauge);
    ImGui::SameLine();
    ImGui::Checkbox("wire", &render.wireframe);
    float arrow = float(render.force_scale * 100), gauge = float(render.gauge_max);
    if (ImGui::SliderFloat("arrow cm/N", &arrow, 0.1f, 10)) render.force_scale = arrow / 100;
    if (ImGui::SliderFloat("gauge N", &gauge, 0.5f, 20)) render.gauge_max = gauge;
    if (ImGui::Button(live.free_camera ? "Laparoscope camera" : "Free camera")) a.camera = true;
  }
  if (ImGui::CollapsingHeader("Controls")) {
    ImGui::TextWrapped(
        "Left drag: pivot the instrument about its port (yaw, pitch). Right drag: roll (x), insert (y). "
        "Wheel or W/S: insert/retract. A/D yaw, arrows pitch, Q/E roll. Space (held): close the jaws. "
        "C: free camera (left drag orbits, wheel zooms). T fire the tacker, X exchange the instrument. Held: B "
        "the electrode's pedal, V suction, I irrigation. P pause, N step, R reset, F9 record/stop.");
  }
  ImGui::End();
  return a;
}

}  // namespace trocar
