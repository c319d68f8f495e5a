#include "pipeline/run_pipeline.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>
#include <tuple>
#include <type_traits>

#include "common/error.h"
#include "common/option_names.h"
#include "common/memory.h"
#include "common/text.h"
#include "io/mesh_io.h"
#include "io/volume_io.h"
#include "multi/complex_tetrahedralize.h"
#include "common/kd_tree.h"
#include "mc/marching_cubes.h"
#include "mesh/slice_phase.h"
#include "mesh/surface_attributes.h"
#include "mesh/topology.h"
#include "mesh/voxel_grid.h"
#include "mpu/polygonize.h"
#include "points/mesh_points.h"
#include "segment/label_map.h"

namespace mpumesh::pipeline {
namespace {

// A stage between the observer's begin and end.
template <class F>
auto stage(Observer& obs, const std::string& name, F&& work) {
  obs.begin(name);
  if constexpr (std::is_void_v<decltype(work())>) {
    work();
    obs.end();
  } else {
    auto out = work();
    obs.end();
    return out;
  }
}

// The state the stages share: the caller's options as given, and the result, whose
// `derived` the stages fill in with what follows from the input.
struct Run {
  const std::string& input;
  const RunOptions& opt;
  const BackendOpener& open;
  Observer& obs;
  RunResult& r;
  ComputeBackend* backend = nullptr;
  int64_t voxels = 0;
  // > 0: no eps was given and the points come from a scan or a voxel-grid mesh, whose
  // finest spacing this is; the fit's tolerance then follows the points (set_tolerance).
  double tolerance_pixel = 0;
  std::optional<Eigen::Vector3d> tolerance_grid{};  // the voxel grid a mesh's vertices lie on
  // A label map's grid, when the tolerance follows the scan: each point's tolerance then
  // follows it (mpu::set_label_map_tolerance).
  std::optional<mpu::LabelGrid> label_grid{};
  // A label map's slices (a plane through a slice's centres, its normal, the spacing), for
  // the result's slice-phase modulation.
  std::optional<std::tuple<Eigen::Vector3d, Eigen::Vector3d, double>> label_slices{};
};

// Too sparse a sample for the surface's thin plates shows as many repair points, and its
// triangles next to them are poor: on the sample CT at full resolution, 36% repair points
// at 40,000 particles with a smallest angle of 10.6°, 3% and 20.2° at 1.5 times the count.
bool too_sparse(const RestrictedDelaunayStats& t, size_t particles) {
  return particles > 0 && t.repair_points > int64_t(particles) / 10;
}

// The next sampling: kRaise times the particles (by spacing, its square root finer).
particles::SampleOptions denser(particles::SampleOptions x, int64_t asked) {
  if (x.spacing > 0)
    x.spacing /= std::sqrt(kRaise);
  else
    x.particles =
        int64_t(std::ceil(double(asked > 0 ? asked : particles::kDefaultParticles) * kRaise / 1000)) * 1000;
  return x;
}

// A closed manifold mesh to its points (the vertices, with area-weighted normals, and the
// triangles' centroids unless it is a marching-cubes surface).
PointCloud points_from_mesh(Run& run, const TriangleMesh& in) {
  require_closed_manifold(in, run.input, "the input mesh", "remeshing needs a closed surface");
  // A marching-cubes surface of a scan (its vertices on a voxel grid's edges) is fitted
  // and sampled as the scan would be: the tolerance and the default count follow the
  // grid's finest spacing (mesh/voxel_grid.h). Its vertices alone are the data: the
  // centroids of its triangles lie on the staircase's facets, within the voxel the
  // tolerance allows, and would triple the points, nearly double the leaves and make a
  // rougher mesh. Any other mesh is exact data, its faces sampled too.
  const auto grid = voxel_grid_spacing(in);
  PointCloud cloud = stage(run.obs, "points", [&] { return pts::mesh_points(in, !grid); });
  if (cloud.size() == 0) throw InputError(run.input + ": the mesh has no triangle with an area");
  // A marching-cubes surface's parts are not counted: its shells are kept as a scan's
  // would be, and counting them (each cavity's enclosing shell by ray crossings) takes
  // 0.37 s on the sample CT's 678,480 triangles.
  run.r.input.mesh = MeshInput{in.vertices.size(), in.triangles.size(), grid ? 0 : count_parts(in)};
  if (grid) {
    const double voxel = grid->minCoeff();
    run.r.derived.sample_source.voxel_size = voxel;
    if (!(run.opt.fit.eps > 0)) {
      run.tolerance_pixel = voxel;
      run.tolerance_grid = *grid;
    }
  }
  if (run.opt.baselines) run.r.baselines.push_back({"input mesh", in});
  run.backend = &run.open();
  return cloud;
}

// A label's indicator is segmented at 0.5, and its caps stop short of other labels
// (seg/label_map.h).
void use_label(Derived& d) {
  d.segment.method = seg::Method::kThreshold;
  d.segment.threshold = mc::ThresholdRange{0.5};
  d.points.caps_to_field_crossing = true;
  d.points.partial_volume_caps = false;  // a label map has no partial volume
  d.points.curved_caps = true;
}

// A volume to its slice points; the fit's tolerance and the default count follow the scan.
PointCloud points_from_volume(Run& run, const Volume& scan) {
  run.backend = &run.open();
  std::optional<Volume> indicator;
  if (run.opt.label > 0) indicator = stage(run.obs, "label", [&] { return seg::label_indicator(scan, run.opt.label, run.opt.label_shares_faces ? 0.0f : -1.0f);
  });
  const Volume& vol = indicator ? *indicator : scan;
  const Derived& d = run.r.derived;
  const seg::Segmentation s = stage(run.obs, "segment", [&] { return seg::segment(vol, d.segment, *run.backend); });
  pts::SlicePoints p = stage(run.obs, "points", [&] { return pts::extract_points(s, vol, d.points); });
  if (p.cloud.size() == 0)
    throw InputError(run.input + (run.opt.label > 0 ? ": the label holds no surface"
                                                    : ": the segmentation holds no surface (nothing inside the "
                                                      "threshold range?)"));
  run.r.derived.sample_source.voxel_size = vol.in_plane_spacing();  // the default count follows it
  // No eps given: the tolerance follows the scan (set_tolerance).
  if (!(run.opt.fit.eps > 0)) run.tolerance_pixel = vol.in_plane_spacing();
  const Eigen::Vector3d slice_axis = vol.direction.col(2).normalized();
  if (run.opt.label > 0) {
    run.label_slices = {vol.origin, slice_axis, vol.spacing.z()};
    run.r.derived.sample_source.slice_axis = slice_axis;
    run.r.derived.sample_source.slice_spacing = vol.spacing.z();
    run.r.derived.fit.min_radius_floor = mpu::kLabelMinRadiusSlices * vol.spacing.z();
  }
  if (run.tolerance_pixel > 0 && run.opt.label > 0) {
    run.label_grid = mpu::LabelGrid{slice_axis, vol.in_plane_spacing(), vol.spacing.z()};
    // The complex's label runs give it their fits and vertices only (pipeline/complex_run.h):
    // their meshes' curvature is never written.
    if (!run.opt.label_shares_faces) run.r.derived.curvature_scale_mm = run.r.derived.fit.min_radius_floor;
  }
  run.voxels = vol.voxel_count();
  run.r.input.volume = VolumeInput{vol.dims, vol.spacing, vol.modality, vol.read_notes};
  run.r.segmentation = seg::summarize(s);
  if (run.opt.baselines)
    run.r.baselines.push_back({"marching cubes", stage(run.obs, "marching cubes (report)", [&] {
                                 return marching_cubes(vol, d.segment.threshold, *run.backend);
                               })});
  return std::move(p.cloud);
}

// The fit's tolerance from the points' scatter (mpu/fit_tolerance.h), for the points of a
// scan or a voxel-grid mesh when no eps was given.
void set_tolerance(Run& run, PointCloud& cloud, const KdTree& index) {
  mpu::Tolerance& t = run.r.derived.tolerance;
  t = mpu::volume_tolerance(cloud, run.tolerance_pixel, &index);
  if (const auto& grid = run.tolerance_grid) {
    const std::string on_grid = fmt::format("the {:.3f} x {:.3f} x {:.3f} mm voxel grid the input's vertices lie on",
                                            grid->x(), grid->y(), grid->z());
    t.source = 3 * t.noise > t.pixel
                   ? fmt::format("3 x the vertices' scatter ({:.3f} mm), above the finest spacing of {}", t.noise, on_grid)
                   : fmt::format("the finest spacing of {}; the vertices' scatter is {:.3f} mm", on_grid, t.noise);
  }
  run.r.derived.fit.eps = t.eps;
  if (run.label_grid) {
    run.r.derived.label_tolerance = mpu::set_label_map_tolerance(cloud, index, *run.label_grid, t.eps);
    t.source += fmt::format("; label map: each point's tolerance {} grid steps along its normal (median {:.2f} x "
                            "this), less across plates and gaps thinner than that",
                            mpu::kLabelSteps, run.r.derived.label_tolerance->median_factor);
    if (const double scale = run.r.derived.curvature_scale_mm; scale > 0)
      t.source += fmt::format("; the mesh's curvature taken at the scale of the smallest ball ({:.2f} mm)", scale);
  }
}

// Particles and their restricted Delaunay triangulation, sampled again with kRaise times
// the particles while the triangulation shows the sample too sparse and retries are left
// (the first sample keeps the default count's own rules, see sample_surface).
void sample_and_triangulate(Run& run, const PointCloud& cloud, const KdTree& index) {
  RunResult& r = run.r;
  const particles::SampleOptions& asked = run.opt.sample;
  const bool count_given = asked.particles > 0 || asked.spacing > 0;
  int retries = run.opt.count_retries >= 0 ? run.opt.count_retries : count_given ? 0 : 2;
  particles::SampleOptions so = asked;
  particles::SampleSource& source = r.derived.sample_source;
  // The fit measured the points' gap over the same points and tree, unless it dropped
  // duplicates.
  if (r.fit.duplicates_removed == 0) source.candidate_gap = r.fit.gap12;
  for (;;) {
    run.obs.begin("particles");
    r.particles = particles::sample_surface(r.surface, cloud.positions, so, *run.backend, &r.sample, &index, source,
                                            run.obs.progress_of("particles"));
    // The particle kernels' device times, before a later stage's kernels replace them.
    r.particle_kernel_ms = run.backend->kernel_ms();
    run.obs.end();
    run.obs.begin("triangulate");
    r.triangulation = RestrictedDelaunayStats{};
    r.mesh = restricted_delaunay(r.surface, r.particles.x, &r.triangulation, 0, run.backend,
                                 run.obs.progress_of("triangulate"));
    run.obs.end();
    if (!too_sparse(r.triangulation, r.particles.size()) || retries == 0) break;
    --retries;
    const particles::SampleOptions next = denser(so, r.sample.asked);
    r.raises.push_back({so.particles, so.spacing, r.sample.asked, int64_t(r.particles.size()),
                        r.triangulation.repair_points, next.particles, next.spacing});
    run.obs.note(fmt::format("note: {} repair points for {} particles, too sparse a sample: sampling again with {}",
                             r.triangulation.repair_points, r.particles.size(),
                             next.spacing > 0 ? fmt::format("spacing {:.3f} mm", next.spacing)
                                              : fmt::format("{} particles", next.particles)));
    so = next;
    // (By spacing, the count grows by the same factor.)
    r.derived.memory_estimate = estimate_run_bytes(run.voxels, int64_t(cloud.size()),
                                                   so.particles > 0 ? so.particles
                                                                    : int64_t(double(r.particles.size()) * kRaise),
                                                   run.opt.volume_mesh.has_value());
    check_memory(run.input, r.derived.memory_estimate);
    r.mesh = TriangleMesh{};
    r.particles = particles::ParticleState{};
  }
  r.derived.sample = so;
  r.sparse = too_sparse(r.triangulation, r.particles.size());
}

// Each vertex's target spacing: that of the particle nearest to it (a repair point's is
// its neighbourhood's).
std::vector<double> vertex_spacing(const TriangleMesh& mesh, const particles::ParticleState& p) {
  const PointIndex index(p.x);
  const KdTree& tree = index.tree;
  std::vector<double> s(mesh.vertices.size());
  tbb::parallel_for(size_t(0), s.size(), [&](size_t v) {
    uint32_t i = 0;
    double d2 = 0;
    nanoflann::KNNResultSet<double, uint32_t> rs(1);
    rs.init(&i, &d2);
    tree.findNeighbors(rs, mesh.vertices[v].data(), nanoflann::SearchParams());
    s[v] = p.target[i] * particles::spacing_per_sigma();
  });
  return s;
}

// The mesh optimisation (mesh/mesh_optimize.h), on the backend.
void optimize(Run& run) {
  RunResult& r = run.r;
  if (run.opt.optimize.rounds <= 0 || r.particles.size() == 0) return;
  run.obs.begin("optimize");
  r.optimization = optimize_mesh(r.mesh, r.surface, *run.backend, vertex_spacing(r.mesh, r.particles), run.opt.optimize,
                                 run.obs.progress_of("optimize"));
  run.obs.end();
}

// The mesh must be a closed oriented manifold with finite vertices and normals; it gets
// the surface's normals and curvatures (a label map's at the scale of its grid).
void attach_and_check(Run& run) {
  TriangleMesh& mesh = run.r.mesh;
  const Topology topo = analyze_topology(mesh);
  if (!topo.closed || !topo.oriented)
    throw InputError(fmt::format("{}: the triangulation is not a closed oriented manifold ({} border edges, {} "
                                 "non-manifold edges, {} non-manifold vertices); nothing written",
                                 run.input, topo.border_edges, topo.nonmanifold_edges, topo.nonmanifold_vertices));
  stage(run.obs, "curvature", [&] {
    attach_surface_attributes(mesh, run.r.surface, *run.backend);
    if (run.r.derived.curvature_scale_mm > 0) smooth_curvature(mesh, run.r.derived.curvature_scale_mm);
  });
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    if (!mesh.vertices[i].allFinite() || !mesh.normals[i].allFinite())
      throw NumericalError(run.input + ": vertex " + std::to_string(i) +
                           " of the triangulation or its normal is not finite; nothing written");
}

// The components the filter keeps (mesh/component_filter.h); none left is an error.
void keep_components(Run& run) {
  RunResult& r = run.r;
  const ComponentOptions& filter = r.derived.components;
  FilteredMesh f = stage(run.obs, "keep components", [&] { return filter_components(r.mesh, filter); });
  if (f.mesh.triangles.empty() && std::all_of(f.dropped.begin(), f.dropped.end(), [](const auto& d) { return d.thin; }))
    throw InputError(run.input + ": the surface encloses nothing (a sheet folded onto itself, or specks under the "
                                 "fit's tolerance); nothing written");
  if (f.mesh.triangles.empty() && filter.min_volume_mm3 > run.opt.components.min_volume_mm3)
    throw InputError(fmt::format("{}: every structure is a speck, enclosing less than {:.3g} mm3 ({:g} voxels), below "
                                 "what the scan resolves ({} keeps them); nothing written",
                                 run.input, filter.min_volume_mm3, run.opt.speck_voxels, option_ref("keep_specks")));
  require_kept(f, filter, run.input);
  r.mesh = std::move(f.mesh);
  r.components = ComponentsKept{f.kept, std::move(f.dropped)};
}

// The note a still too sparse sample gets, with the count that should do better.
std::string sparse_note(const RunResult& r) {
  const particles::SampleOptions more = denser(r.derived.sample, r.sample.asked);
  const std::string option = more.spacing > 0 ? fmt::format("{} {:.2f}", option_ref("particle_spacing"), more.spacing)
                                              : fmt::format("{} {}", option_ref("particles"), more.particles);
  return fmt::format(
      "the triangulation added {} repair points to {} particles ({:.0f}%): the particles are too sparse for this "
      "surface's thin plates, and the triangles next to repair points are poor; {} times as many particles ({}) "
      "should do better",
      r.triangulation.repair_points, r.particles.size(),
      100.0 * double(r.triangulation.repair_points) / double(r.particles.size()), kRaise, option);
}

int64_t asked_particles(const RunOptions& options) {
  return options.sample.particles > 0 ? options.sample.particles : particles::kDefaultParticles;
}

// The caller's observer, with each stage's time kept for the result.
class TimedObserver : public Observer {
 public:
  explicit TimedObserver(Observer* inner) : inner_(inner ? *inner : quiet_) {}
  void begin(const std::string& stage) override {
    stage_ = stage;
    t0_ = std::chrono::steady_clock::now();
    inner_.begin(stage);
  }
  void end() override {
    times_.emplace_back(stage_, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count());
    inner_.end();
  }
  void note(const std::string& line) override { inner_.note(line); }
  void progress(const std::string& stage, double fraction) override { inner_.progress(stage, fraction); }
  std::vector<std::pair<std::string, double>> take_times() { return std::move(times_); }

 private:
  Observer quiet_;
  Observer& inner_;
  std::string stage_;
  std::chrono::steady_clock::time_point t0_;
  std::vector<std::pair<std::string, double>> times_;
};

// What the run derives before its stages: the options each stage starts from, and where
// the fit's tolerance comes from when no stage measures it.
void start_derived(Derived& d, const RunOptions& options) {
  d.segment = options.segment;
  d.points = options.points;
  if (options.label > 0) use_label(d);
  d.fit = options.fit;
  d.eps_given = options.fit.eps > 0;
  if (d.eps_given) {
    d.tolerance.eps = options.fit.eps;
    d.tolerance.source = option_ref("eps");
  } else {
    d.tolerance.source = "a quarter of the points' median spacing";
  }
}

// A closed shell thinner on average (2 × volume / area) than this fraction of the fit's
// tolerance ε0 is no structure the fit resolves: a sheet of the fit folded onto itself
// (its two sides a few hundredths of a millimetre apart, enclosing nothing) or a speck
// under the tolerance (a ball of radius 3/8 ε0, a tetrahedron of four triangles with
// 1.8 ε0 edges). On the sample CT these are 1-7 tetrahedra of 0.05-0.8 mm³ per run.
constexpr double kSheetThickness = 0.25;

// The components filter as applied: from a volume, with the specks' bound; from a mesh
// whose parts are counted, at most as many shells as it has (unless a number is asked):
// a remeshed surface has its input's parts, and a shell more is one the fit made away
// from the data; from any input, without the shells thinner than the fit resolves
// (`eps`: the fit's tolerance, mm).
ComponentOptions applied_filter(const RunOptions& options, const Volume* scan, const std::optional<MeshInput>& mesh,
                                double eps) {
  ComponentOptions f = options.components;
  if (mesh && f.largest == 0) f.largest = mesh->parts;  // 0 (not counted): all
  if (scan && options.speck_voxels > 0)
    f.min_volume_mm3 = std::max(f.min_volume_mm3, options.speck_voxels * scan->spacing.prod());
  f.min_thickness_mm = kSheetThickness * eps;
  return f;
}

// The stages after the mesh is made: quality, the volume mesh, the notes, the baselines.
void measure_and_fill(Run& run) {
  RunResult& r = run.r;
  const RunOptions& options = run.opt;
  if (options.quality) r.quality = stage(run.obs, "quality", [&] { return measure_quality(r.mesh, *options.quality); });
  if (options.spacing_figures) r.spacing = particles::spacing_summary(r.sample, r.particles);
  if (const auto& sl = run.label_slices)
    r.slice_phase = stage(run.obs, "slice phase", [&] {
      return slice_phase(r.mesh, std::get<0>(*sl), std::get<1>(*sl), std::get<2>(*sl));
    });
  if (options.volume_mesh) {
    VolumeMeshResult v;
    v.options = *options.volume_mesh;
    v.mesh = stage(run.obs, "volume mesh", [&] {
      try {
        return multi::tetrahedralize_surface(r.mesh, v.options, &v.stats, run.obs.progress_of("volume mesh"));
      } catch (const InputError& e) {
        throw volume_mesh_error(run.input, e);
      }
    });
    r.volume = std::move(v);
  }
  if (r.input.volume) r.notes = r.input.volume->read_notes;
  if (r.sparse) r.notes.push_back(sparse_note(r));  // the last note
  if (options.baselines)
    r.baselines.push_back({"original MPU", stage(run.obs, "original MPU (report)", [&] {
                             return mpu::polygonize(r.surface, 0, *run.backend);
                           })});
}

// Every stage after reading, on a volume (`scan`) or a mesh; `input` names it in messages.
RunResult run_stages(const std::string& input, const Volume* scan, const TriangleMesh* mesh,
                     const RunOptions& options, const BackendOpener& open_backend, Observer& obs) {
  RunResult r;
  Run run{input, options, open_backend, obs, r};
  start_derived(r.derived, options);
  r.input.path = scan ? scan->source : input;  // the file, without the label
  PointCloud cloud = scan ? points_from_volume(run, *scan) : points_from_mesh(run, *mesh);
  r.points = cloud.size();
  // One k-d tree over the points for the noise estimate, the fit and the sampling's pool.
  const PointIndex index(cloud.positions);
  if (run.tolerance_pixel > 0) set_tolerance(run, cloud, index.tree);
  // By default from a volume the count follows the surface (particles/particle_system.h);
  // one particle a point is the estimate.
  const bool count_follows = scan && options.sample.particles == 0 && options.sample.spacing == 0;
  const int64_t asked =
      count_follows ? std::max(particles::kDefaultParticles, int64_t(cloud.size())) : asked_particles(options);
  r.derived.memory_estimate =
      estimate_run_bytes(run.voxels, int64_t(cloud.size()), asked, options.volume_mesh.has_value());
  check_memory(input, r.derived.memory_estimate);
  r.surface = stage(run.obs, "fit", [&] { return mpu::fit_mpu(cloud, r.derived.fit, &r.fit, &index.tree); });
  if (options.fit_only) return r;
  sample_and_triangulate(run, cloud, index.tree);
  r.derived.components = applied_filter(options, scan, r.input.mesh, r.fit.eps);
  if (r.derived.components.active()) keep_components(run);  // before the optimisation, which then has less to do
  optimize(run);
  attach_and_check(run);
  measure_and_fill(run);
  return r;
}

// A label's runs name it beside the volume in their messages.
std::string input_name(const Volume& scan, const RunOptions& options) {
  return options.label > 0 ? seg::label_name(scan.source, options.label) : scan.source;
}

}  // namespace

bool is_mesh_path(const std::string& path) {
  const std::string ext = lower_case(std::filesystem::path(path).extension().string());
  return ext == ".stl" || ext == ".ply" || ext == ".obj" || ext == ".off";
}

RunResult run_pipeline(const std::string& input, const RunOptions& options, const BackendOpener& open_backend,
                       Observer* observer) {
  TimedObserver obs(observer);
  // Memory: the particles alone first, then with the volume and the points, before the
  // fit, the particles and the triangulation start.
  check_memory("run", estimate_run_bytes(0, 0, asked_particles(options)));
  RunResult r;
  if (is_mesh_path(input)) {
    const TriangleMesh mesh = stage(obs, "read mesh", [&] { return read_mesh(input); });
    r = run_stages(input, nullptr, &mesh, options, open_backend, obs);
  } else {
    const Volume scan = stage(obs, "read volume", [&] { return read_volume(input); });
    r = run_stages(input_name(scan, options), &scan, nullptr, options, open_backend, obs);
  }
  r.stage_seconds = obs.take_times();
  return r;
}

RunResult run_pipeline(const Volume& volume, const RunOptions& options, const BackendOpener& open_backend,
                       Observer* observer) {
  TimedObserver obs(observer);
  check_memory("run", estimate_run_bytes(0, 0, asked_particles(options)));
  RunResult r = run_stages(input_name(volume, options), &volume, nullptr, options, open_backend, obs);
  r.stage_seconds = obs.take_times();
  return r;
}

RunResult run_pipeline(const TriangleMesh& mesh, const std::string& name, const RunOptions& options,
                       const BackendOpener& open_backend, Observer* observer) {
  TimedObserver obs(observer);
  check_memory("run", estimate_run_bytes(0, 0, asked_particles(options)));
  RunResult r = run_stages(name, nullptr, &mesh, options, open_backend, obs);
  r.stage_seconds = obs.take_times();
  return r;
}

}  // namespace mpumesh::pipeline
