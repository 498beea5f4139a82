#pragma once
/// The detector's output: one record per intersecting triangle pair.
#include <cstdint>
#include <tuple>

#include "trocar/collision/collision_object.h"
#include "trocar/core/types.h"

namespace trocar {

/// Which roles touch. Rigid–rigid pairs are never tested and have no kind.
enum class ContactKind : std::uint8_t {
  kInstrumentTissue,      ///< object_a is the instrument, object_b the tissue
  kInstrumentInstrument,  ///< two instruments (object_a has the lower index)
  kInstrumentRigid,       ///< object_a is the instrument, object_b the rigid object
  kTissueRigid,           ///< object_a is the tissue, object_b the rigid object
  kTissueTissue,          ///< two organs (object_a has the lower index)
};

/// Lower-case name ("instrument-tissue", ...).
const char* contact_kind_name(ContactKind kind);

/// Rank used to put roles in contact order: instrument 0, tissue 1, rigid 2.
constexpr int role_rank(ObjectRole role) { return static_cast<int>(role); }

/// True when a pair of objects with these roles is tested (everything but rigid–rigid).
constexpr bool roles_tested(ObjectRole a, ObjectRole b) {
  return !(a == ObjectRole::kRigid && b == ObjectRole::kRigid);
}

/// True when object i comes first in a contact between objects i and j (i ≠ j): the lower role
/// rank first (instrument, then tissue, then rigid); for equal roles the lower index.
constexpr bool object_first(ObjectRole role_i, std::uint32_t i, ObjectRole role_j, std::uint32_t j) {
  return role_rank(role_i) != role_rank(role_j) ? role_rank(role_i) < role_rank(role_j) : i < j;
}

/// The kind of a contact between roles a and b, given in contact order (object_first(a, ·, b, ·)).
/// Must not be called for rigid–rigid.
ContactKind contact_kind(ObjectRole a, ObjectRole b);

/// One intersecting pair of triangles. Objects are indices into the span given to detect();
/// triangles are indices into each object's triangle span. Contacts are sorted by
/// (object_a, object_b, triangle_a, triangle_b), each triangle pair appears once.
struct Contact {
  std::uint32_t object_a = 0;    ///< the first object in contact order (see object_first)
  std::uint32_t object_b = 0;    ///< the second object
  std::uint32_t triangle_a = 0;  ///< triangle of object_a
  std::uint32_t triangle_b = 0;  ///< triangle of object_b
  ContactKind kind = ContactKind::kInstrumentTissue;  ///< the roles of object_a and object_b
  /// The two triangles lie in a common plane (within the tri–tri tolerance); the segment is then
  /// a representative chord of their overlap polygon (see intersect_triangles).
  bool coplanar = false;
  Vec3 segment_p = Vec3::Zero();  ///< one end of the intersection segment (world units, metres)
  Vec3 segment_q = Vec3::Zero();  ///< the other end (equal to segment_p for a touching point)
};

/// The sort key of a contact.
inline auto contact_key(const Contact& c) {
  return std::tuple(c.object_a, c.object_b, c.triangle_a, c.triangle_b);
}

/// Strict order of contacts by (object_a, object_b, triangle_a, triangle_b).
inline bool contact_less(const Contact& x, const Contact& y) { return contact_key(x) < contact_key(y); }

}  // namespace trocar
