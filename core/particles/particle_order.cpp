#include "particles/particle_order.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace mpumesh::particles {
namespace {

// Spreads the low 10 bits of v to every third bit (for a 30-bit Morton code).
uint32_t spread_bits(uint32_t v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

}  // namespace

// The order of the points along a Morton curve over a 1024^3 grid on their bounding box.
std::vector<size_t> morton_order(const std::vector<Eigen::Vector3d>& x) {
  const size_t n = x.size();
  std::vector<size_t> order(n);
  if (n == 0) return order;
  Eigen::Vector3d lo = x[0], hi = lo;
  for (const auto& p : x) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double scale = 1023.0 / std::max((hi - lo).maxCoeff(), 1e-9);
  std::vector<std::pair<uint32_t, uint32_t>> key(n);
  for (size_t i = 0; i < n; ++i) {
    uint32_t c = 0;
    for (int d = 0; d < 3; ++d) c |= spread_bits(uint32_t((x[i][d] - lo[d]) * scale)) << d;
    key[i] = {c, uint32_t(i)};
  }
  std::sort(key.begin(), key.end());
  for (size_t k = 0; k < n; ++k) order[k] = key[k].second;
  return order;
}

// Puts the particles in Morton order, so that consecutive particles
// share MPU leaves and neighbours in the cache. Seeding leaves them in the Poisson disk's
// random order and fission appends children at the end; in that order each evaluation
// and neighbour search missed the cache (the sample CT's surface is 258,581 leaves, about
// 75 MB). Both backends get the same order.
void order_spatially(ParticleState& st) {
  const size_t n = st.size();
  const std::vector<size_t> order = morton_order(st.x);
  auto permute = [&](auto& v) {
    std::remove_reference_t<decltype(v)> out(n);
    for (size_t k = 0; k < n; ++k) out[k] = v[order[k]];
    v.swap(out);
  };
  permute(st.x);
  permute(st.sigma);
  permute(st.target);
  permute(st.normal);
  permute(st.distance);
  permute(st.curv);
  permute(st.energy);
  permute(st.speed);
}

// Keeps the particles `rows` (ascending) in that order, all their per-particle values.
void keep_rows(ParticleState& st, const std::vector<size_t>& rows) {
  size_t m = 0;
  for (size_t k : rows) {
    MPUMESH_ASSERT(k >= m && k < st.size(), "keep_rows: rows must ascend");
    st.x[m] = st.x[k];
    st.sigma[m] = st.sigma[k];
    st.target[m] = st.target[k];
    st.normal[m] = st.normal[k];
    st.distance[m] = st.distance[k];
    st.curv[m] = st.curv[k];
    st.energy[m] = st.energy[k];
    st.speed[m] = st.speed[k];
    ++m;
  }
  st.resize(m);
}

// A tangent direction at angle 2π u in the plane normal to n.
Eigen::Vector3d tangent(const Eigen::Vector3d& n, double u) {
  Eigen::Vector3d a = Eigen::Vector3d::UnitX();
  if (std::abs(n.x()) > 0.7) a = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = n.cross(a).normalized(), e2 = n.cross(e1);
  const double t = 2 * M_PI * u;
  return std::cos(t) * e1 + std::sin(t) * e2;
}

}  // namespace mpumesh::particles
