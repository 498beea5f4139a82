#pragma once
// A prosthetic mesh (8 × 6 cm, 5 mm grid) dropped 4 mm onto a peritoneum sheet with its border
// fixed, with mesh–wall and mesh self contact ("tissue_contacts") and, with `roll`, rolled first;
// both tissues stepped by `integrator` (a scene integrator name).
#include <string>

namespace trocar::test {

inline std::string mesh_on_wall_scene(bool roll = false, const std::string& integrator = "implicit-euler") {
  const std::string stepped = R"("integrator": ")" + integrator + "\"";
  return std::string(R"({
  "schema": 1, "name": "mesh-on-wall", "timestep": 0.001, "duration": 0.3, "gravity": [0, 0, -9.81],
  "tissues": [
    { "name": "wall", "mesh": {"generate": "sheet", "width": 0.12, "height": 0.1, "nx": 24, "ny": 20},
      "material": {"preset": "peritoneum", "k_home": 20}, "fixed": {"indices": [0, 24, 500, 524]}, )") +
         stepped + R"( },
    { "name": "mesh", "mesh": {"generate": "prosthetic-mesh", "width": 0.08, "height": 0.06, "spacing": 0.005},
      "translate": [0, 0, 0.004], "material": {"preset": "polypropylene-mesh"}, )" + stepped +
         (roll ? R"(, "roll": {"axis": "y", "radius": 0.004, "gap": 0.003})" : "") + R"( }],
  "tissue_contacts": [{"a": "mesh", "b": "wall", "thickness": 0.001, "friction": 0.3},
                      {"a": "mesh", "b": "mesh", "thickness": 0.001}]
})";
}

}  // namespace trocar::test
