#include "trocar/scene/contact_keys.h"

#include "trocar/core/error.h"
#include "trocar/mesh/prosthetic_mesh.h"

namespace trocar {
namespace {

std::size_t tissue_named(const JsonReader& key, const Scene& scene) {
  const std::string name = key.string();
  std::string known;
  for (std::size_t t = 0; t < scene.world.tissues.size(); ++t) {
    if (scene.world.tissues[t]->name == name) return t;
    known += (known.empty() ? "" : ", ") + scene.world.tissues[t]->name;
  }
  key.fail("no tissue named \"" + name + "\" (tissues: " + (known.empty() ? "none" : known) + ")");
}

}  // namespace

void read_tissue_contacts(const JsonReader& list, Scene& scene) {
  for (std::size_t i = 0; i < list.array_size(); ++i) {
    const JsonReader c = list.at(i);
    c.expect_keys({"a", "b", "thickness", "friction", "adhesion", "adhesion_range"});
    TissueContactPair pair;
    pair.a = tissue_named(c.at("a"), scene);
    pair.b = tissue_named(c.at("b"), scene);
    if (c.has("thickness")) pair.thickness = c.at("thickness").number_above(0);
    if (c.has("friction")) pair.friction = c.at("friction").number_at_least(0);
    if (c.has("adhesion")) pair.adhesion = c.at("adhesion").number_at_least(0);
    if (c.has("adhesion_range")) pair.adhesion_range = c.at("adhesion_range").number_above(0);
    scene.settings.tissue_contacts.push_back(pair);
  }
}

void read_tissue_roll(const JsonReader& r, TissueBody& tissue) {
  r.expect_keys({"axis", "radius", "gap"});
  SheetRoll roll;
  const std::string axis = r.at("axis").string();
  if (axis != "x" && axis != "y") r.at("axis").fail("must be \"x\" or \"y\"");
  roll.axis = axis == "x" ? 0 : 1;
  roll.radius = r.at("radius").number_above(0);
  roll.gap = r.at("gap").number_above(0);
  try {
    roll_sheet(tissue.state.positions, roll);
  } catch (const Error& e) {
    r.fail(e.what());
  }
}

TriMesh generate_prosthetic_mesh(const JsonReader& spec) {
  spec.expect_keys({"generate", "width", "height", "spacing"});
  const Real w = spec.at("width").number_above(0), h = spec.at("height").number_above(0);
  const Real s = spec.has("spacing") ? spec.at("spacing").number_above(0) : 0.005;
  try {
    return make_prosthetic_mesh(w, h, s);
  } catch (const Error& e) {
    spec.fail(e.what());
  }
}

}  // namespace trocar
