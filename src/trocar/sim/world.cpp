#include "trocar/sim/world.h"

#include <algorithm>

namespace trocar {

TissueBody::TissueBody(std::string body_name, const TriMesh& world_mesh, const MassSpringMaterial& material,
                       const FixedSelection& fixed, const Vec3& gravity, IntegratorKind kind)
    : name(std::move(body_name)),
      settings(MassSpringSettings::build(world_mesh, material, fixed, gravity)),
      state(MassSpringState::at_rest(settings)),
      integrator(settings, kind),
      energy(settings) {
  if (world_mesh.texcoords.size() == 3 * world_mesh.triangles.size()) texcoords = world_mesh.texcoords;
  // One ContactJacobian per applied contact; 8192 covers a tool buried in a fine mesh, so the
  // response does not grow the array inside a step.
  loads.reset(settings.vertex_count(), 8192);
}

TissueBody::TissueBody(std::string body_name, MassSpringSettings model, IntegratorKind kind, ImplicitOptions implicit,
                       XpbdOptions xpbd)
    : name(std::move(body_name)),
      settings(std::move(model)),
      state(MassSpringState::at_rest(settings)),
      integrator(settings, kind, implicit, xpbd),
      energy(settings) {
  loads.reset(settings.vertex_count(), 8192);
}

TissueBody& World::add_tissue(std::string name, const TriMesh& world_mesh, const MassSpringMaterial& material,
                              const FixedSelection& fixed, const Vec3& gravity, IntegratorKind kind) {
  tissues.push_back(std::make_unique<TissueBody>(std::move(name), world_mesh, material, fixed, gravity, kind));
  return *tissues.back();
}

InstrumentBody& World::add_instrument(std::string name, Instrument instrument, KeyframeMotion motion) {
  InstrumentBody body;
  body.name = std::move(name);
  body.thickness = 2 * instrument.local_obb().half_extents.minCoeff();
  body.instrument = std::move(instrument);
  body.motion = std::move(motion);
  instruments.push_back(std::move(body));
  return instruments.back();
}

RigidBody& World::add_rigid(std::string name, TriMesh world_mesh) {
  rigids.push_back(RigidBody{std::move(name), std::move(world_mesh)});
  return rigids.back();
}

const TissueBody* World::find_tissue(std::string_view name, std::size_t* index) const {
  for (std::size_t t = 0; t < tissues.size(); ++t)
    if (tissues[t]->name == name) {
      if (index) *index = t;
      return tissues[t].get();
    }
  return nullptr;
}

}  // namespace trocar
