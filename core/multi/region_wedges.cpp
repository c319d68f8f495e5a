#include "multi/region_wedges.h"

#include "geometry/angle.h"

namespace mpumesh::multi {

namespace {

uint32_t third_vertex(const std::array<uint32_t, 3>& t, uint32_t p, uint32_t q) {
  for (const uint32_t v : t)
    if (v != p && v != q) return v;
  return p;
}

}  // namespace

double wedge_of(const std::vector<Eigen::Vector3d>& V, const std::vector<std::array<uint32_t, 3>>& tris,
                const RegionWedge& w) {
  const auto& t = tris[w.f1];
  const Eigen::Vector3d n = (V[t[1]] - V[t[0]]).cross(V[t[2]] - V[t[0]]) * w.out_sign;
  return wedge_angle(V[w.p], V[w.q], V[third_vertex(t, w.p, w.q)], V[third_vertex(tris[w.f2], w.p, w.q)], n);
}

}  // namespace mpumesh::multi
