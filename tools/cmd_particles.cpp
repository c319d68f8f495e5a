// mpumesh sample: curvature-adaptive particles on an MPU surface.
// mpumesh triangulate: the restricted Delaunay mesh of particles on a surface.
#include <fmt/format.h>

#include <iostream>

#include "cli_util.h"
#include "commands.h"
#include "cpu/cpu_backend.h"
#include "io/atomic_file.h"
#include "io/mesh_io.h"
#include "io/point_io.h"
#include "mesh/restricted_delaunay.h"
#include "mesh/surface_attributes.h"
#include "mesh/topology.h"
#include "mpu/mpu_io.h"
#include "particles/particle_system.h"
#include "option_spelling.h"
#include "particles/spacing_stats.h"
#include "run_json.h"
#include "sample_cli.h"

namespace mpumesh::tools {
namespace {

PointCloud particle_cloud(const particles::ParticleState& ps) {
  PointCloud c;
  c.positions = ps.x;
  c.normals = ps.normal;
  return c;
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
      as_command("sample", [&] { particles::validate(o->sample); });
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
      const particles::SpacingSummary spacing = particles::spacing_summary(st, ps);
      nlohmann::json j = sample_json(o->sample, st, &spacing);
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

}  // namespace mpumesh::tools
