// Where each region of a label map may be: its voxels, dilated by kSupportVoxels voxels
// along each grid axis. A fitted MPU function is trustworthy near its own points only:
// away from them its leaves extrapolate, and a label's function can go negative inside
// another label (on the sectors phantom, f = -4 mm 9 mm from that label's voxels). The
// labelling (multi/material_field.h) lets a region compete only where its support
// reaches, so that deep inside a label only that label is a candidate; near an
// interface both of its regions are. One bit per voxel of each region's box (its voxels'
// bounding box widened by the support), so that a map of many small labels costs little.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

#include "volume/volume.h"

namespace mpumesh::multi {

// Two voxels: a label's fitted surface lies within a voxel of its voxels' boundary.
inline constexpr int kSupportVoxels = 2;

class RegionSupport {
 public:
  // Region r > 0 is the voxels holding labels[r-1]; region 0 every other voxel.
  RegionSupport(const Volume& map, const std::vector<int64_t>& labels);
  // Whether region r may be at p; beyond the grid only the background may.
  bool allows(int r, const Eigen::Vector3d& p) const;
  int regions() const { return int(bits_.size()); }

  // The layout, for a device's copy: voxel index = round(to_index() * (p - origin()) /
  // spacing()); region r's bits cover box(r), x fastest, 64 voxels a word.
  struct Box {
    std::array<int64_t, 3> lo{0, 0, 0}, hi{0, 0, 0};  // voxel indices, hi exclusive
  };
  const std::array<int64_t, 3>& dims() const { return dims_; }
  const Eigen::Vector3d& origin() const { return origin_; }
  const Eigen::Vector3d& spacing() const { return spacing_; }
  const Eigen::Matrix3d& to_index() const { return to_index_; }
  const Box& box(int r) const { return boxes_[size_t(r)]; }
  const std::vector<uint64_t>& bits(int r) const { return bits_[size_t(r)]; }

 private:
  // The voxel nearest p; false beyond the grid.
  bool voxel_of(const Eigen::Vector3d& p, std::array<int64_t, 3>& idx) const;
  std::array<int64_t, 3> dims_;
  Eigen::Vector3d origin_, spacing_;
  Eigen::Matrix3d to_index_;
  std::vector<Box> boxes_;
  std::vector<std::vector<uint64_t>> bits_;
};

}  // namespace mpumesh::multi
