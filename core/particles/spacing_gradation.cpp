#include "particles/spacing_gradation.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <queue>

#include "common/error.h"
#include "particles/particle_step_ref.h"

namespace mpumesh::particles {

size_t limit_spacing_gradient(const std::vector<Eigen::Vector3d>& x, std::vector<double>& spacing, double grade,
                              double max_reach, double link) {
  const size_t n = x.size();
  MPUMESH_ASSERT(spacing.size() == n, "one target spacing per point");
  MPUMESH_ASSERT(grade > 0 && link > 0 && max_reach > 0, "spacing gradation: grade and link must be positive");
  if (n < 2) return 0;
  std::vector<double> sorted(spacing);
  std::nth_element(sorted.begin(), sorted.begin() + ptrdiff_t(n / 2), sorted.end());
  const double median = sorted[n / 2];
  MPUMESH_ASSERT(median > 0 && std::isfinite(median), "target spacings must be positive and finite");
  const ParticleGrid g = build_particle_grid(x, std::min(link * median, max_reach));

  // Each point's neighbours within link · s_i (at most max_reach), found from its own side,
  // as (i, j) pairs gathered per block of points.
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> blocks((n + 1023) / 1024);
  tbb::parallel_for(size_t(0), blocks.size(), [&](size_t b) {
    auto& pairs = blocks[b];
    for (size_t i = b * 1024; i < std::min(n, (b + 1) * 1024); ++i) {
      const double reach = std::min(link * spacing[i], max_reach), reach2 = reach * reach;
      int64_t lo[3], hi[3];
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::max<int64_t>(int64_t(std::floor((x[i][d] - reach - g.origin[d]) / g.cell)), 0);
        hi[d] = std::min<int64_t>(int64_t(std::floor((x[i][d] + reach - g.origin[d]) / g.cell)),
                                  int64_t(g.dims[size_t(d)]) - 1);
      }
      for (int64_t z = lo[2]; z <= hi[2]; ++z)
        for (int64_t y = lo[1]; y <= hi[1]; ++y) {
          const int64_t row = int64_t(g.dims[0]) * (y + int64_t(g.dims[1]) * z);
          for (uint32_t k = g.start[size_t(row + lo[0])]; k < g.start[size_t(row + hi[0] + 1)]; ++k) {
            const uint32_t j = g.order[k];
            if (j != i && (x[j] - x[i]).squaredNorm() < reach2) pairs.push_back({uint32_t(i), j});
          }
        }
    }
  });
  // Symmetric adjacency (compressed rows).
  std::vector<uint32_t> start(n + 1, 0);
  for (const auto& pairs : blocks)
    for (const auto& [i, j] : pairs) {
      ++start[i + 1];
      ++start[j + 1];
    }
  for (size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<uint32_t> adj(start[n]), fill(start.begin(), start.end() - 1);
  for (const auto& pairs : blocks)
    for (const auto& [i, j] : pairs) {
      adj[fill[i]++] = j;
      adj[fill[j]++] = i;
    }
  blocks = {};

  // Dijkstra: the smallest target is final; it bounds its neighbours', and so on. Ties are
  // broken by index, so the result does not depend on the order the points came in.
  using Entry = std::pair<double, uint32_t>;
  std::vector<Entry> initial(n);
  for (size_t i = 0; i < n; ++i) initial[i] = {spacing[i], uint32_t(i)};
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue(std::greater<Entry>(), std::move(initial));
  std::vector<char> lowered(n, 0), done(n, 0);
  while (!queue.empty()) {
    const auto [s, i] = queue.top();
    queue.pop();
    if (done[i] || s > spacing[i]) continue;
    done[i] = 1;
    for (uint32_t k = start[i]; k < start[i + 1]; ++k) {
      const uint32_t j = adj[k];
      const double bound = s + grade * (x[j] - x[i]).norm();
      if (!done[j] && bound < spacing[j]) {
        spacing[j] = bound;
        lowered[j] = 1;
        queue.push({bound, j});
      }
    }
  }
  size_t count = 0;
  for (char l : lowered) count += size_t(l);
  return count;
}

}  // namespace mpumesh::particles
