// Where an MPU fit holds: within its points' bounding box, widened by 0.5% of its cube.
// No surface lies beyond it, while the leaves' polynomials, extrapolated into the cube's
// margin, can go negative (on the sample CT, f = -35 to -650 mm 4 to 16 mm beyond the
// points at the volume's border): the triangulation (mesh/delaunay_state.h) and the
// multi-material field (multi/material_field.h) take a fit as far outside there.
#pragma once

#include <Eigen/Dense>

#include "mpu/mpu_surface.h"

namespace mpumesh {

inline bool within_data(const mpu::MpuSurface& s, const Eigen::Vector3d& x) {
  const double margin = 0.005 * s.box_size;
  return !((x.array() < s.data_min.array() - margin).any() || (x.array() > s.data_max.array() + margin).any());
}

}  // namespace mpumesh
