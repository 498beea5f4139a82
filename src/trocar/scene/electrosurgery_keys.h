#pragma once
/// Scene keys of electrosurgery (docs/scene.md, "Electrosurgery"): an instrument's "electrode" and
/// "suction", a tissue's "thermal" properties and "coagulation_stiffening".
#include "trocar/scene/json_reader.h"
#include "trocar/sim/world.h"

namespace trocar {

/// "electrode": true (the defaults, 40 W) or {"power": W, "active_length": m, "reach": m}.
ElectrodeSpec read_electrode(const JsonReader& r);

/// "suction": true (SuctionSpec's defaults: a 5 mm suction-irrigator), false (none), or
/// {"suction_flow": m³/s, "suction_radius": m, "smoke_radius": m, "irrigation_flow": m³/s,
/// "irrigation_reach": m, "jet_radius": m}, each optional over the defaults. A flow may be 0 (that
/// valve does nothing); a radius or reach must be > 0.
SuctionSpec read_suction(const JsonReader& r);

/// "thermal": {"density", "specific_heat", "conductivity", "heated_depth", "water_fraction",
/// "perfusion", "body_temperature" (K), "arrhenius_rate", "activation_energy"}, each optional
/// over the soft-tissue defaults (electrosurgery/thermal.h).
ThermalProperties read_thermal(const JsonReader& r);

/// "bleeds": {"diameter": m, "artery": bool} — the tissue is a vessel of that lumen.
VesselSpec read_vessel(const JsonReader& r);

}  // namespace trocar
