// mpumesh tetmesh: linear tetrahedra inside any closed, oriented surface mesh (core/tet), or
// a multi-material complex's regions (core/multi/complex_tetrahedralize.h), written in an FE
// format by extension (core/io/tet_io.h).
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "cli_util.h"
#include "commands.h"
#include "common/error.h"
#include "io/atomic_file.h"
#include "io/mesh_io.h"
#include "io/tet_io.h"
#include "multi/complex_tetrahedralize.h"
#include "progress.h"
#include "option_spelling.h"
#include "tet_cli.h"

namespace mpumesh::tools {

void add_tetmesh_command(CLI::App& app, CommonOptions& common, std::function<void()>& action) {
  struct Opts {
    std::string input, output, report;
    TetOptions tet;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("tetmesh", "Fill a closed surface mesh, or each label of a multi-material complex, "
                                            "with quality tetrahedra for finite elements (the surface's triangles "
                                            "are their boundary)");
  cmd->add_option("surface", o->input,
                  "closed, oriented surface: .ply, .stl, .obj or .off; or a complex: a PLY whose faces carry "
                  "label_a, label_b")
      ->required();
  cmd->add_option("-o,--output", o->output,
                  "volume mesh: .msh (gmsh 4.1), .vtu (VTK), .mesh (medit) or .inp (Abaqus/CalculiX, mesh only)")
      ->required();
  cmd->add_option("--report", o->report, "write the JSON report here");
  add_tet_options(cmd, o->tet, "");
  add_common(cmd, common);
  add_progress_flag(cmd, common);
  cmd->callback([&common, &action, o] {
    action = [&common, o] {
      as_command("tetmesh", [&] { validate(o->tet); });
      tet_format_from_path(o->output);
      check_writable(o->output);
      if (!o->report.empty()) check_writable(o->report);
      Progress progress(common.quiet || common.json, common.progress);
      progress.begin("read mesh");
      const TriangleMesh surface = read_mesh(o->input);
      progress.end();
      progress.begin("tetrahedralize");
      TetStats st;
      TetMesh m;
      try {
        m = multi::tetrahedralize_surface(surface, o->tet, &st, progress.fraction_of("tetrahedralize"));
      } catch (const InputError& e) {  // name the file
        const std::string what = e.what();
        throw InputError(o->input + what.substr(what.find(':')));
      }
      progress.end();
      progress.begin("write volume mesh");
      write_tet_mesh(m, o->output);
      progress.end();
      nlohmann::json j = tet_json(o->tet, st);
      j["input"] = o->input;
      j["output"] = o->output;
      j["stage_seconds"] = stage_json(progress);
      if (!o->report.empty()) write_json_file(j, o->report);
      if (common.json) std::cout << j.dump(2) << '\n';
      else if (!common.quiet) std::cout << tet_text(o->output, st);
    };
  });
}

}  // namespace mpumesh::tools
