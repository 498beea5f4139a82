#include "trocar/scene/anatomy_scene.h"

#include "trocar/core/error.h"
#include "trocar/mesh/inguinal_anatomy.h"
#include "trocar/mesh/renumber.h"
#include "trocar/tissue/material.h"

namespace trocar {
namespace {

/// Sets one material field by its scene key (the keys of a tissue's "material").
void set_material_field(MassSpringMaterial& m, const std::string& key, Real value) {
  if (key == "mass") m.mass = value;
  else if (key == "density") m.density = value;
  else if (key == "sheet_thickness") m.sheet_thickness = value;
  else if (key == "k_structural") m.k_structural = value;
  else if (key == "k_bending") m.k_bending = value;
  else if (key == "damping") m.damping = value;
  else if (key == "spring_damping") m.spring_damping = value;
  else if (key == "k_area") m.k_area = value;
  else if (key == "k_volume") m.k_volume = value;
  else if (key == "k_home") m.k_home = value;
  else if (key == "home_yield") m.home_yield = value;
  else throw Error("unknown material field '" + key + "'");
}

/// N: a grasper pulling a vessel harder tears it. An assumption: within the 1.25–11.43 N of the
/// largest acceptable tractive forces on porcine tissues (Rodrigues et al., Surg Endosc 2012),
/// near their low end; no vessel was measured.
constexpr Real kVesselTearForce = 3.0;

void add_structure(const AnatomyStructure& s, Scene& scene) {
  Appearance look;
  look.given = true;
  look.colour = s.colour;
  look.opacity = s.opacity;
  look.pattern = SurfacePattern::kDefault;  // the tissue texture in the structure's colour
  if (s.role == StructureRole::kRigid) {
    scene.world.add_rigid(s.name, s.mesh);
    scene.rigid_appearance.push_back(look);
    return;
  }
  MassSpringMaterial material = material_preset(s.material_preset);
  for (const auto& [key, value] : s.material) set_material_field(material, key, value);
  // Renumbered for memory locality as read_tissue does; the fixed indices follow.
  const std::vector<std::uint32_t> order = locality_vertex_order(s.mesh);
  const TriMesh mesh = renumber_vertices(s.mesh, order);
  const std::vector<std::uint32_t> new_index = inverse_order(order);
  FixedSelection fixed;
  for (std::uint32_t v : s.fixed) fixed.indices.push_back(new_index[v]);
  TissueBody& tissue = scene.world.add_tissue(s.name, mesh, material, fixed, scene.gravity, IntegratorKind::kXpbd);
  tissue.graspable = s.graspable;
  if (s.vessel_diameter > 0) {
    tissue.bleeds = VesselSpec{s.vessel_diameter, s.artery};
    tissue.tear_force = kVesselTearForce;
  }
  scene.textures.emplace_back();
  scene.tissue_appearance.push_back(look);
}

}  // namespace

void read_anatomy(const JsonReader& spec, Scene& scene) {
  spec.expect_keys({"generate", "hernia", "cell", "tube_segments", "tube_spacing", "sac_segments", "sac_rings",
                    "defect_diameter", "sac_length", "sac_k_home", "sac_home_yield", "sac_neck_fixed"});
  const JsonReader gen = spec.at("generate");
  if (gen.string() != "tapp-inguinal") gen.fail("unknown anatomy \"" + gen.string() + "\" (known: tapp-inguinal)");
  const JsonReader h = spec.at("hernia");
  const std::string hernia = h.string();
  HerniaKind kind;
  if (hernia == "indirect") kind = HerniaKind::kIndirect;
  else if (hernia == "direct") kind = HerniaKind::kDirect;
  else h.fail("unknown hernia \"" + hernia + "\" (known: indirect, direct)");
  TappOptions o;
  const auto length = [&](const char* key, Real& value, Real lo, Real hi) {
    if (!spec.has(key)) return;
    const JsonReader r = spec.at(key);
    value = r.number();
    if (!(value >= lo && value <= hi)) r.fail("must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  };
  const auto count = [&](const char* key, std::size_t& value, std::int64_t lo, std::int64_t hi) {
    if (spec.has(key)) value = static_cast<std::size_t>(spec.at(key).integer(lo, hi));
  };
  length("cell", o.cell, 0.002, 0.01);
  count("tube_segments", o.tube_segments, 3, 64);
  length("tube_spacing", o.tube_spacing, 0.002, 0.02);
  count("sac_segments", o.sac_segments, 8, 128);
  if (o.sac_segments % 4 != 0) spec.at("sac_segments").fail("must be a multiple of 4");
  count("sac_rings", o.sac_rings, 2, 64);
  length("defect_diameter", o.defect_diameter, 0.01, 0.024);
  length("sac_length", o.sac_length, 0.005, 0.08);
  length("sac_k_home", o.sac_k_home, 0, 1e4);
  length("sac_home_yield", o.sac_home_yield, 0, 0.1);
  o.sac_neck_fixed = spec.boolean_or("sac_neck_fixed", o.sac_neck_fixed);
  InguinalAnatomy anatomy;
  try {
    anatomy = make_tapp_anatomy(kind, o);
  } catch (const Error& e) {
    spec.fail(e.what());
  }
  for (const AnatomyStructure& s : anatomy.structures) {
    for (const auto& t : scene.world.tissues)
      if (t->name == s.name) spec.fail("a tissue is already called \"" + s.name + "\"");
    add_structure(s, scene);
  }
  scene.zones.insert(scene.zones.end(), anatomy.zones.begin(), anatomy.zones.end());
  for (const auto& [name, point] : anatomy.landmarks) scene.landmarks[name] = point;
}

Appearance read_appearance(const JsonReader& spec) {
  spec.expect_keys({"colour", "opacity", "pattern"});
  Appearance a;
  a.given = true;
  if (spec.has("colour")) {
    const JsonReader c = spec.at("colour");
    const Vec3 rgb = c.vec3();
    if ((rgb.array() < 0).any() || (rgb.array() > 1).any()) c.fail("each component must be in [0, 1]");
    a.colour = {static_cast<float>(rgb.x()), static_cast<float>(rgb.y()), static_cast<float>(rgb.z())};
  }
  if (spec.has("opacity")) {
    const JsonReader o = spec.at("opacity");
    const Real v = o.number();
    if (!(v >= 0 && v <= 1)) o.fail("must be in [0, 1]");
    a.opacity = static_cast<float>(v);
  }
  if (spec.has("pattern")) {
    const JsonReader p = spec.at("pattern");
    const std::string name = p.string();
    if (name == "default") a.pattern = SurfacePattern::kDefault;
    else if (name == "plain") a.pattern = SurfacePattern::kPlain;
    else if (name == "weave") a.pattern = SurfacePattern::kWeave;
    else p.fail("unknown pattern \"" + name + "\" (known: default, plain, weave)");
  }
  return a;
}

}  // namespace trocar
