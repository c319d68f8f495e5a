// How the particles are spaced, for tests, the report and the benchmark: each particle's
// local spacing (mean distance to its 6 nearest neighbours, which is the spacing of a
// hexagonal sample), and how it follows the Gaussian curvature.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "common/kd_tree.h"
#include "particles/particle_system.h"

namespace mpumesh::particles {

// Of every stride-th point (0, stride, 2 stride, ...), among all of x; `index`: a
// PointIndex's tree over x, when the caller has one.
std::vector<double> local_spacing(const std::vector<Eigen::Vector3d>& x, size_t stride = 1,
                                  const KdTree* index = nullptr);

struct SpacingStats {
  double mean = 0, cv = 0;       // of the local spacing
  double high_k_median = 0;      // median spacing over the 10% highest |K|
  double low_k_median = 0;       // over the 10% lowest
  double ratio = 0;              // high_k_median / low_k_median
  double rank_correlation = 0;   // Spearman, spacing vs |K|
};
SpacingStats spacing_stats(const std::vector<double>& spacing, const std::vector<double>& abs_gauss);

// The particles' spacing (local_spacing) against |K| at the sampling's scale
// (SampleStats::gauss_at_scale): over all of them, and over those whose spacing their
// curvature sets rather than a plate's thickness (SampleStats::spacing_by_thickness), the
// relation the curvature weight is for: thin plates are flat and sampled densely, which
// can turn the relation over all of them around.
struct SpacingSummary {
  SpacingStats all, curved;
  int64_t curved_particles = 0;
};
SpacingSummary spacing_summary(const SampleStats& stats, const ParticleState& particles);

// Spearman's rank correlation of a and b (average ranks for ties).
double rank_correlation(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace mpumesh::particles
