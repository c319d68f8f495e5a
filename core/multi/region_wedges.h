// A region's wedge at an edge of a multi-material complex where three or more regions meet:
// the angle inside the region between its two triangles there (geometry/angle.h
// wedge_angle), which bounds its tetrahedra's dihedral angles at that edge
// (multi/thin_wedges.h). The complex's optimiser and its volume match keep it.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace mpumesh::multi {

// The least wedge a region keeps (degrees). It is above the 10° a tetrahedron is to keep:
// where two wedges near 10° meet at a vertex on a flat ridge of the region, the corner
// between them holds one tetrahedron whose angles the surface fixes, under 10° whatever
// lies inside.
inline constexpr double kMinWedgeDeg = 15;

// A region's two triangles f1, f2 at edge p-q; f1's normal points out of the region when
// out_sign is 1, into it when -1.
struct RegionWedge {
  uint32_t p = 0, q = 0, f1 = 0, f2 = 0;
  double out_sign = 1;
  int64_t region = 0;
};

// The wedges at edge p-q of the regions other than the background (0) that have exactly
// two of `faces`, the triangles at that edge (labels[f]: face f's two regions, the first
// the one its normal points out of), each region once, in the order its first triangle
// has among `faces`.
template <class Labels>
std::vector<RegionWedge> region_wedges(uint32_t p, uint32_t q, std::span<const uint32_t> faces, const Labels& labels) {
  std::vector<RegionWedge> out;
  for (const uint32_t f : faces)
    for (const auto region : labels[f]) {
      if (region == 0) continue;
      std::vector<uint32_t> two;
      for (const uint32_t g : faces)
        if (labels[g][0] == region || labels[g][1] == region) two.push_back(g);
      if (two.size() != 2 || two[0] != f) continue;
      out.push_back({p, q, two[0], two[1], labels[two[0]][0] == region ? 1.0 : -1.0, int64_t(region)});
    }
  return out;
}

// The wedge's angle (radians, in [0, 2 pi]) with the triangles `tris` over the points `V`.
double wedge_of(const std::vector<Eigen::Vector3d>& V, const std::vector<std::array<uint32_t, 3>>& tris,
                const RegionWedge& w);

}  // namespace mpumesh::multi
