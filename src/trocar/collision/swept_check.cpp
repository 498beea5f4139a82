#include "trocar/collision/swept_check.h"

namespace trocar {

// Stub.
SweptCheckResult swept_check(const SweptObject&, const SweptObject&) { return {}; }

int coplanarity_times(const Vec3&, const Vec3&, const Vec3&, const Vec3&, const Vec3&, const Vec3&,
                      const Vec3&, const Vec3&, Real*) {
  return 0;
}

}  // namespace trocar
