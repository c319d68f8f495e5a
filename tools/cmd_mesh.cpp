// mpumesh mc, quality and filter: the marching-cubes baseline, the quality report, and
// keeping a closed mesh's wanted structures.
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "cli_util.h"
#include "component_cli.h"
#include "commands.h"
#include "common/error.h"
#include "io/atomic_file.h"
#include "io/mesh_io.h"
#include "io/tet_io.h"
#include "tet_cli.h"
#include "io/volume_io.h"
#include "mc/marching_cubes.h"
#include "mesh/component_filter.h"
#include "mesh/quality.h"
#include "mesh/topology.h"
#include "progress.h"
#include "vulkan_backend.h"

namespace mpumesh::tools {
namespace {

struct MeshJob {
  std::string input, output, threshold = "226";
  BackendOptions backend;
};

// Reads, meshes and writes; returns the summary (and fills `mesh`).
nlohmann::json run_mc(const MeshJob& job, const CommonOptions& common, Progress& progress, TriangleMesh& mesh) {
  check_writable(job.output);
  mesh_format_from_path(job.output);
  const mc::ThresholdRange range = mc::parse_threshold(job.threshold);
  progress.begin("read volume");
  Volume vol = read_volume(job.input);
  progress.end();
  vk::BackendChoice choice = open_backend(job.backend, common, progress);
  progress.begin("marching cubes");
  mesh = marching_cubes(vol, range, *choice.backend);
  progress.end();
  progress.begin("write mesh");
  write_mesh(mesh, job.output);
  progress.end();
  nlohmann::json j;
  j["input"] = {{"path", job.input},
                {"dims", vol.dims},
                {"spacing_mm", {vol.spacing.x(), vol.spacing.y(), vol.spacing.z()}},
                {"modality", vol.modality},
                {"read_notes", vol.read_notes}};
  j["threshold"] = {{"lo", range.lo}, {"hi", std::isinf(range.hi) ? nlohmann::json() : nlohmann::json(range.hi)}};
  j["backend"] = backend_json(choice);
  j["kernel_ms"] = choice.backend->kernel_ms();
  j["output"] = job.output;
  j["vertices"] = mesh.vertices.size();
  j["triangles"] = mesh.triangles.size();
  return j;
}

}  // namespace

void add_mc_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  auto job = std::make_shared<MeshJob>();
  auto* cmd = app.add_subcommand("mc", "Marching cubes on the thresholded volume (the voxel-level baseline)");
  cmd->add_option("input", job->input, "volume: DICOM directory, .dcm, .nii[.gz], .nrrd, .mha/.mhd, .inv3")->required();
  cmd->add_option("-o,--output", job->output, "mesh: .ply, .stl, .obj or .off")->required();
  cmd->add_option("--threshold", job->threshold, "inside range LO or LO:HI (HU for CT)")->capture_default_str();
  add_backend_options(cmd, job->backend);
  add_common(cmd, common);
  cmd->callback([&common, &action, job] {
    action = [&common, job] {
      Progress progress(common.quiet || common.json);
      TriangleMesh mesh;
      nlohmann::json j = run_mc(*job, common, progress, mesh);
      j["stage_seconds"] = stage_json(progress);
      const Topology t = analyze_topology(mesh);
      j["closed"] = t.closed;
      j["manifold"] = t.manifold;
      j["components"] = t.components;
      if (common.json) std::cout << j.dump(2) << '\n';
      else if (!common.quiet)
        std::cout << fmt::format("{}: {} vertices, {} triangles, {} components, closed {}, manifold {} ({})\n",
                                 job->output, mesh.vertices.size(), mesh.triangles.size(), t.components,
                                 t.closed ? "yes" : "no", t.manifold ? "yes" : "no",
                                 j["backend"]["device"].get<std::string>());
    };
  });
}

void add_quality_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string mesh, reference;
    bool no_self = false;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("quality", "Topology, triangle quality, smoothness and distances of a mesh; the "
                                            "tetrahedra's shapes of a volume mesh");
  cmd->add_option("mesh", o->mesh, "mesh: .ply, .stl, .obj or .off; or a volume mesh: .msh, .vtu, .mesh or .inp")
      ->required();
  cmd->add_option("--reference", o->reference, "reference mesh for Hausdorff and mean distances (mm)");
  cmd->add_flag("--no-self-intersections", o->no_self, "skip the self-intersection test (slow on huge meshes)");
  add_common(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      // The figures as JSON (with the mesh's path) or as text.
      const auto print = [&](nlohmann::json j, const std::string& text) {
        if (common.json) {
          j["mesh"] = o->mesh;
          std::cout << j.dump(2) << '\n';
        } else if (!common.quiet) {
          std::cout << o->mesh << "\n" << text;
        }
      };
      if (is_tet_mesh_path(o->mesh)) {
        if (!o->reference.empty()) throw InputError(o->mesh + ": --reference measures surfaces, not volume meshes");
        const TetQuality q = measure_tet_quality(read_tet_mesh(o->mesh));
        print(tet_quality_json(q), tet_quality_text(q));
        return;
      }
      TriangleMesh mesh = read_mesh(o->mesh);
      TriangleMesh ref;
      QualityOptions opt;
      opt.self_intersections = !o->no_self;
      if (!o->reference.empty()) {
        ref = read_mesh(o->reference);
        opt.reference = &ref;
      }
      const Quality q = measure_quality(mesh, opt);
      print(quality_to_json(q), quality_to_text(q));
    };
  });
}

void add_filter_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string input, output;
    ComponentOptions components;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("filter", "Keep the wanted structures of a closed mesh: the largest, or those "
                                           "above a volume");
  cmd->add_option("mesh", o->input, "mesh: .ply, .stl, .obj or .off (closed)")->required();
  cmd->add_option("-o,--output", o->output, "mesh: .ply, .stl, .obj or .off")->required();
  add_component_options(cmd, o->components);
  add_common(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      check_writable(o->output);
      mesh_format_from_path(o->output);
      if (!o->components.active()) throw InputError("filter: give --largest or --min-volume");
      Progress progress(common.quiet || common.json);
      progress.begin("read mesh");
      const TriangleMesh in = read_mesh(o->input);
      progress.end();
      require_closed_manifold(in, o->input, "the mesh", "its structures enclose no volume");
      progress.begin("keep components");
      const FilteredMesh f = filter_components(in, o->components);
      progress.end();
      require_kept(f, o->components, o->input);
      progress.begin("write mesh");
      write_mesh(f.mesh, o->output);
      progress.end();
      nlohmann::json j = components_json(o->components, f.kept, f.dropped);
      j["input"] = o->input;
      j["output"] = o->output;
      j["triangles"] = f.mesh.triangles.size();
      j["stage_seconds"] = stage_json(progress);
      if (common.json) std::cout << j.dump(2) << '\n';
      else if (!common.quiet)
        std::cout << fmt::format("{}: {} triangles\n", o->output, f.mesh.triangles.size())
                  << components_text(f.kept, f.dropped);
    };
  });
}

}  // namespace mpumesh::tools
