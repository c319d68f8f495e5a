#include "segment/components.h"

#include <algorithm>
#include <functional>
#include <numeric>

namespace mpumesh::seg {
namespace {

struct DisjointSets {
  std::vector<uint32_t> parent;
  uint32_t find(uint32_t a) {
    while (parent[a] != a) {
      parent[a] = parent[parent[a]];
      a = parent[a];
    }
    return a;
  }
  void unite(uint32_t a, uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

struct Run {
  int64_t x0, x1;  // [x0, x1)
};

}  // namespace

// Run-based labelling: the inside voxels of each row as runs along x; a run joins the runs
// of the row below (y - 1) and of the slice below (z - 1) that overlap it in x. Memory and
// time scale with the number of runs, not of voxels.
ComponentStats mask_components(const std::vector<uint8_t>& mask, std::array<int64_t, 3> dims) {
  const int64_t nx = dims[0], ny = dims[1], nz = dims[2], rows = ny * nz;
  std::vector<Run> runs;
  std::vector<size_t> first(size_t(rows) + 1, 0);
  for (int64_t r = 0; r < rows; ++r) {
    first[size_t(r)] = runs.size();
    const uint8_t* row = mask.data() + nx * r;
    for (int64_t i = 0; i < nx;) {
      if (!row[i]) {
        ++i;
        continue;
      }
      const int64_t x0 = i;
      while (i < nx && row[i]) ++i;
      runs.push_back({x0, i});
    }
  }
  first[size_t(rows)] = runs.size();
  DisjointSets ds;
  ds.parent.resize(runs.size());
  std::iota(ds.parent.begin(), ds.parent.end(), 0u);
  auto join_rows = [&](int64_t r, int64_t q) {  // overlapping runs of rows r and q
    size_t a = first[size_t(r)], b = first[size_t(q)];
    const size_t ae = first[size_t(r) + 1], be = first[size_t(q) + 1];
    while (a < ae && b < be) {
      if (runs[a].x0 < runs[b].x1 && runs[b].x0 < runs[a].x1) ds.unite(uint32_t(a), uint32_t(b));
      if (runs[a].x1 < runs[b].x1) ++a;
      else ++b;
    }
  };
  for (int64_t k = 0; k < nz; ++k)
    for (int64_t j = 0; j < ny; ++j) {
      const int64_t r = j + ny * k;
      if (j > 0) join_rows(r, r - 1);
      if (k > 0) join_rows(r, r - ny);
    }
  std::vector<int64_t> size(runs.size(), 0);
  for (size_t a = 0; a < runs.size(); ++a) size[ds.find(uint32_t(a))] += runs[a].x1 - runs[a].x0;
  ComponentStats s;
  for (int64_t v : size)
    if (v) s.sizes.push_back(v);
  std::sort(s.sizes.begin(), s.sizes.end(), std::greater<>());
  s.count = int64_t(s.sizes.size());
  return s;
}

}  // namespace mpumesh::seg
