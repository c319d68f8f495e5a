// The particles' target spacing as a field over the surface, set before the particles run:
// computed on the seeding pool (a Poisson-disk sample of f = 0 at about the input's
// largest sampling gap, particle_system.cpp) and read by each particle from the pool
// points around it. Targets that each particle takes from its own curvature, as it moves,
// follow the noise of the MPU surface's second derivatives: with the targets graded
// (spacing_gradation.h), one noisy particle lowers every target within (h - s) / grade of
// it, which evens the spacing out (on the CT-like torus phantom nearly uniform), and the
// population churns as the targets move with the particles.
//
// Curvature at the sampling's scale. A mesh whose edges are s long cannot follow a bend
// narrower than s, and the MPU surface's curvature at a point holds detail down to its
// leaves' size (and the noise of the contours at that size). So the curvature that sets a
// spacing is the mean over the patch that one sample of that spacing stands for: each
// pool point's K and κ = max(|κ1|, |κ2|) are averaged, weighted by the pool points' areas,
// over the pool points within max(s, r) of it (s its spacing from the curvature it has
// at its own point, r the pool's radius) whose normals agree with its own (within 60°,
// so that the two faces of a plate thinner than s do not mix). The mean of K over a patch
// is its total curvature over its area: what the angle deficit of a mesh vertex of that
// spacing measures.
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <utility>
#include <vector>

#include "common/kd_tree.h"

namespace mpumesh::particles {

// Each point's curvature averaged over its patch (above): `gauss` and `kappa` (K and the
// larger principal |κ|) are replaced by their area-weighted means over the points within
// radius[i] of point i whose normals lie within 60° of its own.
void average_over_patches(const std::vector<Eigen::Vector3d>& x, const std::vector<Eigen::Vector3d>& normal,
                          const std::vector<double>& area, const std::vector<double>& radius, std::vector<double>& gauss,
                          std::vector<double>& kappa);

// A value given at the pool's points, read anywhere on the surface: the inverse-square-
// distance mean over the kNeighbours nearest pool points whose normals lie within 90° of
// the query's (all of them where none does).
class SizingField {
 public:
  static constexpr int kNeighbours = 8;
  // `index`: a PointIndex's tree over x, which fields over the same points share (else
  // the field builds its own); it must outlive the field.
  SizingField(const std::vector<Eigen::Vector3d>& x, const std::vector<Eigen::Vector3d>& normal,
              std::vector<double> value, const KdTree* index = nullptr);
  double at(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const;
  // at(p, n) of this field and of `other`, a field over the same points and tree, from one
  // search: the same two values.
  std::pair<double, double> at_with(const SizingField& other, const Eigen::Vector3d& p, const Eigen::Vector3d& n) const;

 private:
  // The kNeighbours nearest points' ids and squared distances; returns how many.
  size_t nearest(const Eigen::Vector3d& p, uint32_t idx[kNeighbours], double d2[kNeighbours]) const;
  // The mean of `value` over those neighbours (see at).
  double mean(const std::vector<double>& value, const Eigen::Vector3d& n, const uint32_t* idx, const double* d2,
              size_t count) const;

  const std::vector<Eigen::Vector3d>& normal_;
  std::vector<double> value_;
  std::unique_ptr<PointIndex> own_index_;
  const KdTree& tree_;
};

}  // namespace mpumesh::particles
