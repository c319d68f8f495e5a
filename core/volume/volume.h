// A scalar image volume in its physical frame: voxels (x fastest, then y, then z), the
// spacing in mm, the origin (physical position of voxel 0,0,0) and the direction cosines
// (columns are the physical directions of the index axes). CT volumes hold Hounsfield units.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace mpumesh {

struct Volume {
  std::array<int64_t, 3> dims{0, 0, 0};  // voxels along x, y, z
  Eigen::Vector3d spacing{1, 1, 1};       // mm
  Eigen::Vector3d origin{0, 0, 0};        // mm
  Eigen::Matrix3d direction = Eigen::Matrix3d::Identity();
  std::vector<float> voxels;              // dims[0]*dims[1]*dims[2] values
  std::string modality;                   // "CT", "MR", ... when the file says
  std::string source;                     // the path it was read from
  std::vector<std::string> read_notes;    // harmless things the file's reader said

  int64_t voxel_count() const { return dims[0] * dims[1] * dims[2]; }
  // The in-plane voxel size (mm): the finest detail a slice resolves.
  double in_plane_spacing() const { return std::min(spacing.x(), spacing.y()); }
  int64_t index(int64_t i, int64_t j, int64_t k) const { return i + dims[0] * (j + dims[1] * k); }
  float at(int64_t i, int64_t j, int64_t k) const { return voxels[size_t(index(i, j, k))]; }

  // Continuous index (i, j, k) to physical millimetres.
  Eigen::Vector3d index_to_physical(const Eigen::Vector3d& ijk) const {
    return origin + direction * ijk.cwiseProduct(spacing);
  }
};

// Throws InputError unless the volume has at least 2 voxels along every axis (a 2D image
// or a single slice cannot hold a closed surface).
void require_3d(const Volume& v);

// Checks the invariants every stage relies on; throws InputError naming `what`.
void validate_volume(const Volume& v, const std::string& what);

// Throws InputError naming `what` when a voxel is NaN or infinite.
void require_finite_voxels(const Volume& v, const std::string& what);

// The same physical extent on a grid of `dims` voxels (trilinear; voxel centres keep
// their places: new spacing = old spacing x old dims / new dims). Values are rounded when
// every input value is a whole number (CT in HU), so the result stores as int16.
Volume resample(const Volume& v, std::array<int64_t, 3> dims);

}  // namespace mpumesh
