#include "tet/region_quality.h"

namespace mpumesh {

std::map<int32_t, TetQuality> quality_by_region(const TetMesh& m) {
  std::map<int32_t, TetMesh> parts;
  for (size_t t = 0; t < m.tets.size(); ++t) parts[m.region[t]].tets.push_back(m.tets[t]);
  std::map<int32_t, TetQuality> out;
  for (auto& [region, part] : parts) {
    part.nodes = m.nodes;
    part.region.assign(part.tets.size(), region);
    part.regions = 1;
    out[region] = measure_tet_quality(part);
  }
  return out;
}

}  // namespace mpumesh
