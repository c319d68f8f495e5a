// `mpumesh render`: a PNG of a mesh from the offscreen renderer (host/render), on a Vulkan
// device or the CPU reference; `mpumesh report`: the HTML report of any mesh.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli_util.h"
#include "commands.h"
#include "common/error.h"
#include "io/atomic_file.h"
#include "io/mesh_io.h"
#include "io/read_file.h"
#include "render/mesh_render_vk.h"
#include "render/render_scene.h"
#include "report_builder.h"
#include "run_json.h"

namespace mpumesh::tools {

void add_render_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string mesh, output, color = "none", view = "iso", zoom, size = "1024x768", title, range;
    bool wireframe = false;
    BackendOptions backend;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("render", "Offscreen picture of a mesh (PNG), on a Vulkan device or the CPU");
  cmd->add_option("mesh", o->mesh, "mesh: .ply, .stl, .obj or .off")->required();
  cmd->add_option("-o,--output", o->output, "image: .png")->required();
  cmd->add_option("--color", o->color,
                  "none, curvature (Gaussian K: the mesh's own from `run`, else estimated from the mesh), "
                  "min-angle (each triangle's smallest angle), edge-length, or label (a complex of `run --labels`: its outer "
                  "faces coloured by the label they bound)")
      ->capture_default_str();
  cmd->add_option("--view", o->view, "iso, front, side, top, or x,y,z: the direction toward the viewer (LPS)")
      ->capture_default_str();
  cmd->add_option("--zoom", o->zoom, "x,y,z,r: frame only the ball of radius r mm at (x, y, z)");
  cmd->add_flag("--wireframe", o->wireframe, "draw the triangle edges over the surface");
  cmd->add_option("--size", o->size, "WxH in pixels")->capture_default_str();
  cmd->add_option("--title", o->title, "text at the top left");
  cmd->add_option("--range", o->range, "LO:HI: the colour bar's range instead of the automatic one");
  add_backend_options(cmd, o->backend);
  add_common(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      check_writable(o->output);
      if (lower_extension(o->output) != ".png") throw InputError(o->output + ": the image must be a .png");
      render::RenderOptions ro;
      ro.color = render::parse_color(o->color);
      ro.view = render::parse_view(o->view);
      if (!o->zoom.empty()) ro.zoom = render::parse_zoom(o->zoom);
      std::tie(ro.width, ro.height) = render::parse_size(o->size);
      ro.wireframe = o->wireframe;
      ro.title = o->title;
      if (!o->range.empty()) {
        const size_t colon = o->range.find(':');
        try {
          if (colon == std::string::npos) throw std::invalid_argument("no colon");
          ro.range = {std::stod(o->range.substr(0, colon)), std::stod(o->range.substr(colon + 1))};
        } catch (const std::exception&) {
          throw InputError("--range: '" + o->range + "' is not LO:HI");
        }
        if (!(ro.range->second > ro.range->first)) throw InputError("--range: HI must exceed LO");
      }
      Progress progress(common.quiet || common.json);
      progress.begin("read mesh");
      const TriangleMesh mesh = read_mesh(o->mesh);
      progress.end();
      if (mesh.triangles.empty()) throw InputError(o->mesh + ": the mesh has no triangles to render");
      vk::BackendChoice choice = open_backend(o->backend, common, progress);
      progress.begin("render");
      const render::RenderScene scene = render::build_scene(mesh, ro);
      const render::Image img = vk::render_image(*choice.backend, scene);
      progress.end();
      progress.begin("write image");
      render::write_png(img, o->output);
      progress.end();
      nlohmann::json j;
      j["input"] = o->mesh;
      j["output"] = o->output;
      j["size"] = {img.width, img.height};
      j["triangles"] = mesh.triangles.size();
      j["backend"] = backend_json(choice);
      j["legend"] = {{"shown", scene.legend.shown}, {"title", scene.legend.title}, {"lo", scene.legend.lo},
                     {"hi", scene.legend.hi}};
      j["stage_seconds"] = stage_json(progress);
      if (common.json) std::cout << j.dump(2) << '\n';
      else if (!common.quiet)
        std::cout << fmt::format("{}: {} x {} from {} triangles ({})\n", o->output, img.width, img.height,
                                 mesh.triangles.size(), choice.backend->device());
    };
  });
}

}  // namespace mpumesh::tools

namespace mpumesh::tools {

void add_report_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string mesh, output, run_report;
    std::vector<std::string> references;
    BackendOptions backend;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("report", "Self-contained HTML report of a mesh, beside reference meshes");
  cmd->add_option("mesh", o->mesh, "mesh: .ply (with the curvature `run` writes), .stl, .obj or .off")->required();
  cmd->add_option("-o,--output", o->output, "report: .html")->required();
  cmd->add_option("--reference", o->references, "a mesh to compare with (repeatable), e.g. a marching-cubes mesh");
  cmd->add_option("--run-report", o->run_report, "the JSON report of the run that made the mesh (stages, parameters)");
  add_backend_options(cmd, o->backend);
  add_common(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      check_writable(o->output);
      if (lower_extension(o->output) != ".html") throw InputError(o->output + ": the report must be a .html file");
      Progress progress(common.quiet || common.json);
      progress.begin("read");
      const TriangleMesh mesh = read_mesh(o->mesh);
      std::vector<TriangleMesh> refs;
      for (const auto& r : o->references) refs.push_back(read_mesh(r));
      nlohmann::json run = nlohmann::json::object();
      if (!o->run_report.empty()) {
        try {
          run = nlohmann::json::parse(read_file(o->run_report));
        } catch (const nlohmann::json::exception& e) {
          throw InputError(o->run_report + ": not a JSON report (" + e.what() + ")");
        }
        if (!run.is_object()) throw InputError(o->run_report + ": not a JSON report (not an object)");
      }
      progress.end();
      if (mesh.triangles.empty()) throw InputError(o->mesh + ": the mesh has no triangles to report on");
      vk::BackendChoice choice = open_backend(o->backend, common, progress);
      progress.begin("report");
      ReportInputs in;
      in.ours = {std::filesystem::path(o->mesh).filename().string(), &mesh};
      for (size_t i = 0; i < refs.size(); ++i)
        in.baselines.push_back({std::filesystem::path(o->references[i]).filename().string(), &refs[i]});
      RunReportRead read;
      if (!o->run_report.empty()) {
        read = read_run_json(run, o->run_report);
        in.run.result = &read.run;
        in.run.device = read.device;
        in.run.stage_seconds = read.stage_seconds;
        in.run.parameters = report_parameters(run);
      }
      const std::string html = build_report(in, *choice.backend);
      progress.end();
      write_file_atomically(html, o->output);
      if (common.json)
        std::cout << nlohmann::json{{"output", o->output}, {"bytes", html.size()}, {"stage_seconds", stage_json(progress)}}
                         .dump(2)
                  << '\n';
      else if (!common.quiet)
        std::cout << fmt::format("{}: {} KiB ({})\n", o->output, html.size() / 1024, choice.backend->device());
    };
  });
}

}  // namespace mpumesh::tools
