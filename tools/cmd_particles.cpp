// mpumesh sample: curvature-adaptive particles on an MPU surface.
// mpumesh triangulate: the restricted Delaunay mesh of particles on a surface.
// mpumesh run: the whole job, a CT/MR volume (or a surface mesh, to remesh it) to a mesh:
// segment, points, fit, particles, triangulation, quality report.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "cli_util.h"
#include "commands.h"
#include "common/error.h"
#include "common/memory.h"
#include "compute/cpu_backend.h"
#include "io/atomic_file.h"
#include "io/mesh_io.h"
#include "io/point_io.h"
#include "mesh/quality.h"
#include "mesh/restricted_delaunay.h"
#include "mesh/surface_attributes.h"
#include "mc/marching_cubes.h"
#include "mpu/polygonize.h"
#include "common/text.h"
#include "io/read_file.h"
#include "report_builder.h"
#include "mpu/mpu_fit.h"
#include "mpu/fit_tolerance.h"
#include "mpu/mpu_io.h"
#include "mpu_cli.h"
#include "particles/particle_system.h"
#include "particles/spacing_stats.h"
#include "points/mesh_points.h"
#include "points/slice_points.h"
#include "seg_cli.h"

namespace mpumesh::tools {
namespace {

// `iterations_flag`: "--iterations" for sample, "--particle-iterations" for run (where
// --iterations is Chan-Vese's).
void add_sample_options(CLI::App* cmd, particles::SampleOptions& o, const std::string& iterations_flag) {
  cmd->add_option("--particles", o.particles, "about this many particles (0: from --spacing; both 0: 40000)")
      ->capture_default_str();
  cmd->add_option("--spacing", o.spacing, "particle spacing on flat parts (mm); overrides --particles")
      ->capture_default_str();
  cmd->add_option("--curvature-scale", o.curvature_scale,
                  "how strongly curvature drives density: spacing at the highest |K| is exp(-S) of the flat one")
      ->capture_default_str();
  cmd->add_option("--thickness-factor", o.thickness_factor,
                  "spacing at most this times the local thickness of plates and gaps")
      ->capture_default_str();
  cmd->add_option("--spacing-grade", o.spacing_grade,
                  "largest change of the target spacing per mm along the surface (0: ungraded)")
      ->capture_default_str();
  cmd->add_option(iterations_flag, o.iterations, "particle iteration cap")->capture_default_str();
  cmd->add_option("--seed", o.seed, "seed of the random choices (splits, deaths, seeding order)")->capture_default_str();
}

nlohmann::json sample_json(const particles::SampleOptions& o, const particles::SampleStats& st,
                           const particles::ParticleState& ps) {
  std::vector<double> absk(ps.size());
  for (size_t i = 0; i < ps.size(); ++i) absk[i] = std::abs(ps.curv[i].gauss);
  const std::vector<double> spacing = particles::local_spacing(ps.x);
  const particles::SpacingStats sp = particles::spacing_stats(spacing, absk);
  // The same over the particles whose spacing their curvature sets (not a plate's
  // thickness): the relation the curvature weight is for.
  std::vector<double> curved_spacing, curved_absk;
  for (size_t i = 0; i < ps.size(); ++i)
    if (i < st.spacing_by_thickness.size() && !st.spacing_by_thickness[i])
      curved_spacing.push_back(spacing[i]), curved_absk.push_back(absk[i]);
  const particles::SpacingStats sc = particles::spacing_stats(curved_spacing, curved_absk);
  auto spacing_json = [](const particles::SpacingStats& x) {
    return nlohmann::json{{"mean_mm", x.mean},
                          {"cv", x.cv},
                          {"median_high_K_mm", x.high_k_median},
                          {"median_low_K_mm", x.low_k_median},
                          {"high_over_low", x.ratio},
                          {"rank_correlation_with_abs_K", x.rank_correlation}};
  };
  nlohmann::json curved = spacing_json(sc);
  curved["particles"] = curved_spacing.size();
  nlohmann::json hist = nlohmann::json::array();
  for (const auto& h : st.history)
    hist.push_back({{"iteration", h.iteration}, {"count", h.count}, {"births", h.births}, {"deaths", h.deaths},
                    {"mean_energy", h.mean_energy}, {"mean_move", h.mean_move}});
  return {{"particles", st.particles},
          {"requested_particles", o.particles},
          {"requested_spacing_mm", o.spacing},
          {"asked_particles", st.asked},  // what the spacing was solved for (the default's rule applied)
          {"seeds", st.seeds},
          {"pool", st.pool},
          {"candidates", st.candidates},
          {"births", st.births},
          {"deaths", st.deaths},
          {"iterations", st.iterations},
          {"converged", st.converged},
          {"flat_spacing_mm", st.spacing},
          {"area_mm2", st.area},
          {"thickness_bound", st.thickness_bound},
          {"off_data_removed", st.off_data},
          {"curvature_scale", o.curvature_scale},
          {"spacing_grade", o.spacing_grade},
          {"sqrt_abs_K_clamp", {st.kappa_lo, st.kappa_hi}},
          {"spacing", spacing_json(sp)},
          {"spacing_where_curvature_sets", curved},
          {"seconds", {{"seed", st.seconds_seed}, {"iterate", st.seconds_iterate}, {"population", st.seconds_population}}},
          {"history", hist}};
}

PointCloud particle_cloud(const particles::ParticleState& ps) {
  PointCloud c;
  c.positions = ps.x;
  c.normals = ps.normal;
  return c;
}

nlohmann::json triangulation_json(const RestrictedDelaunayStats& st) {
  return {{"particles", st.particles},
          {"repair_points", st.repair_points},
          {"repair_rounds", st.repair_rounds},
          {"repair_crossings_merged", st.repair_merged},
          {"wide_facets_refined", st.wide_facets},
          {"unused_particles", st.unused_points},
          {"sheet_points", st.sheet_points},
          {"spurious_components_removed", st.spurious_components},
          {"spurious_triangles_removed", st.spurious_triangles},
          {"components_flipped", st.flipped_components},
          {"edge_flips", st.edge_flips},
          {"edge_collapses", st.edge_collapses},
          {"vertices_relaxed", st.vertices_relaxed},
          {"cleanup_retries", st.cleanup_retries},
          {"seconds", st.seconds},
          {"seconds_by_step",
           {{"delaunay", st.seconds_delaunay},
            {"evaluate", st.seconds_evaluate},
            {"repair", st.seconds_repair},
            {"mesh", st.seconds_mesh},
            {"cleanup", st.seconds_cleanup}}}};
}

bool is_mesh_path(const std::string& path) {
  const std::string ext = lower_case(std::filesystem::path(path).extension().string());
  return ext == ".stl" || ext == ".ply" || ext == ".obj" || ext == ".off";
}

}  // namespace

void add_sample_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string surface, output, points;
    particles::SampleOptions sample;
    BackendOptions backend;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("sample", "Spread curvature-adaptive particles over an MPU surface");
  cmd->add_option("surface", o->surface, "surface: .mpu")->required();
  cmd->add_option("-o,--output", o->output, "particles: .ply or .xyz (x y z nx ny nz)")->required();
  cmd->add_option("--points", o->points, "seed candidates: the fitted points (default: the surface's leaf centres)");
  add_sample_options(cmd, o->sample, "--iterations");
  add_backend_options(cmd, o->backend);
  add_common(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      check_writable(o->output);
      particles::validate(o->sample);
      Progress progress(common.quiet || common.json);
      progress.begin("read surface");
      const mpu::MpuSurface s = mpu::read_mpu(o->surface);
      const std::vector<Eigen::Vector3d> candidates =
          o->points.empty() ? particles::leaf_candidates(s) : read_point_cloud(o->points).positions;
      progress.end();
      const vk::BackendChoice choice = open_backend(o->backend, common, progress);
      progress.begin("particles");
      particles::SampleStats st;
      const particles::ParticleState ps = particles::sample_surface(s, candidates, o->sample, *choice.backend, &st);
      progress.end();
      progress.begin("write particles");
      write_point_cloud(particle_cloud(ps), o->output);
      progress.end();
      nlohmann::json j = sample_json(o->sample, st, ps);
      j["input"] = o->surface;
      j["output"] = o->output;
      j["backend"] = backend_json(choice);
      j["stage_seconds"] = stage_json(progress);
      if (common.json) std::cout << j.dump(2) << '\n';
      else if (!common.quiet)
        std::cout << fmt::format("{}: {} particles after {} iterations ({}), flat spacing {:.3g} mm ({})\n", o->output,
                                 st.particles, st.iterations, st.converged ? "settled" : "at the cap", st.spacing,
                                 choice.backend->device());
    };
  });
}

void add_triangulate_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string surface, particles, output;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("triangulate", "Restricted Delaunay mesh of particles on an MPU surface (CGAL)");
  cmd->add_option("surface", o->surface, "surface: .mpu")->required();
  cmd->add_option("particles", o->particles, "particles: .ply or .xyz")->required();
  cmd->add_option("-o,--output", o->output, "mesh: .ply, .stl, .obj or .off")->required();
  add_common(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      check_writable(o->output);
      mesh_format_from_path(o->output);
      Progress progress(common.quiet || common.json);
      progress.begin("read");
      const mpu::MpuSurface s = mpu::read_mpu(o->surface);
      const PointCloud p = read_point_cloud(o->particles);
      progress.end();
      progress.begin("triangulate");
      RestrictedDelaunayStats st;
      TriangleMesh mesh = restricted_delaunay(s, p.positions, &st);
      progress.end();
      progress.begin("curvature");
      CpuBackend cpu;
      attach_surface_attributes(mesh, s, cpu);
      progress.end();
      progress.begin("write mesh");
      write_mesh(mesh, o->output);
      progress.end();
      const Topology t = analyze_topology(mesh);
      nlohmann::json j = triangulation_json(st);
      j["input"] = {o->surface, o->particles};
      j["output"] = o->output;
      j["vertices"] = mesh.vertices.size();
      j["triangles"] = mesh.triangles.size();
      j["closed"] = t.closed;
      j["oriented_manifold"] = t.oriented;
      j["components"] = t.components;
      j["stage_seconds"] = stage_json(progress);
      if (common.json) std::cout << j.dump(2) << '\n';
      else if (!common.quiet)
        std::cout << fmt::format("{}: {} triangles, {} repair points, closed {}, oriented manifold {}\n", o->output,
                                 mesh.triangles.size(), st.repair_points, t.closed ? "yes" : "no",
                                 t.oriented ? "yes" : "no");
    };
  });
}

// run's factor on the particle count when it samples again (the spacing is divided by its
// square root; a count is rounded up to a thousand particles).
constexpr double kRaise = 1.5;

void add_run_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string input, output, report, html, surface, local_fit = "orthopoly";
    SegmentCli seg;
    mpu::FitOptions fit;
    particles::SampleOptions sample;
    BackendOptions backend;
    bool self_intersections = true, partial_volume_caps = false;
    int count_retries = -1;  // -1: 2 when neither --particles nor --spacing is given, else 0
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand(
      "run", "The whole job: a CT/MR volume (or a surface mesh, to remesh it) to a smooth adaptive mesh");
  cmd->add_option("input", o->input,
                  "volume (DICOM directory, .dcm, .nii[.gz], .nrrd, .mha/.mhd, .inv3) or mesh (.stl, .ply, .obj, .off)")
      ->required();
  cmd->add_option("-o,--output", o->output, "mesh: .ply, .stl, .obj or .off")->required();
  cmd->add_option("--report", o->report, "write the JSON report here");
  cmd->add_option("--surface", o->surface, "write the fitted implicit surface here (.mpu), e.g. for `polygonize`");
  cmd->add_option("--html", o->html,
                  "write the HTML report here: renders, the comparison with marching cubes and the original MPU, "
                  "histograms, stage times");
  cmd->add_flag("!--no-self-intersections", o->self_intersections, "skip the self-intersection test of the report");
  add_segment_options(cmd, o->seg);
  cmd->add_flag("--partial-volume-caps", o->partial_volume_caps,
                "cap points' heights from the grey of the two slabs the surface crosses, not the contours alone");
  add_fit_options(cmd, o->fit, o->local_fit);
  add_sample_options(cmd, o->sample, "--particle-iterations");
  cmd->add_option("--count-retries", o->count_retries,
                  fmt::format("when the triangulation needs repair points for more than a tenth of the particles "
                              "(too sparse a sample for the surface's thin plates), sample again with {} times the "
                              "particles, up to this many times; default 2 when neither --particles nor --spacing "
                              "is given, 0 when one is",
                              kRaise))
      ->check(CLI::Range(0, 8));
  add_backend_options(cmd, o->backend);
  add_common(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      // Every output and parameter is checked before the long work starts.
      check_writable(o->output);
      mesh_format_from_path(o->output);
      if (!o->report.empty()) check_writable(o->report);
      if (!o->surface.empty()) check_writable(o->surface);
      if (!o->html.empty()) {
        check_writable(o->html);
        if (lower_extension(o->html) != ".html") throw InputError(o->html + ": the HTML report must be a .html file");
      }
      o->fit.local_fit = o->local_fit == "quadric" ? mpu::LocalFit::kQuadric : mpu::LocalFit::kOrthopoly;
      mpu::validate(o->fit);
      particles::validate(o->sample, "run", "particle-iterations");
      // Memory: the particles alone first, then (below) with the volume and the points,
      // before the fit, the particles and the triangulation start.
      const int64_t asked = o->sample.particles > 0 ? o->sample.particles : particles::kDefaultParticles;
      check_memory("run", estimate_run_bytes(0, 0, asked));
      int64_t voxels = 0;
      const bool eps_given = o->fit.eps > 0;
      mpu::Tolerance tolerance;
      Progress progress(common.quiet || common.json);
      nlohmann::json j;
      PointCloud cloud;
      vk::BackendChoice choice;
      // The report's baselines: the input mesh, or marching cubes of the volume.
      std::vector<std::pair<std::string, TriangleMesh>> baselines;
      if (is_mesh_path(o->input)) {
        progress.begin("read mesh");
        const TriangleMesh in = read_mesh(o->input);
        progress.end();
        const Topology in_topo = analyze_topology(in);
        if (!in_topo.closed || in_topo.nonmanifold_edges > 0)
          throw InputError(fmt::format("{}: the input mesh is not a closed manifold ({} border edges, {} non-manifold "
                                       "edges); remeshing needs a closed surface",
                                       o->input, in_topo.border_edges, in_topo.nonmanifold_edges));
        progress.begin("points");
        cloud = pts::mesh_points(in);
        progress.end();
        if (!o->html.empty()) baselines.push_back({"input mesh", in});
        if (cloud.size() == 0) throw InputError(o->input + ": the mesh has no triangle with an area");
        j["input"] = {{"path", o->input}, {"kind", "mesh"}, {"vertices", in.vertices.size()},
                      {"triangles", in.triangles.size()}};
        choice = open_backend(o->backend, common, progress);
      } else {
        SegmentedVolume sv = read_and_segment(o->input, o->seg, o->backend, common, progress);
        progress.begin("points");
        pts::PointOptions popt;
        popt.partial_volume_caps = o->partial_volume_caps;
        pts::SlicePoints p = pts::extract_points(sv.segmentation, sv.volume, popt);
        progress.end();
        if (p.cloud.size() == 0)
          throw InputError(o->input + ": the segmentation holds no surface (nothing inside the threshold range?)");
        cloud = std::move(p.cloud);
        const Volume& vol = sv.volume;
        o->sample.voxel_size = vol.in_plane_spacing();  // the default count follows it
        if (!(o->fit.eps > 0)) {  // no --eps: the tolerance follows the scan (mpu/fit_tolerance.h)
          tolerance = mpu::volume_tolerance(cloud, vol.in_plane_spacing());
          o->fit.eps = tolerance.eps;
        }
        voxels = vol.voxel_count();
        j["input"] = {{"path", o->input},
                      {"kind", "volume"},
                      {"dims", vol.dims},
                      {"spacing_mm", {vol.spacing.x(), vol.spacing.y(), vol.spacing.z()}},
                      {"modality", vol.modality},
                      {"read_notes", vol.read_notes}};
        j["segmentation"] = segment_json(sv.options, sv.segmentation);
        choice = std::move(sv.backend);
        if (!o->html.empty()) {
          progress.begin("marching cubes (report)");
          baselines.push_back({"marching cubes", marching_cubes(vol, sv.options.threshold, *choice.backend)});
          progress.end();
        }
      }
      j["points"] = cloud.size();
      uint64_t estimate = estimate_run_bytes(voxels, int64_t(cloud.size()), asked);
      check_memory(o->input, estimate);
      progress.begin("fit");
      mpu::FitStats fit_stats;
      const mpu::MpuSurface s = mpu::fit_mpu(cloud, o->fit, &fit_stats);
      progress.end();
      // Particles and triangulation, again with 1.5 times the particles while the
      // triangulation shows the sample too sparse (see `sparse` below) and retries are left.
      // (The first sample keeps the default's own rules, see sample_surface.)
      particles::SampleOptions so = o->sample;
      const bool count_given = o->sample.particles > 0 || o->sample.spacing > 0;
      int retries = o->count_retries >= 0 ? o->count_retries : count_given ? 0 : 2;
      // Too sparse a sample for the surface's thin plates shows as many repair points, and
      // its triangles next to them are poor: on the sample CT 4-5% at 40,000 particles
      // (smallest angle 20°), 16% at 30,000 (1.2% of triangles under 30°), 36% at full
      // resolution at 40,000 (10.6°; 3% and 20.2° at 60,000, 1.5 times the count).
      auto sparse = [](const RestrictedDelaunayStats& t, size_t particles) {
        return particles > 0 && t.repair_points > int64_t(particles) / 10;
      };
      auto denser = [](particles::SampleOptions x, int64_t asked) {
        if (x.spacing > 0)
          x.spacing /= std::sqrt(kRaise);
        else
          x.particles = int64_t(std::ceil(double(asked > 0 ? asked : particles::kDefaultParticles) * kRaise / 1000)) *
                        1000;
        return x;
      };
      particles::SampleStats sst;
      particles::ParticleState ps;
      std::map<std::string, double> particle_kernel_ms;
      RestrictedDelaunayStats tst;
      TriangleMesh mesh;
      nlohmann::json raises = nlohmann::json::array();
      for (;;) {
        progress.begin("particles");
        ps = particles::sample_surface(s, cloud.positions, so, *choice.backend, &sst);
        // The particle kernels' device times, before a later stage's kernels replace them.
        particle_kernel_ms = choice.backend->kernel_ms();
        progress.end();
        progress.begin("triangulate");
        tst = RestrictedDelaunayStats{};
        mesh = restricted_delaunay(s, ps.x, &tst, 0, choice.backend.get());
        progress.end();
        if (!sparse(tst, ps.size()) || retries == 0) break;
        --retries;
        const particles::SampleOptions next = denser(so, sst.asked);
        raises.push_back({{"requested_particles", so.particles},
                          {"requested_spacing_mm", so.spacing},
                          {"asked_particles", sst.asked},
                          {"particles", ps.size()},
                          {"repair_points", tst.repair_points},
                          {"next_requested_particles", next.particles},
                          {"next_requested_spacing_mm", next.spacing}});
        if (!common.json && !common.quiet)
          std::cout << fmt::format("note: {} repair points for {} particles, too sparse a sample: sampling again "
                                   "with {}\n",
                                   tst.repair_points, ps.size(),
                                   next.spacing > 0 ? fmt::format("spacing {:.3f} mm", next.spacing)
                                                    : fmt::format("{} particles", next.particles));
        so = next;
        // (By spacing, the count grows by the same factor.)
        estimate = estimate_run_bytes(voxels, int64_t(cloud.size()),
                                      so.particles > 0 ? so.particles : int64_t(double(ps.size()) * kRaise));
        check_memory(o->input, estimate);
        mesh = TriangleMesh{};
        ps = particles::ParticleState{};
      }
      const Topology topo = analyze_topology(mesh);
      if (!topo.closed || !topo.oriented)
        throw InputError(fmt::format("{}: the triangulation is not a closed oriented manifold ({} border edges, {} "
                                     "non-manifold edges, {} non-manifold vertices); nothing written",
                                     o->input, topo.border_edges, topo.nonmanifold_edges, topo.nonmanifold_vertices));
      progress.begin("curvature");
      attach_surface_attributes(mesh, s, *choice.backend);
      progress.end();
      for (size_t i = 0; i < mesh.vertices.size(); ++i)
        if (!mesh.vertices[i].allFinite() || !mesh.normals[i].allFinite())
          throw NumericalError(o->input + ": vertex " + std::to_string(i) +
                               " of the triangulation or its normal is not finite; nothing written");
      progress.begin("write mesh");
      write_mesh(mesh, o->output);
      if (!o->surface.empty()) write_mpu(s, o->surface);
      progress.end();
      j["fit"] = fit_json(o->fit, fit_stats);
      j["fit"]["eps_source"] = tolerance.source.empty() ? (eps_given ? "--eps" : "a quarter of the points' median spacing")
                                                         : tolerance.source;
      if (tolerance.noise > 0) j["fit"]["point_noise_mm"] = tolerance.noise;
      j["particles"] = sample_json(so, sst, ps);
      j["particles"]["kernel_ms"] = particle_kernel_ms;
      j["particles"]["count_raises"] = raises;
      j["triangulation"] = triangulation_json(tst);
      j["backend"] = backend_json(choice);
      j["kernel_ms"] = choice.backend->kernel_ms();
      j["output"] = o->output;
      j["vertices"] = mesh.vertices.size();
      j["triangles"] = mesh.triangles.size();
      if (!o->report.empty() || common.json || !common.quiet) {
        progress.begin("quality");
        QualityOptions qo;
        qo.self_intersections = o->self_intersections;
        const Quality q = measure_quality(mesh, qo);
        progress.end();
        j["quality"] = quality_to_json(q);
        if (!common.json && !common.quiet)
          std::cout << o->output << ": " << mesh.triangles.size() << " triangles from " << ps.size()
                    << " particles (" << choice.backend->device() << ")\n"
                    << quality_to_text(q);
      }
      j["notes"] = nlohmann::json::array();
      if (j["input"].contains("read_notes"))
        for (const auto& n : j["input"]["read_notes"]) j["notes"].push_back(n);
      if (sparse(tst, ps.size())) {
        const particles::SampleOptions more_opt = denser(so, sst.asked);
        const std::string more = more_opt.spacing > 0 ? fmt::format("--spacing {:.2f}", more_opt.spacing)
                                                      : fmt::format("--particles {}", more_opt.particles);
        const std::string note = fmt::format(
            "the triangulation added {} repair points to {} particles ({:.0f}%): the particles are too sparse for "
            "this surface's thin plates, and the triangles next to repair points are poor; {} times as many "
            "particles ({}) should do better",
            tst.repair_points, ps.size(), 100.0 * double(tst.repair_points) / double(ps.size()), kRaise, more);
        j["notes"].push_back(note);
        if (!common.json && !common.quiet) std::cout << "note: " << note << "\n";
      }
      if (!o->html.empty()) {
        progress.begin("original MPU (report)");
        baselines.push_back({"original MPU", mpu::polygonize(s, 0, *choice.backend)});
        progress.end();
      }
      j["stage_seconds"] = stage_json(progress);
      j["version"] = MPUMESH_VERSION;
      j["memory"] = {{"estimate_gib", double(estimate) / double(1ull << 30)},
                     {"available_gib", double(available_memory_bytes()) / double(1ull << 30)},
                     {"peak_rss_gib", double(peak_rss_bytes()) / double(1ull << 30)}};
      if (!o->html.empty()) {
        progress.begin("report");
        ReportInputs in;
        in.ours = {std::filesystem::path(o->output).filename().string() + " (ours)", &mesh};
        for (const auto& [name, m] : baselines) in.baselines.push_back({name, &m});
        in.run = j;
        write_file_atomically(build_report(in, *choice.backend), o->html);
        progress.end();
        j["html"] = o->html;
      }
      if (!o->report.empty()) write_json_file(j, o->report);
      if (common.json) std::cout << j.dump(2) << '\n';
    };
  });
}

}  // namespace mpumesh::tools
