#include "trocar/scene/contact_keys.h"

#include <cmath>
#include <limits>

#include "trocar/core/error.h"
#include "trocar/mesh/prosthetic_mesh.h"

namespace trocar {
namespace {

std::size_t tissue_named(const JsonReader& key, const Scene& scene) {
  const std::string name = key.string();
  std::size_t index = 0;
  if (scene.world.find_tissue(name, &index)) return index;
  std::string known;
  for (const auto& t : scene.world.tissues) known += (known.empty() ? "" : ", ") + t->name;
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

void read_tissue_coupling(const JsonReader& key, Scene& scene) {
  const std::string how = key.string();
  if (how != "substeps" && how != "after") key.fail("must be \"substeps\" or \"after\"");
  scene.settings.couple_tissues = how == "substeps";
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

void read_tissue_lay_on(const JsonReader& spec, const World& world, std::vector<Vec3>& positions) {
  spec.expect_keys({"tissues", "gap"});
  const Real gap = spec.has("gap") ? spec.at("gap").number_at_least(0) : 0.0015;
  const JsonReader names = spec.at("tissues");
  std::vector<const TissueBody*> under;
  for (std::size_t k = 0; k < names.array_size(); ++k) {
    const JsonReader n = names.at(k);
    const TissueBody* found = world.find_tissue(n.string());
    if (found == nullptr) n.fail("no earlier tissue named \"" + n.string() + "\"");
    under.push_back(found);
  }
  for (Vec3& p : positions) {
    Real top = -std::numeric_limits<Real>::infinity();
    for (const TissueBody* t : under) {
      const std::vector<Vec3>& x = t->state.positions;
      for (const Triangle& tri : t->settings.triangles) {
        // The triangle's height over (p.x, p.y), from its barycentric coordinates in the xy plane.
        const Vec3 &a = x[tri[0]], &b = x[tri[1]], &c = x[tri[2]];
        const Real det = (b.y() - c.y()) * (a.x() - c.x()) + (c.x() - b.x()) * (a.y() - c.y());
        if (std::abs(det) < 1e-18) continue;
        const Real l0 = ((b.y() - c.y()) * (p.x() - c.x()) + (c.x() - b.x()) * (p.y() - c.y())) / det;
        const Real l1 = ((c.y() - a.y()) * (p.x() - c.x()) + (a.x() - c.x()) * (p.y() - c.y())) / det;
        const Real l2 = 1 - l0 - l1;
        if (l0 < 0 || l1 < 0 || l2 < 0) continue;
        top = std::max(top, l0 * a.z() + l1 * b.z() + l2 * c.z());
      }
    }
    if (std::isfinite(top)) p.z() = top + gap;
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
