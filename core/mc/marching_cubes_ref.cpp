#include "mc/marching_cubes_ref.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>

#include "common/error.h"
#include "mc/mc_table.h"

namespace mpumesh::mc {
namespace {

// Per grid point: bits 0-2 = owned edges (x, y, z) that cross; bits 3-10 = cube case
// (0 when the point has no cube, at the far faces of the grid).
uint32_t classify_point(const McField& fd, int64_t i, int64_t j, int64_t k) {
  const int64_t nx = fd.dims[0], ny = fd.dims[1], nz = fd.dims[2];
  auto in = [&](int64_t a, int64_t b, int64_t c) {
    return uint32_t(fd.values[size_t(a + nx * (b + ny * c))] >= 0.0f);
  };
  const uint32_t s = in(i, j, k);
  uint32_t mask = 0;
  if (i + 1 < nx) mask |= (s ^ in(i + 1, j, k)) << 0;
  if (j + 1 < ny) mask |= (s ^ in(i, j + 1, k)) << 1;
  if (k + 1 < nz) mask |= (s ^ in(i, j, k + 1)) << 2;
  uint32_t cube = 0;
  if (i + 1 < nx && j + 1 < ny && k + 1 < nz)
    for (int c = 0; c < 8; ++c) cube |= in(i + kCorner[c][0], j + kCorner[c][1], k + kCorner[c][2]) << c;
  return mask | (cube << 3);
}

}  // namespace

McMesh marching_cubes_ref(const McField& fd) {
  const int64_t nx = fd.dims[0], ny = fd.dims[1], nz = fd.dims[2];
  MPUMESH_ASSERT(nx >= 2 && ny >= 2 && nz >= 2 && int64_t(fd.values.size()) == nx * ny * nz,
                 "marching cubes needs a padded field");
  const auto& table = case_table();
  const size_t n = size_t(nx * ny * nz);
  std::vector<uint32_t> info(n);
  // Per-slice counts, so that slices can be generated in parallel at fixed offsets.
  std::vector<uint64_t> slice_v(size_t(nz) + 1, 0), slice_t(size_t(nz) + 1, 0);
  tbb::parallel_for(int64_t(0), nz, [&](int64_t k) {
    uint64_t nv = 0, nt = 0;
    for (int64_t j = 0; j < ny; ++j)
      for (int64_t i = 0; i < nx; ++i) {
        uint32_t v = classify_point(fd, i, j, k);
        info[size_t(i + nx * (j + ny * k))] = v;
        nv += std::popcount(v & 7u);
        nt += uint64_t(table[v >> 3].triangle_count);
      }
    slice_v[size_t(k) + 1] = nv;
    slice_t[size_t(k) + 1] = nt;
  });
  for (int64_t k = 0; k < nz; ++k) {
    slice_v[size_t(k) + 1] += slice_v[size_t(k)];
    slice_t[size_t(k) + 1] += slice_t[size_t(k)];
  }
  if (slice_v.back() > UINT32_MAX) throw InputError("marching cubes: more than 2^32 vertices");
  // Vertex offset of every point, in point order.
  std::vector<uint32_t> voff(n);
  tbb::parallel_for(int64_t(0), nz, [&](int64_t k) {
    uint32_t acc = uint32_t(slice_v[size_t(k)]);
    for (int64_t p = nx * ny * k; p < nx * ny * (k + 1); ++p) {
      voff[size_t(p)] = acc;
      acc += uint32_t(std::popcount(info[size_t(p)] & 7u));
    }
  });
  McMesh mesh;
  mesh.grid_vertices.resize(slice_v.back());
  mesh.triangles.resize(slice_t.back());
  const double lo = kMinEdgeFraction, hi = 1.0 - kMinEdgeFraction;
  tbb::parallel_for(int64_t(0), nz, [&](int64_t k) {
    uint64_t t_at = slice_t[size_t(k)];
    for (int64_t j = 0; j < ny; ++j)
      for (int64_t i = 0; i < nx; ++i) {
        const size_t p = size_t(i + nx * (j + ny * k));
        const uint32_t v = info[p];
        uint32_t at = voff[p];
        const double f0 = fd.values[p];
        const int64_t step[3] = {1, nx, nx * ny};
        for (int a = 0; a < 3; ++a) {
          if (!((v >> a) & 1u)) continue;
          const double f1 = fd.values[p + size_t(step[a])];
          const double t = std::clamp(f0 / (f0 - f1), lo, hi);
          std::array<double, 3> pos{double(i), double(j), double(k)};
          pos[size_t(a)] += t;
          mesh.grid_vertices[at++] = pos;
        }
        const CubeCase& cc = table[v >> 3];
        for (int t = 0; t < cc.triangle_count; ++t) {
          std::array<uint32_t, 3> tri;
          for (int c = 0; c < 3; ++c) {
            const EdgeOwner& eo = kEdgeOwner[size_t(cc.edges[size_t(3 * t + c)])];
            const size_t q = size_t((i + eo.dx) + nx * ((j + eo.dy) + ny * (k + eo.dz)));
            const uint32_t below = info[q] & ((1u << eo.axis) - 1u);
            tri[size_t(c)] = voff[q] + uint32_t(std::popcount(below));
          }
          mesh.triangles[t_at++] = tri;
        }
      }
  });
  return mesh;
}

}  // namespace mpumesh::mc
