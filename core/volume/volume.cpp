#include "volume/volume.h"

#include <cmath>

#include "common/error.h"

namespace mpumesh {

void require_3d(const Volume& v) {
  if (v.dims[0] < 2 || v.dims[1] < 2 || v.dims[2] < 2)
    throw InputError((v.source.empty() ? std::string("volume") : v.source) + ": a 2D image (" +
                     std::to_string(v.dims[0]) + " x " + std::to_string(v.dims[1]) + " x " +
                     std::to_string(v.dims[2]) + " voxels); meshing needs a volume of at least 2 slices");
}

void validate_volume(const Volume& v, const std::string& what) {
  for (int a = 0; a < 3; ++a) {
    if (v.dims[a] < 1) throw InputError(what + ": empty volume (a dimension is 0)");
    if (!(v.spacing[a] > 0) || !std::isfinite(v.spacing[a]))
      throw InputError(what + ": voxel spacing must be positive and finite, got " +
                       std::to_string(v.spacing[a]) + " mm along axis " + std::to_string(a));
  }
  if (int64_t(v.voxels.size()) != v.voxel_count())
    throw InputError(what + ": voxel count does not match the dimensions");
  if (!v.origin.allFinite() || !v.direction.allFinite() || std::abs(v.direction.determinant()) < 1e-6)
    throw InputError(what + ": origin or direction cosines are not valid");
}

}  // namespace mpumesh
