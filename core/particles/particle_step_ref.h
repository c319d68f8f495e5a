// One iteration of the particle system (docs/method.md "Particles", Witkin & Heckbert 1994 with
// the paper's curvature weight) in double precision: the CPU reference of
// shaders/particle_step_grid_*.comp, particle_step_repulsion.comp, particle_step_project.comp and
// particle_step_thickness.comp, and the native CPU path. The population (fission, death)
// is decided between batches of iterations by particle_system.cpp, on the CPU for both
// backends.
//
// Per iteration, from positions x_i on f = 0 with repulsion radii σ_i:
//   1. neighbour grid: cells of cutoff·max σ, particles counting-sorted by cell;
//   2. repulsion (eq. 11, 12): E_ij = μ exp(-r²/2σ_i²), E_ji = μ exp(-r²/2σ_j²), each term
//      cut at r = cutoff·σ of its own particle;
//        E_i  = Σ_j (E_ij + E_ji),           ∂E_i/∂σ_i = Σ_j r²/σ_i³ E_ij,
//        D_i  = σ_i² Σ_j r_ij (E_ij/σ_i² + E_ji/σ_j²),   r_ij = x_i - x_j;
//      the velocity keeps D's tangent part and adds Witkin–Heckbert's feedback toward
//      f = 0: ṗ_i = D_i - (n_i·D_i + φ d_i) n_i (d_i = f/|∇f|, the signed distance);
//      x_i += Δt ṗ_i, the move capped at max_move·σ_i;
//      σ̇_i = -ρ (E_i - Ê) / (∂E_i/∂σ_i + β), σ_i += Δt σ̇_i, the change capped at the
//      factor sigma_change either way and σ_i at sigma_cap (both steps linearly implicit,
//      see repulsion_step);
//   3. projection: newton_steps Newton steps x -= f ∇f / |∇f|² (each capped at σ_i), the
//      last one from the evaluation that also gives the normal for the next iteration;
//      the distance kept is the linearised f / |∇f| after that step (0 unless capped).
//      The curvature (Kindlmann) is measured on the last iteration of a batch only: the
//      weights use it between batches, and leaving the Hessian out of the other
//      iterations' evaluations saves about a third of their cost. It is taken from the
//      Hessian of f, not from the blended Hessian that the surface's curvature elsewhere
//      comes from (mpu_eval_ref.h): the Hessian of f is large where the leaves disagree,
//      on the thinnest plates and folds, and the weights it gives sample those more
//      densely (fewer needles at the rims of plates thinner than the sampling).
// The paper multiplies E_i and ṗ_i by the curvature weight λ_i; here λ_i sets the
// particle's target radius instead (particle_system.h), which is the reading that
// makes high curvature denser (see docs/method.md): scaling E_i and Ê alike would change the
// speed only.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "mpu/mpu_eval_ref.h"
#include "mpu/mpu_surface.h"

namespace mpumesh::particles {

struct StepParams {
  double dt = 0.3;             // Δt (paper)
  double mu = 6;               // μ (paper)
  double desired_energy = 4.8; // Ê = 0.8 μ (Witkin–Heckbert)
  double rho = 15, beta = 10;  // σ update (Witkin–Heckbert)
  double phi = 15;             // surface feedback (Witkin–Heckbert)
  double gamma = 4;            // equilibrium when |ṗ_i| < γ σ_i (paper)
  double cutoff = 3;           // neighbour cutoff, in σ
  double max_move = 0.5;       // largest move per iteration, in σ_i
  double sigma_change = 1.25;  // largest factor σ_i changes by per iteration
  // Largest σ during a batch of iterations, set by the driver (particle_system.h): it
  // bounds the interaction range, so the GPU's neighbour grid can be sized once a batch.
  double sigma_cap = 1e30;
  int newton_steps = 1;  // at least 1
};

// The particles, structure of arrays. x, sigma are the state; normal, distance and curv
// are what the last projection measured at x; energy and speed what the last repulsion
// measured (before the move).
struct ParticleState {
  std::vector<Eigen::Vector3d> x;
  std::vector<double> sigma;
  std::vector<double> target;  // σ̂_i, set between batches (particle_system.cpp)
  std::vector<Eigen::Vector3d> normal;  // ∇f / |∇f|
  std::vector<double> distance;         // f / |∇f|, mm; NaN where ∇f vanished (lost)
  std::vector<mpu::Curvature> curv;
  std::vector<double> energy, speed;    // E_i and |ṗ_i|
  size_t size() const { return x.size(); }
  void resize(size_t n);
};

// Particles sorted by cell of a uniform grid (counting sort), as particle_step_grid_*.comp
// builds it on the GPU.
struct ParticleGrid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double cell = 1;
  std::array<uint32_t, 3> dims{1, 1, 1};
  std::vector<uint32_t> start;  // cells + 1
  std::vector<uint32_t> order;  // particle indices by cell
  std::vector<uint32_t> cell_of;
};
// Of the particles with member[i] set (all when null); cells of at least `cell`.
ParticleGrid build_particle_grid(const std::vector<Eigen::Vector3d>& x, double cell,
                                 const std::vector<uint8_t>* member = nullptr);

// The CPU path's two grids: where σ varies several-fold (the sample CT), one grid with
// cells of cutoff · max σ holds hundreds of particles per cell, and most distance tests
// fail. So the 95% smallest σ go into a grid of cells of cutoff · σ_split (their 95th
// percentile), the rest into one of cutoff · max σ. The GPU keeps one grid.
struct ParticleGrids {
  ParticleGrid small, large;
  double sigma_split = 0;
};
ParticleGrids build_particle_grids(const ParticleState& st, const StepParams& p);

// Step 2 for every particle: writes x_new, sigma_new and st.energy, st.speed. The pairs
// and formulas are those of particle_step_repulsion.comp; only the summation order differs.
void repulsion_step(ParticleState& st, const ParticleGrids& grids, const StepParams& p,
                    std::vector<Eigen::Vector3d>& x_new, std::vector<double>& sigma_new);

// Step 3: moves each x onto f = 0 and measures normal and distance there, and the
// curvature when `with_curvature`.
void project_step(const mpu::MpuSurface& s, ParticleState& st, const StepParams& p, bool with_curvature = true);

// Pulls one point onto f = 0 by up to `steps` Newton steps (each move capped at
// `max_move` mm; it stops once a step is under 1 pm); returns false when ∇f vanishes on
// the way.
bool newton_project(const mpu::MpuSurface& s, Eigen::Vector3d& x, int steps, double max_move);

// Local thickness at x on the surface with outward normal n: the distance to the nearest
// other sheet along -n (through the inside) or +n (across a gap), searched up to max_dist;
// infinity when there is none that near. Each direction is sampled at kThicknessSteps
// even steps; the first step past the far sheet brackets the crossing, which
// kThicknessBisections bisections narrow (to 1/128 of max_dist). The CPU reference of
// shaders/particle_step_thickness.comp.
// Bisections rather than a faster-converging root finder: the targets that the thickness
// sets move with its last digits, and the population follows them, so a thickness that
// changes with the method changes how soon the particles settle.
constexpr int kThicknessSteps = 4, kThicknessBisections = 5;
double local_thickness(const mpu::MpuSurface& s, const Eigen::Vector3d& x, const Eigen::Vector3d& n, double max_dist);
// For every i: local_thickness(s, x[i], n[i], max_dist[i]) (infinity where max_dist is
// not positive and finite), in parallel.
std::vector<double> thickness_step(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& x,
                                   const std::vector<Eigen::Vector3d>& n, const std::vector<double>& max_dist);

// Steps 1-3, `iterations` times.
void particle_iterations(const mpu::MpuSurface& s, ParticleState& st, const StepParams& p, int iterations);

}  // namespace mpumesh::particles
