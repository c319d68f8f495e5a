#include "volume/volume.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/option_names.h"

namespace mpumesh {

Volume resample(const Volume& v, std::array<int64_t, 3> dims) {
  validate_volume(v, v.source);
  for (int a = 0; a < 3; ++a)
    if (dims[size_t(a)] < 1 || dims[size_t(a)] > 8192) throw InputError(option_ref("size") + ": each dimension must be 1 to 8192");
  Volume out;
  out.dims = dims;
  out.modality = v.modality;
  out.source = v.source;
  out.direction = v.direction;
  Eigen::Vector3d ratio, first;
  for (int a = 0; a < 3; ++a) {
    ratio[a] = double(v.dims[size_t(a)]) / double(dims[size_t(a)]);
    out.spacing[a] = v.spacing[a] * ratio[a];
    first[a] = 0.5 * ratio[a] - 0.5;  // old index of new voxel 0's centre
  }
  out.origin = v.index_to_physical(first);
  const bool whole = std::all_of(v.voxels.begin(), v.voxels.end(), [](float x) { return x == std::round(x); });
  out.voxels.resize(size_t(out.voxel_count()));
  // Per axis: the two old indices and the weight of the second, for each new index.
  std::array<std::vector<int64_t>, 3> lo;
  std::array<std::vector<float>, 3> w;
  for (int a = 0; a < 3; ++a) {
    const int64_t n = v.dims[size_t(a)];
    for (int64_t i = 0; i < dims[size_t(a)]; ++i) {
      const double u = std::clamp((double(i) + 0.5) * ratio[a] - 0.5, 0.0, double(n - 1));
      const int64_t i0 = std::min<int64_t>(int64_t(std::floor(u)), std::max<int64_t>(n - 2, 0));
      lo[size_t(a)].push_back(i0);
      w[size_t(a)].push_back(n > 1 ? float(u - double(i0)) : 0.0f);
    }
  }
  tbb::parallel_for(int64_t(0), dims[2], [&](int64_t k) {
    const int64_t k0 = lo[2][size_t(k)], k1 = std::min(k0 + 1, v.dims[2] - 1);
    const float wk = w[2][size_t(k)];
    for (int64_t j = 0; j < dims[1]; ++j) {
      const int64_t j0 = lo[1][size_t(j)], j1 = std::min(j0 + 1, v.dims[1] - 1);
      const float wj = w[1][size_t(j)];
      for (int64_t i = 0; i < dims[0]; ++i) {
        const int64_t i0 = lo[0][size_t(i)], i1 = std::min(i0 + 1, v.dims[0] - 1);
        const float wi = w[0][size_t(i)];
        auto lerp_x = [&](int64_t jj, int64_t kk) { return v.at(i0, jj, kk) * (1 - wi) + v.at(i1, jj, kk) * wi; };
        const float a = lerp_x(j0, k0) * (1 - wj) + lerp_x(j1, k0) * wj;
        const float b = lerp_x(j0, k1) * (1 - wj) + lerp_x(j1, k1) * wj;
        const float x = a * (1 - wk) + b * wk;
        out.voxels[size_t(out.index(i, j, k))] = whole ? std::round(x) : x;
      }
    }
  });
  return out;
}

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

void require_finite_voxels(const Volume& v, const std::string& what) {
  for (const float x : v.voxels)
    if (!std::isfinite(x)) throw InputError(what + ": the volume holds NaN or infinite values");
}

}  // namespace mpumesh
