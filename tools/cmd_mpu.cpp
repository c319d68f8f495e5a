// mpumesh fit: oriented points to an MPU implicit surface (.mpu).
// mpumesh eval: f, ∇f and curvature of a surface at query points, on either backend.
// mpumesh polygonize: the original MPU method's mesh of a surface (uniform grid + MC).
#include <fmt/format.h>

#include <cstdio>
#include <fstream>
#include <iostream>

#include "cli_util.h"
#include "commands.h"
#include "common/error.h"
#include "io/atomic_file.h"
#include "io/mesh_io.h"
#include "io/point_io.h"
#include "mpu_cli.h"
#include "mpu/mpu_fit.h"
#include "mpu/mpu_io.h"
#include "mpu/polygonize.h"
#include "mpu/mpu_eval_ref.h"

namespace mpumesh::tools {

void add_fit_options(CLI::App* cmd, mpu::FitOptions& f, std::string& local_fit) {
  cmd->add_option("--local-fit", local_fit,
                  "orthopoly (height field in orthogonal polynomials, adaptive degree) or quadric (Ohtake's)")
      ->check(CLI::IsMember({"orthopoly", "quadric"}))
      ->capture_default_str();
  cmd->add_option("--eps", f.eps, "error bound eps0 (mm); 0 = a quarter of the median point spacing")
      ->capture_default_str();
  cmd->add_option("--nmin", f.nmin, "points a support ball must hold")->capture_default_str();
  cmd->add_option("--alpha", f.alpha, "support radius / cell diagonal")->capture_default_str();
  cmd->add_option("--lambda", f.lambda, "support growth factor per step")->capture_default_str();
  cmd->add_option("--max-depth", f.max_depth, "deepest octree level")->capture_default_str();
  cmd->add_option("--max-degree", f.max_degree, "highest orthopoly degree (2-4)")->capture_default_str();
  cmd->add_flag("--fit-normals", f.fit_normals,
                "fit the points' normals too (for exact normals: analytic or a smooth mesh's; off for CT contours)");
  cmd->add_option("--min-radius", f.min_radius,
                  "smallest support radius (mm); negative = 1.5 x the median distance to the 12th nearest point")
      ->capture_default_str();
}

nlohmann::json fit_json(const mpu::FitOptions& o, const mpu::FitStats& st) {
  return {{"local_fit", mpu::local_fit_name(o.local_fit)},
          {"leaves", st.leaves},
          {"height_orthopoly", st.height_orthopoly},
          {"height_quadric", st.height_quadric},
          {"general_quadric", st.general_quadric},
          {"two_sheets", st.two_sheets},
          {"orthopoly_degrees", {{"2", st.degree_counts[2]}, {"3", st.degree_counts[3]}, {"4", st.degree_counts[4]}}},
          {"leaves_over_eps", st.over_eps},
          {"leaves_kept_below_held_bound", st.kept_below_held_bound},
          {"duplicates_removed", st.duplicates_removed},
          {"max_depth_reached", st.max_depth_reached},
          {"eps_mm", st.eps},
          {"min_radius_mm", st.min_radius},
          {"nmin", o.nmin},
          {"alpha", o.alpha},
          {"lambda", o.lambda},
          {"max_depth", o.max_depth},
          {"max_degree", o.max_degree},
          {"fit_normals", o.fit_normals},
          {"seconds", st.seconds},
          {"seconds_by_step",
           {{"setup", st.seconds_setup}, {"levels", st.seconds_by_depth}, {"lookup_grid", st.seconds_grid}}}};
}

void add_fit_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string input, output, local_fit = "orthopoly";
    mpu::FitOptions fit;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("fit", "Fit an MPU implicit surface to oriented points");
  cmd->add_option("points", o->input, "oriented points: .ply (x y z nx ny nz) or .xyz")->required();
  cmd->add_option("-o,--output", o->output, "surface: .mpu")->required();
  add_fit_options(cmd, o->fit, o->local_fit);
  add_common(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      check_writable(o->output);
      o->fit.local_fit = o->local_fit == "quadric" ? mpu::LocalFit::kQuadric : mpu::LocalFit::kOrthopoly;
      mpu::validate(o->fit);
      Progress progress(common.quiet || common.json);
      progress.begin("read points");
      const PointCloud cloud = read_point_cloud(o->input);
      progress.end();
      progress.begin("fit");
      mpu::FitStats st;
      const mpu::MpuSurface s = mpu::fit_mpu(cloud, o->fit, &st);
      progress.end();
      progress.begin("write surface");
      mpu::write_mpu(s, o->output);
      progress.end();
      nlohmann::json j = fit_json(o->fit, st);
      j["input"] = o->input;
      j["points"] = cloud.size();
      j["output"] = o->output;
      j["stage_seconds"] = stage_json(progress);
      if (common.json) std::cout << j.dump(2) << '\n';
      else if (!common.quiet)
        std::cout << fmt::format("{}: {} leaves ({} orthopoly, {} quadric height fields, {} general quadrics, {} two "
                                 "sheets) from {} points in {:.2f} s, eps {:.3g} mm\n",
                                 o->output, st.leaves, st.height_orthopoly, st.height_quadric, st.general_quadric,
                                 st.two_sheets, cloud.size(), st.seconds, st.eps);
    };
  });
}

void add_eval_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string surface, queries, output;
    BackendOptions backend;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand(
      "eval", "Evaluate a surface at query points: one line 'x y z f gx gy gz k1 k2 K H' per point (mm, 1/mm, 1/mm^2)");
  cmd->add_option("surface", o->surface, "surface: .mpu")->required();
  cmd->add_option("queries", o->queries, "query points: text, x y z per line (further columns ignored)")->required();
  cmd->add_option("-o,--output", o->output, "write the lines here instead of stdout");
  add_backend_options(cmd, o->backend);
  cmd->add_flag("--quiet,-q", common.quiet, "print nothing but errors");
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      if (!o->output.empty()) check_writable(o->output);
      const mpu::MpuSurface s = mpu::read_mpu(o->surface);
      const auto points = read_positions(o->queries);
      Progress progress(true);
      const vk::BackendChoice choice = open_backend(o->backend, common, progress);
      const auto rows = choice.backend->mpu_eval(s, points);
      std::string text;
      text.reserve(rows.size() * 160);
      char line[512];
      for (const auto& r : rows) {
        const int n = std::snprintf(line, sizeof line, "%.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n",
                                    r.x[0], r.x[1], r.x[2], r.f, r.g[0], r.g[1], r.g[2], r.k1, r.k2, r.gauss, r.mean);
        text.append(line, size_t(n));
      }
      if (o->output.empty()) {
        std::fwrite(text.data(), 1, text.size(), stdout);
        return;
      }
      AtomicFile out(o->output);
      {
        std::ofstream os(out.temp_path(), std::ios::binary);
        os.write(text.data(), std::streamsize(text.size()));
        os.flush();
        if (!os) throw InputError(o->output + ": write failed (disk full?)");
      }
      out.commit();
    };
  });
}

void add_polygonize_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string surface, output;
    double cell = 0;
    BackendOptions backend;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("polygonize", "The original MPU mesh: f on a uniform grid, then marching cubes");
  cmd->add_option("surface", o->surface, "surface: .mpu")->required();
  cmd->add_option("-o,--output", o->output, "mesh: .ply, .stl, .obj or .off")->required();
  cmd->add_option("--cell", o->cell, "grid cell (mm); 0 = 1/200 of the surface's largest extent")
      ->capture_default_str();
  add_backend_options(cmd, o->backend);
  add_common(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      check_writable(o->output);
      mesh_format_from_path(o->output);
      if (!(o->cell >= 0)) throw InputError("polygonize: --cell must be positive (or 0 for the default)");
      Progress progress(common.quiet || common.json);
      progress.begin("read surface");
      const mpu::MpuSurface s = mpu::read_mpu(o->surface);
      progress.end();
      const vk::BackendChoice choice = open_backend(o->backend, common, progress);
      progress.begin("polygonize");
      mpu::PolygonizeStats st;
      const TriangleMesh mesh = mpu::polygonize(s, o->cell, *choice.backend, &st);
      progress.end();
      progress.begin("write mesh");
      write_mesh(mesh, o->output);
      progress.end();
      nlohmann::json j;
      j["input"] = o->surface;
      j["output"] = o->output;
      j["cell_mm"] = st.cell;
      j["grid"] = st.dims;
      j["vertices"] = mesh.vertices.size();
      j["triangles"] = mesh.triangles.size();
      j["seconds"] = {{"evaluate", st.eval_seconds}, {"marching_cubes", st.mc_seconds}};
      j["backend"] = backend_json(choice);
      j["stage_seconds"] = stage_json(progress);
      if (common.json) std::cout << j.dump(2) << '\n';
      else if (!common.quiet)
        std::cout << fmt::format("{}: {} triangles, {} vertices ({} x {} x {} grid, {:.3g} mm cells)\n", o->output,
                                 mesh.triangles.size(), mesh.vertices.size(), st.dims[0], st.dims[1], st.dims[2],
                                 st.cell);
    };
  });
}

}  // namespace mpumesh::tools
