#pragma once
/// Scene keys of tissue–tissue contact (docs/scene.md): the root's "tissue_contacts", a tissue's
/// "roll", and the "prosthetic-mesh" generator.
#include "trocar/mesh/tri_mesh.h"
#include "trocar/scene/json_reader.h"
#include "trocar/scene/scene.h"

namespace trocar {

/// "tissue_contacts": [{"a": NAME, "b": NAME, "thickness": m (> 0, default 1e-3), "friction": μ
/// (≥ 0, default 0.3)}] → scene.settings.tissue_contacts. Names are tissue names (a == b: self
/// contact). Call after the tissues are read; an unknown name fails naming the key.
void read_tissue_contacts(const JsonReader& list, Scene& scene);

/// "tissue_coupling": "substeps" (default: the contacts and tacks between XPBD tissues solved
/// inside their substeps, the tissues in lock-step) or "after" (after the integrators) →
/// scene.settings.couple_tissues. Anything else fails naming the key.
void read_tissue_coupling(const JsonReader& key, Scene& scene);

/// A tissue's "roll": {"axis": "x" | "y", "radius": m, "gap": m} rolls the tissue's current
/// positions (mesh/prosthetic_mesh.h, roll_sheet) after its model is built, so the flat sheet
/// stays the rest shape and its bending springs unroll it.
void read_tissue_roll(const JsonReader& roll, TissueBody& tissue);

/// "prosthetic-mesh": width, height (m, required), spacing (m, default 0.005).
TriMesh generate_prosthetic_mesh(const JsonReader& spec);

/// A tissue's "lay_on": {"tissues": [names], "gap": m}: each of its mesh's vertices (before the
/// model is built, so the laid shape is also its rest shape) moves along z to `gap` above the
/// highest point of the named tissues' surfaces under it (vertices over none stay): a cloth laid on the anatomy, e.g. the prosthetic mesh on
/// the wall. The named tissues must come earlier in the scene. Throws naming the key.
void read_tissue_lay_on(const JsonReader& spec, const World& world, std::vector<Vec3>& positions);

}  // namespace trocar
