// Stage 6: curvature-adaptive particles on an MPU surface (docs/method.md "Particles").
//
// Seeding: a Poisson-disk subset of candidate points (the input points, or the fit's leaf
// centres) pulled onto f = 0. Each particle's target spacing is
//     s_i = min(h λ_i, thickness_factor · t_i),
// h the spacing on flat parts, λ_i = exp(-S k_i) the curvature weight (k_i = √|K_i|
// clamped to mean ± 2 sd over the particles and scaled to 0..1; S = curvature_scale), and
// t_i the local thickness: the distance along -n to the opposite sheet of a plate, or
// along +n to the next sheet across a gap (Meyer, Kirby & Whitaker 2007 bound their
// spacing by local feature size in the same spirit): two sheets closer than the spacing
// would be bridged by the triangulation. The target radius is σ̂_i = s_i / 2.327, the σ
// at which six neighbours at distance s_i give the desired energy Ê = 0.8 μ.
//
// The backend runs `population_every` iterations at a time (particle_step_ref.h); between
// them, on the CPU for both backends, the weights, targets and population are updated:
// a particle at equilibrium (|ṗ| < γ σ) on the surface splits in two (at ±σ/2 along a
// random tangent, σ/√2 each) when σ_i > split_ratio · σ̂_i, and dies with probability
// 1 - σ_i / (0.7 σ̂_i) when σ_i < 0.7 σ̂_i; a particle that lost the surface dies. Random
// choices come from a hash of (particle index, iteration, seed), so runs repeat exactly.
// Reading back every few iterations keeps the population's order deterministic and costs
// a copy of ~100 bytes per particle.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "common/kd_tree.h"
#include "common/progress_fn.h"
#include "mpu/mpu_surface.h"
#include "particles/particle_step_ref.h"

namespace mpumesh {
class ComputeBackend;
}

namespace mpumesh::particles {

// Without --particles or --spacing, and with no voxel size to follow (a point cloud or a
// mesh): this many, unless that would make the flat spacing finer than half the input
// points' sampling gap. It is the count at which the sample CT's bone meets the quality
// targets with a margin (fewer leave its thin plates to the triangulation's repair).
constexpr int64_t kDefaultParticles = 40000;
// For a surface from a volume (SampleSource::voxel_size > 0), the default instead sets
// the spacing in the scan's terms and the count follows from it: a flat spacing h of
// kDefaultFlatVoxels in-plane voxels (about what a mean spacing of 2.5 voxels solved for
// before, on the phantoms and the sample CT), the bend bound (normal_turn) no finer than
// kMinBendVoxels voxels, which is as fine as a scan resolves a surface's shape (a bend of
// a shorter wavelength than two voxels is not in the data). On the CT-like phantoms
// (40-70 mm, 0.5-0.7 mm voxels) it gives 3,900-22,500 triangles; on the sample CT
// (0.957 mm voxels), whose bone bends more sharply than 10° per 2 voxels over a third
// of its area, 315,000.
constexpr double kDefaultFlatVoxels = 6;
constexpr double kMinBendVoxels = 2;

struct SampleOptions {
  int64_t particles = 0;        // target count; 0 = from spacing
  double spacing = 0;           // h, mm; 0 = from particles (or the default)
  double curvature_scale = 1.0; // S: spacing at the highest |K| is exp(-S) of the base spacing
  double thickness_factor = 1.0;
  // Largest turn of the normal across one spacing (radians): the base spacing is at most
  // normal_turn / κ_i, κ_i the larger principal curvature at the sampling's scale, but not
  // under the bend floor (kMinBendVoxels voxels; without a volume, the input points'
  // largest sampling gap); 0: no such bound. At 10°, a flat triangle's face normal is
  // about 1° off the surface's on average.
  double normal_turn = 10 * M_PI / 180;
  int iterations = 100;         // cap
  int min_iterations = 20;
  int population_every = 5;
  double split_ratio = 1.25;
  double death_ratio = 0.7;
  // Largest rate of change of the target spacing along the surface (spacing_gradation.h);
  // 0: ungraded.
  double spacing_grade = 0.3;
  uint32_t seed = 1;
  int64_t max_particles = 0;    // cap on the population; 0 = 1.05 x the count the targets ask for
  StepParams step;
};

// What a sampling knows of where its surface came from, beside the options its caller
// chose (the pipeline derives it from the input).
struct SampleSource {
  // The in-plane voxel (mm) of the volume the surface came from (0: none): the default
  // size follows it (kDefaultFlatVoxels, kMinBendVoxels).
  double voxel_size = 0;
  // The candidates' median distance to their 12th nearest (median_spacing with the
  // candidate index), when the caller has measured it; 0: measured here.
  double candidate_gap = 0;
  // A label map's candidates (its contour points) lie on the slices' planes: on a wall
  // steep to the slices, seeds drawn from them stand in rows a slice apart, a lattice the
  // particles' repulsion holds. Each seed starts from its candidate moved along the slice
  // axis (unit) by a random fraction of the slice spacing (mm), within half of it either
  // way, before it is pulled onto f = 0. 0: the candidates as they are.
  Eigen::Vector3d slice_axis{0, 0, 1};
  double slice_spacing = 0;
};

// The spacing s whose six neighbours give a particle of radius σ the desired energy
// Ê = 0.8 μ (12 exp(-s²/2σ²) = 0.8): a target radius σ̂ (ParticleState::target) asks for
// a spacing of σ̂ times this.
inline double spacing_per_sigma() { return std::sqrt(2 * std::log(15.0)); }

// Throws NumericalError naming the iteration and the device when a particle's position,
// σ, energy or curvature is not finite (checked after seeding and after every batch).
void check_finite(const ParticleState& st, int iteration, const std::string& device);

// Throws InputError naming the option (common/option_names.h; the iteration cap is
// `particle_iterations`, the flat spacing `particle_spacing`).
void validate(const SampleOptions& o);

struct PopulationRecord {
  int iteration = 0;
  int64_t count = 0, births = 0, deaths = 0;
  double mean_energy = 0, mean_move = 0;  // mean Δt|ṗ|/σ
};

struct SampleStats {
  int64_t candidates = 0, pool = 0, seeds = 0, particles = 0, births = 0, deaths = 0;
  int64_t asked = 0;  // the count the spacing was solved for (0: by --spacing)
  int64_t thickness_bound = 0;  // particles whose spacing the thickness bound set
  int64_t off_data = 0;         // removed for lying farther than 4 r_pool from every
                                // candidate (on a spurious sheet; particles/data_support.h)
  int iterations = 0;
  bool converged = false;
  double spacing = 0;           // h
  double area = 0;              // estimated surface area, mm²
  double kappa_lo = 0, kappa_hi = 0;  // the clamp range of √|K|, 1/mm
  double seconds_seed = 0, seconds_iterate = 0, seconds_population = 0;
  std::vector<PopulationRecord> history;
  // Per final particle: 1 where its local thickness, not its curvature, sets its spacing
  // (the smaller of the two bounds at the end; spacing_targets). On the sample CT two
  // thirds of the particles lie on plates thinner than their curvature's spacing: thin
  // plates are flat and sampled densely, so over all particles the spacing rises with |K|
  // (rank correlation +0.30), while over the others it falls (-0.74).
  std::vector<uint8_t> spacing_by_thickness;
  // Per final particle: the Gaussian curvature at the sampling's scale (sizing_field.h)
  // where it lies, the curvature its spacing follows.
  std::vector<double> gauss_at_scale;
};

// The step parameters for the next batch: within a batch σ may grow to twice its target
// (a particle past split_ratio splits at the next update anyway) or stay at its current
// value if larger; that cap bounds the interaction range for the batch.
StepParams batch_params(const StepParams& step, const ParticleState& st);

// The iterations run on `backend` (ComputeBackend::particle_iterations), in batches of
// batch_params. `candidate_index`: a PointIndex's tree over the candidates, when the
// caller has one (else one is built). `progress` is told the iterations done over their
// cap after each batch, and 1 at the end.
ParticleState sample_surface(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& candidates,
                             const SampleOptions& opt, ComputeBackend& backend, SampleStats* stats = nullptr,
                             const KdTree* candidate_index = nullptr, const SampleSource& source = {},
                             const ProgressFn& progress = {});

// Candidate seeds when no input points are at hand: the centres of the leaves that held
// points.
std::vector<Eigen::Vector3d> leaf_candidates(const mpu::MpuSurface& s);

// The population step's decision for each particle (see above), given the population cap.
enum Fate : uint8_t { kKeep = 0, kSplit = 1, kDie = 2 };
std::vector<uint8_t> decide_population(const ParticleState& st, const SampleOptions& opt, int iteration, int64_t cap);

// The hash behind every random choice: uniform in [0, 1).
double hash01(uint32_t index, uint32_t iteration, uint32_t seed, uint32_t salt);

}  // namespace mpumesh::particles
