// The multi-material implicit model (docs/method.md "Several labels"): one fitted MPU
// function per label, and a labelling of space from them. Region 0 is the background and
// regions 1..n the labels, each with a function f_r (negative inside, about the signed
// distance in mm). The background's own function is f_0 = -f_U, U the union of the
// labels fitted as one more label (a label map), or, without it, f_0 = -min_r f_r (the
// parts of a mesh, which stay apart where they do not overlap). The labelling is
//     region(p) = argmin_r f_r(p),   r = 0..n,
// the most inside; where two regions touch, their common boundary is the one surface
// f_a = f_b, with no gap and no overlap by construction, and three regions meet along
// the curves f_a = f_b = f_c. With a label map's support (multi/region_support.h), only
// the regions whose voxels lie within two voxels of p compete there (a region beyond
// its support has f = +infinity), so that a fit extrapolated far from its points cannot
// claim space. Two labels fitted from touching voxels each end near the
// voxels' common face; between them the union is inside, f_0 > 0, so the background
// takes no sliver there. A label's function counts only within its fitted points' box
// (widened by 0.5% of its cube): beyond it the leaves' polynomials are extrapolated and
// may go negative where no surface is (mesh/delaunay_state.h says the same of one fit).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

#include "mpu/mpu_surface.h"
#include "multi/region_support.h"

namespace mpumesh::multi {

class MaterialField {
 public:
  // `fits[r-1]` is region r's function (label `labels[r-1]`); `outside` the union's fit or
  // null. The fits must outlive the field.
  MaterialField(std::vector<int64_t> labels, std::vector<const mpu::MpuSurface*> fits,
                const mpu::MpuSurface* outside, const RegionSupport* support = nullptr);

  int regions() const { return int(fits_.size()) + 1; }
  // The label of region r (0 for the background).
  int64_t label(int r) const { return r == 0 ? 0 : labels_[size_t(r - 1)]; }

  // Every region's function at p (size regions()).
  void values(const Eigen::Vector3d& p, std::vector<double>& f) const;
  // The same with gradients.
  void values_and_gradients(const Eigen::Vector3d& p, std::vector<double>& f, std::vector<Eigen::Vector3d>& g) const;
  // The region at p.
  int region_at(const Eigen::Vector3d& p) const;
  // The regions in order of their value at p, most inside first (ties by index).
  std::vector<int> ranked(const Eigen::Vector3d& p) const;
  // The same from the values at a point (values()).
  static std::vector<int> ranked(const std::vector<double>& f);

  // p moved onto the interface f_a = f_b (Newton steps on f_a - f_b along its gradient,
  // at most `max_move` in all); false when it does not converge there.
  bool project_interface(Eigen::Vector3d& p, int a, int b, double max_move) const;
  // p moved onto the curve f_a = f_b = f_c (the least-norm Newton step of the two
  // differences); false when it does not converge within `max_move`.
  bool project_junction(Eigen::Vector3d& p, const std::array<int, 3>& abc, double max_move) const;
  // The junction curve's unit tangent at p (zero where the three gradients are parallel).
  Eigen::Vector3d junction_tangent(const Eigen::Vector3d& p, const std::array<int, 3>& abc) const;
  // The interface's unit normal at p, pointing from a into b.
  Eigen::Vector3d interface_normal(const Eigen::Vector3d& p, int a, int b) const;

 private:
  double f_of(int r, const Eigen::Vector3d& p, Eigen::Vector3d* g) const;
  std::vector<int64_t> labels_;
  std::vector<const mpu::MpuSurface*> fits_;
  const mpu::MpuSurface* outside_;
  const RegionSupport* support_;
};

// Whether p lies within the fit's points' box, widened by 0.5% of its cube.
bool within_fit(const mpu::MpuSurface& s, const Eigen::Vector3d& p);

}  // namespace mpumesh::multi
