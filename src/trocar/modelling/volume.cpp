#include "trocar/modelling/volume.h"

namespace trocar {

Volume make_volume(std::array<std::size_t, 3> dims, const Vec3& spacing, const Vec3& origin, float fill) {
  Volume v;
  v.dims = dims;
  v.spacing = spacing;
  v.origin = origin;
  v.layers.assign(1, std::vector<float>(v.voxel_count(), fill));
  v.source = "(volume made in code)";
  return v;
}

}  // namespace trocar
