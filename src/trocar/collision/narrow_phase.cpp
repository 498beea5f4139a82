#include "trocar/collision/narrow_phase.h"

#include <algorithm>

#include "trocar/geometry/triangle_triangle.h"

namespace trocar {

void narrow_phase(std::span<const CollisionObject> objects, std::span<const CandidatePair> pairs,
                  std::vector<Contact>& out) {
  out.clear();
  for (const CandidatePair& pair : pairs) {
    const CollisionObject& oa = objects[pair.object_a];
    const CollisionObject& ob = objects[pair.object_b];
    const Triangle& ta = oa.triangles[pair.triangle_a];
    const Triangle& tb = ob.triangles[pair.triangle_b];
    const TriTriResult r = intersect_triangles(oa.positions[ta[0]], oa.positions[ta[1]], oa.positions[ta[2]],
                                               ob.positions[tb[0]], ob.positions[tb[1]], ob.positions[tb[2]]);
    if (!r.intersects) continue;
    Contact c;
    c.object_a = pair.object_a;
    c.object_b = pair.object_b;
    c.triangle_a = pair.triangle_a;
    c.triangle_b = pair.triangle_b;
    c.kind = contact_kind(oa.role, ob.role);
    c.coplanar = r.coplanar;
    c.segment_p = r.p;
    c.segment_q = r.q;
    out.push_back(c);
  }
  // std::sort does not allocate (introsort in place).
  std::sort(out.begin(), out.end(), contact_less);
}

}  // namespace trocar
