// Disjoint sets over 0..n-1 (union-find with path halving), for grouping by connection:
// a complex's junction curves, a label's closed pieces.
#pragma once

#include <cstdint>
#include <numeric>
#include <vector>

namespace mpumesh {

class DisjointSets {
 public:
  explicit DisjointSets(size_t n) : up_(n) { std::iota(up_.begin(), up_.end(), 0u); }
  uint32_t find(uint32_t x) {
    while (up_[x] != x) x = up_[x] = up_[up_[x]];
    return x;
  }
  void join(uint32_t a, uint32_t b) { up_[find(a)] = find(b); }

 private:
  std::vector<uint32_t> up_;
};

}  // namespace mpumesh
