#include "trocar/core/aabb.h"

namespace trocar {

Aabb Aabb::of_points(std::span<const Vec3> points) {
  Aabb box;
  for (const Vec3& p : points) box.expand(p);
  return box;
}

}  // namespace trocar
