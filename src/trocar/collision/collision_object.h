#pragma once
/// What the collision detector sees of one object: a role and a view of its world-space mesh.
#include <cstdint>
#include <span>

#include "trocar/core/types.h"

namespace trocar {

/// What an object is, which decides the contact kind and which pairs are tested
/// (rigid–rigid pairs are not).
enum class ObjectRole : std::uint8_t {
  kInstrument,  ///< a rigid tool moved by a device or a script
  kTissue,      ///< a deforming organ surface
  kRigid,       ///< static scene geometry (bones, table, trocar ports)
};

/// Lower-case name ("instrument", "tissue", "rigid").
const char* role_name(ObjectRole role);

/// A non-owning view of one object's surface in world space. The caller owns the arrays and
/// updates the positions every frame; the detector reads them during detect() and never copies
/// the meshes. Triangle indices must be < positions.size(). Between calls an object is
/// recognised as "the same" (so cached per-object structures such as BVH topologies are kept)
/// when its index, triangle span (pointer and size) and vertex count are unchanged.
struct CollisionObject {
  ObjectRole role = ObjectRole::kTissue;      ///< what the object is
  std::span<const Vec3> positions;            ///< world-space vertex positions (metres)
  std::span<const Triangle> triangles;        ///< vertex index triplets into positions
};

}  // namespace trocar
