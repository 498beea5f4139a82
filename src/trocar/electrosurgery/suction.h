#pragma once
/// A suction-irrigation cannula (docs/electrosurgery.md, "Suction and irrigation"): its two
/// trumpet valves draw fluid and smoke in at the tip, or jet saline out of it.
#include "trocar/core/types.h"

namespace trocar {

/// An instrument's suction and irrigation (scene key "suction"; both flows 0: not a
/// suction-irrigator). The defaults are a 5 mm suction-irrigation cannula; figures marked
/// "assumed" have no measurement behind them.
struct SuctionSpec {
  /// No suction and no irrigation (both flows 0): an instrument that is not a suction-irrigator.
  static SuctionSpec none() {
    SuctionSpec s;
    s.suction_flow = s.irrigation_flow = 0;
    return s;
  }

  /// m³/s of liquid the open suction valve draws. Wall suction through a 5 mm cannula: medical
  /// suction's high-flow class draws ≥ 20 L/min of free air (ISO 10079-1); liquid, 50 times more
  /// viscous and limited by the tubing, comes far slower. Assumed: 1 L/min.
  Real suction_flow = 1.0 / 60 * 1e-3;
  /// m: fluid on a surface within this distance of the tip is drawn in (the cannula's side holes
  /// and the film's meniscus around it; assumed).
  Real suction_radius = 0.005;
  /// m: smoke within this distance of the tip is drawn in (SmokeField::suction: a 2 cm sphere at
  /// the high-flow class empties in about 0.1 s).
  Real smoke_radius = 0.02;
  /// m³/s of saline the open irrigation valve jets out (a pressure bag at 300 mmHg through the
  /// cannula; assumed: 0.6 L/min).
  Real irrigation_flow = 0.6 / 60 * 1e-3;
  /// m: the jet lands on the first surface ahead of the tip along the shaft within this distance.
  Real irrigation_reach = 0.05;
  /// m: the jet's radius where it lands (the 5 mm cannula's bore, spreading a little).
  Real jet_radius = 0.003;

  bool suction() const { return suction_flow > 0; }
  bool irrigation() const { return irrigation_flow > 0; }
  bool any() const { return suction() || irrigation(); }
};

}  // namespace trocar
