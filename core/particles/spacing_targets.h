// The particles' target spacings (docs/method.md "Particles"): the curvature weights, the
// spacing each pool point asks for from its curvature, the bend bound and its local
// thickness, their grading, and the thickness search.
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <cstdint>
#include <vector>

#include "mpu/mpu_surface.h"
#include "particles/particle_step_ref.h"
#include "particles/particle_system.h"

namespace mpumesh {
class ComputeBackend;
}

namespace mpumesh::particles {

// Curvature weights λ_i = exp(-S k̂_i), k̂_i = √|K_i| clamped to mean ± 2 sd and scaled by
// the clamp range (at least the mean, so that a surface of nearly constant curvature, a
// sphere, gets uniform weights rather than its noise scaled up to 0..1). The mean and sd
// are taken over the values below the 99th percentile: where ∇f nearly vanishes (between
// two sheets of a CT surface) K reaches 1e14 and would set the clamp range alone.
std::vector<double> curvature_weights(const std::vector<double>& gauss, double scale, double& lo, double& hi);

struct Targets {
  std::vector<double> spacing;
  std::vector<double> by_thickness;  // 1 where the thickness bound sets the spacing, else 0
  int64_t thickness_bound = 0;
};

// Each pool point's target spacing s_i = min(b_i λ_i, max(factor t_i, 0.22 b_i)): its
// curvature's, or its local thickness t_i where that is finer, but no finer than 0.22 of
// the base spacing b_i (spacing a bone's thin plates at their thickness everywhere would
// take several times the particles; where a plate is thinner than the spacing allows,
// the triangulation's manifold repair adds the points it needs instead).
// The bend bound: the base spacing b_i = min(h, max(floor, turn / κ_i)), κ_i the larger principal
// curvature at the sampling's scale, so that the normal turns by at most `turn` radians
// across one spacing (a flat triangle's normal is then off the surface's by a fraction of
// that), where the scan resolves it (the floor); λ_i then makes it finer where |K| is high.
// `scale` multiplies turn and floor alike: a count or spacing asked for scales the whole
// field (Sampler::solve_flat_spacing).
Targets spacing_targets(const std::vector<double>& lambda, const std::vector<double>& thickness,
                        const std::vector<double>& kappa, double h, double bend_floor, double scale,
                        const SampleOptions& opt);

// Grades the targets (spacing_gradation.h; neighbours within max_reach at most) and then
// scales them all by one factor, so that they ask for as many particles as before:
// Σ w_i / s_i² is kept, w_i the area each point stands for. Grading alone only lowers
// targets, and where they are noisy (curvature measured on a coarse slice stack) it lowers
// them much: a 6 mm sphere phantom at 2 mm slices ended with 1,946 particles for 1,500
// (1,705 with the scaling). So grading moves particles from the flat parts to the steps,
// and the count stays about what --particles or --spacing asked.
void grade_targets(const std::vector<Eigen::Vector3d>& x, const std::vector<double>& w, Targets& t,
                   const SampleOptions& opt, double max_reach = INFINITY);

// Each particle's local thickness (local_thickness, on the backend), searched up to
// reach · lambda[i] (the spacing that curvature alone would give it, over the thickness
// factor: a thicker plate binds nothing); infinity for a lost particle.
std::vector<double> thicknesses(ComputeBackend& backend, const mpu::MpuSurface& s, const ParticleState& st,
                                const std::vector<double>& lambda, double reach);

}  // namespace mpumesh::particles
