// What a run of the pipeline (pipeline/run_pipeline.h) measured and derived, as C++ types:
// the input's facts, the options each stage used and what the run derived for them (the
// fit's tolerance and its source, the voxel size the default count follows, the filter
// as applied), each stage's figures and time, the mesh and its quality, the particles'
// spacing against curvature, the volume mesh, and the notes for the user. The command
// line's JSON and HTML reports and the Python module are written from it; none of them
// measures anything of its own.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "geometry/tet_mesh.h"
#include "geometry/triangle_mesh.h"
#include "mesh/component_filter.h"
#include "mesh/mesh_optimize.h"
#include "mesh/quality.h"
#include "mesh/restricted_delaunay.h"
#include "mesh/slice_phase.h"
#include "mpu/fit_tolerance.h"
#include "mpu/mpu_fit.h"
#include "mpu/mpu_surface.h"
#include "particles/particle_system.h"
#include "particles/spacing_stats.h"
#include "points/slice_points.h"
#include "segment/segmentation.h"
#include "tet/tetrahedralize.h"

namespace mpumesh::pipeline {

// A volume's geometry and what its reader said.
struct VolumeInput {
  std::array<int64_t, 3> dims{0, 0, 0};
  Eigen::Vector3d spacing{0, 0, 0};
  std::string modality;
  std::vector<std::string> read_notes;
};

// A mesh's size.
struct MeshInput {
  size_t vertices = 0, triangles = 0;
  // Closed shells, each with the cavities it encloses; 0: not counted (a marching-cubes
  // surface, whose components are a scan's structures and specks: filtered as the scan's).
  int64_t parts = 0;
};

// The input: a volume or a mesh (exactly one of the two is set).
struct InputInfo {
  std::string path;
  std::optional<VolumeInput> volume;
  std::optional<MeshInput> mesh;
};

// One sampling that the triangulation found too sparse, and what came next.
struct CountRaise {
  int64_t requested_particles = 0;
  double requested_spacing_mm = 0;
  int64_t asked_particles = 0, particles = 0, repair_points = 0;
  int64_t next_requested_particles = 0;
  double next_requested_spacing_mm = 0;
};

// What the run derived from its input for its stages, beside what its caller asked
// (RunOptions): the options each stage ran with, and why.
struct Derived {
  seg::SegmentOptions segment;  // volumes: as used (a label's indicator thresholded at 0.5)
  pts::PointOptions points;     // volumes: as used
  mpu::FitOptions fit;          // as used: eps the fit's tolerance
  // Where eps came from: the rule and the figures that set it (tolerance.source), or given.
  mpu::Tolerance tolerance;
  // A label map's points: their tolerances along their normals (mpu/fit_tolerance.h).
  std::optional<mpu::LabelTolerance> label_tolerance;
  bool eps_given = false;
  // A label map's: the scale (mm, the Gaussian's sigma) at which its mesh's curvature is
  // taken (mesh/surface_attributes.h smooth_curvature); 0: the fit's at each vertex.
  double curvature_scale_mm = 0;
  particles::SampleSource sample_source;
  particles::SampleOptions sample;  // of the last sampling (after any raise)
  ComponentOptions components;      // as applied: the options' with the specks' bound
  uint64_t memory_estimate = 0;     // bytes, as checked before the long stages
};

// The components kept by the filter and those dropped (when Derived::components is active).
struct ComponentsKept {
  int64_t kept = 0;
  std::vector<DroppedComponent> dropped;
};

// The volume mesh (RunOptions::volume_mesh) and its figures.
struct VolumeMeshResult {
  TetOptions options;
  TetMesh mesh;
  TetStats stats;
};

struct RunResult {
  InputInfo input;
  Derived derived;
  seg::SegmentationSummary segmentation;  // volumes
  size_t points = 0;
  mpu::FitStats fit;
  mpu::MpuSurface surface;
  particles::SampleStats sample;
  particles::ParticleState particles;
  std::map<std::string, double> particle_kernel_ms;  // the particle kernels' device times
  std::optional<particles::SpacingSummary> spacing;  // RunOptions::spacing_figures
  std::vector<CountRaise> raises;
  RestrictedDelaunayStats triangulation;
  OptimizeStats optimization;
  TriangleMesh mesh;
  std::optional<ComponentsKept> components;  // when a filter was applied
  std::optional<Quality> quality;            // RunOptions::quality
  std::optional<SlicePhase> slice_phase;     // a label map's: |H| by the phase within its slices
  std::optional<VolumeMeshResult> volume;    // RunOptions::volume_mesh
  bool sparse = false;  // still too sparse after the last sampling
  // The reader's notes, then, when sparse, the note that says so (the last). Options are
  // named as core names them (common/option_names.h).
  std::vector<std::string> notes;
  std::vector<std::pair<std::string, TriangleMesh>> baselines;
  // Each stage's time in the order run (a stage run twice, when the count is raised,
  // appears twice).
  std::vector<std::pair<std::string, double>> stage_seconds;
};

}  // namespace mpumesh::pipeline
