// The whole job, as `mpumesh run` does it and as the benchmark and the tests time it: a
// CT/MR volume (or a closed surface mesh, to remesh it) to a closed, oriented, adaptive
// mesh on the fitted MPU surface. Its stages, in order:
//   read -> segment (volumes) -> points -> fit -> sample and triangulate (sampling again
//   with more particles while the triangulation shows the sample too sparse) -> the
//   components kept (largest, min_volume; from a volume, specks under a tenth of a voxel
//   dropped) -> optimise the mesh -> surface attributes -> checks -> quality (optional)
//   -> the volume mesh (optional) -> the report's baselines (optional).
// The caller's choices are RunOptions; what the run derives from its input (the fit's
// tolerance, the voxel size the default count follows, the filter as applied) and what it
// measures come back in RunResult (pipeline/run_result.h), the typed summary that the
// command line's JSON and HTML reports and the Python module are written from. Writing
// the outputs is the caller's.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "common/progress_fn.h"
#include "compute/compute_backend.h"
#include "mesh/component_filter.h"
#include "mesh/mesh_optimize.h"
#include "mesh/quality.h"
#include "mpu/mpu_fit.h"
#include "particles/particle_system.h"
#include "pipeline/run_result.h"
#include "points/slice_points.h"
#include "segment/segmentation.h"
#include "tet/tetrahedralize.h"

namespace mpumesh::pipeline {

// What the stages say while they run: a stage's start and end (by name), how far a long
// stage is (its fraction done, 0 to 1: "particles", "triangulate", "optimize",
// "volume mesh"; and "labels" or "parts", the loop over a label map's labels or a mesh's
// parts, around the stages of each), and lines a user should see. Every method does
// nothing unless overridden.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void begin(const std::string& /*stage*/) {}
  virtual void end() {}
  virtual void progress(const std::string& /*stage*/, double /*fraction*/) {}
  virtual void note(const std::string& /*line*/) {}
  // A ProgressFn (common/progress_fn.h) that tells this observer about `stage`.
  ProgressFn progress_of(std::string stage) {
    return [this, stage = std::move(stage)](double f) { progress(stage, f); };
  }
};

// What the caller chooses; everything else the run derives (RunResult::derived).
struct RunOptions {
  seg::SegmentOptions segment;  // volumes only
  pts::PointOptions points;     // volumes only
  // Above 0: the volume is a label map and this label is meshed (seg/label_map.h); the
  // segmentation is its indicator's threshold at 0.5, whatever `segment` says.
  int64_t label = 0;
  // With `label`: the other labels count as background, so that the fit passes through
  // the faces the label shares with them (seg::label_indicator); the complex's label runs
  // set it (pipeline/complex_run.h).
  bool label_shares_faces = false;
  mpu::FitOptions fit;  // eps 0: from the scan (mpu/fit_tolerance.h), or from the points
  // particles and spacing 0: the default count, which follows the volume's voxel size.
  particles::SampleOptions sample;
  // Samples again with kRaise times the particles while the triangulation needs repair
  // points for more than a tenth of them, up to this many times; -1: 2 when neither a
  // count nor a spacing is given, else 0.
  int count_retries = -1;
  OptimizeOptions optimize;  // the mesh optimisation after the triangulation (rounds 0: none)
  ComponentOptions components;  // the structures to keep (largest, min_volume)
  // From a volume, the closed structures enclosing less than this many voxels are dropped
  // too (0: kept): a speck that small is below what the scan resolves (a sliver of one
  // voxel's partial volume), and the particles mesh it with four vertices, whose flat
  // tetrahedron has triangles and a volume mesh of poor shape.
  double speck_voxels = 0.1;
  // Measure the mesh's quality (RunResult::quality) with these options; none: not measured.
  std::optional<QualityOptions> quality = QualityOptions{};
  // Measure how the particles' spacing follows |K| (RunResult::spacing).
  bool spacing_figures = false;
  // Fill the final mesh with tetrahedra (tet/tetrahedralize.h) as the last stage.
  std::optional<TetOptions> volume_mesh;
  // Keep the report's baselines: marching cubes of the volume (or the input mesh) and the
  // original MPU mesh (the surface polygonized).
  bool baselines = false;
  // Stop after the fit (RunResult::surface and the fit's figures; no mesh): the complex
  // needs the labels' union for its function only (pipeline/complex_run.h).
  bool fit_only = false;
};

// The factor on the particle count when sampling again (the spacing is divided by its
// square root; a count is rounded up to a thousand particles).
inline constexpr double kRaise = 1.5;

// Opens the compute backend when the pipeline first needs it (after reading, so that a bad
// input fails first); the backend outlives the call.
using BackendOpener = std::function<ComputeBackend&()>;

// Throws InputError for bad input (a path that reads as neither, an open or non-manifold
// input mesh, no surface in the segmentation, a triangulation that is not a closed
// oriented manifold) and NumericalError for a non-finite vertex.
RunResult run_pipeline(const std::string& input, const RunOptions& options, const BackendOpener& open_backend,
                       Observer* observer = nullptr);
// The same on a volume already read (its source names it in messages), so that one
// reading serves many runs, one per label of a label map.
RunResult run_pipeline(const Volume& volume, const RunOptions& options, const BackendOpener& open_backend,
                       Observer* observer = nullptr);
// The same on a closed surface mesh already read, to remesh it; `name` names it in messages.
RunResult run_pipeline(const TriangleMesh& mesh, const std::string& name, const RunOptions& options,
                       const BackendOpener& open_backend, Observer* observer = nullptr);

// Whether `path` names a surface mesh (.stl, .ply, .obj, .off) rather than a volume.
bool is_mesh_path(const std::string& path);

}  // namespace mpumesh::pipeline
