#include "trocar/scene/electrosurgery_keys.h"

namespace trocar {

ElectrodeSpec read_electrode(const JsonReader& r) {
  ElectrodeSpec e;
  e.power = 40;
  if (!r.is_object()) {
    if (!r.boolean()) e.power = 0;
    return e;
  }
  r.expect_keys({"power", "active_length", "reach"});
  if (r.has("power")) e.power = r.at("power").number_at_least(0);
  if (r.has("active_length")) e.active_length = r.at("active_length").number_above(0);
  if (r.has("reach")) e.reach = r.at("reach").number_at_least(0);
  return e;
}

SuctionSpec read_suction(const JsonReader& r) {
  if (!r.is_object()) return r.boolean() ? SuctionSpec{} : SuctionSpec::none();
  r.expect_keys({"suction_flow", "suction_radius", "smoke_radius", "irrigation_flow", "irrigation_reach", "jet_radius"});
  SuctionSpec s;
  if (r.has("suction_flow")) s.suction_flow = r.at("suction_flow").number_at_least(0);
  if (r.has("suction_radius")) s.suction_radius = r.at("suction_radius").number_above(0);
  if (r.has("smoke_radius")) s.smoke_radius = r.at("smoke_radius").number_above(0);
  if (r.has("irrigation_flow")) s.irrigation_flow = r.at("irrigation_flow").number_at_least(0);
  if (r.has("irrigation_reach")) s.irrigation_reach = r.at("irrigation_reach").number_above(0);
  if (r.has("jet_radius")) s.jet_radius = r.at("jet_radius").number_above(0);
  return s;
}

ThermalProperties read_thermal(const JsonReader& r) {
  r.expect_keys({"density", "specific_heat", "conductivity", "heated_depth", "water_fraction", "perfusion",
                 "body_temperature", "arrhenius_rate", "activation_energy"});
  ThermalProperties p;
  if (r.has("density")) p.density = r.at("density").number_above(0);
  if (r.has("specific_heat")) p.specific_heat = r.at("specific_heat").number_above(0);
  if (r.has("conductivity")) p.conductivity = r.at("conductivity").number_at_least(0);
  if (r.has("heated_depth")) p.heated_depth = r.at("heated_depth").number_above(0);
  if (r.has("water_fraction")) {
    const JsonReader w = r.at("water_fraction");
    p.water_fraction = w.number_above(0);
    if (p.water_fraction > 1) w.fail("must be at most 1");
  }
  if (r.has("perfusion")) p.perfusion = r.at("perfusion").number_at_least(0);
  if (r.has("body_temperature")) {
    const JsonReader t = r.at("body_temperature");
    p.body_temperature = t.number_above(0);
    if (p.body_temperature >= p.boiling_temperature) t.fail("must be below the boiling point, 373.15 K");
  }
  if (r.has("arrhenius_rate")) p.arrhenius_rate = r.at("arrhenius_rate").number_above(0);
  if (r.has("activation_energy")) p.activation_energy = r.at("activation_energy").number_above(0);
  return p;
}

VesselSpec read_vessel(const JsonReader& r) {
  r.expect_keys({"diameter", "artery"});
  VesselSpec v;
  v.diameter = r.at("diameter").number_above(0);
  v.artery = r.boolean_or("artery", false);
  return v;
}

}  // namespace trocar
