#include "mc/mc_field.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <tbb/parallel_for.h>

#include "common/error.h"
#include "common/option_names.h"

namespace mpumesh::mc {

McField make_threshold_field(const Volume& vol, ThresholdRange range) {
  if (!(range.lo <= range.hi))
    throw InputError("threshold: the lower bound " + std::to_string(range.lo) +
                     " is above the upper bound " + std::to_string(range.hi));
  McField field;
  const int64_t nx = vol.dims[0], ny = vol.dims[1], nz = vol.dims[2];
  field.dims = {nx + 2, ny + 2, nz + 2};
  const int64_t px = nx + 2, py = ny + 2, pz = nz + 2;
  field.values.assign(size_t(px * py * pz), 0.0f);
  const float lo = float(range.lo), hi = float(std::min(range.hi, 3.0e38));
  auto inner = [&](float v) {
    float f = std::min(v - lo, hi - v);
    return std::isnan(f) ? -1.0f : f;
  };
  tbb::parallel_for(int64_t(0), pz, [&](int64_t k) {
    const int64_t sk = std::clamp<int64_t>(k - 1, 0, nz - 1);
    const bool pad_k = k == 0 || k == pz - 1;
    for (int64_t j = 0; j < py; ++j) {
      const int64_t sj = std::clamp<int64_t>(j - 1, 0, ny - 1);
      const bool pad_j = pad_k || j == 0 || j == py - 1;
      float* row = &field.values[size_t(px * (j + py * k))];
      const float* src = &vol.voxels[size_t(nx * (sj + ny * sk))];
      for (int64_t i = 0; i < px; ++i) {
        const int64_t si = std::clamp<int64_t>(i - 1, 0, nx - 1);
        float f = inner(src[si]);
        const bool pad = pad_j || i == 0 || i == px - 1;
        row[i] = pad ? -std::max(std::abs(f), 0.5f) : f;
      }
    }
  });
  return field;
}

ThresholdRange parse_threshold(const std::string& text) {
  ThresholdRange r;
  auto num = [&](const std::string& s) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != s.size() || !std::isfinite(v))
      throw InputError(option_ref("threshold") + ": '" + text + "' is not LO or LO:HI (numbers)");
    return v;
  };
  auto colon = text.find(':');
  if (colon == std::string::npos) {
    r.lo = num(text);
  } else {
    r.lo = num(text.substr(0, colon));
    r.hi = num(text.substr(colon + 1));
  }
  if (r.lo > r.hi) throw InputError(option_ref("threshold") + ": LO is above HI in '" + text + "'");
  return r;
}

}  // namespace mpumesh::mc
