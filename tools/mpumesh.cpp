// mpumesh: CT/MR volumes to smooth, closed, adaptive triangle meshes. main() parses the
// subcommand, runs it, and turns every error into one line on stderr and a non-zero exit.
// SIGINT/SIGTERM remove the temporary output files and exit with 130/143.
#include <csignal>
#include <cstdio>
#include <unistd.h>

#include "commands.h"
#include "common/error.h"
#include "common/memory.h"
#include "io/atomic_file.h"
#include "option_spelling.h"
#include "vk/vk_check.h"

namespace {

extern "C" void on_signal(int sig) {
  mpumesh::remove_pending_temporaries();
  const char msg[] = "mpumesh: interrupted, partial output removed\n";
  (void)!::write(STDERR_FILENO, msg, sizeof msg - 1);
  ::_exit(128 + sig);
}

}  // namespace

int main(int argc, char** argv) {
  mpumesh::tune_memory();
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  CLI::App app{"mpumesh: smooth, closed, adaptive triangle meshes from CT/MR volumes"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("mpumesh ") + MPUMESH_VERSION);
  mpumesh::tools::CommonOptions common;
  common.argv = argv;
  std::function<void()> action;
  mpumesh::tools::add_run_command(app, common, action);
  mpumesh::tools::add_render_command(app, common, action);
  mpumesh::tools::add_report_command(app, common, action);
  mpumesh::tools::add_segment_command(app, common, action);
  mpumesh::tools::add_points_command(app, common, action);
  mpumesh::tools::add_fit_command(app, common, action);
  mpumesh::tools::add_eval_command(app, common, action);
  mpumesh::tools::add_polygonize_command(app, common, action);
  mpumesh::tools::add_sample_command(app, common, action);
  mpumesh::tools::add_triangulate_command(app, common, action);
  mpumesh::tools::add_mc_command(app, common, action);
  mpumesh::tools::add_quality_command(app, common, action);
  mpumesh::tools::add_filter_command(app, common, action);
  mpumesh::tools::add_tetmesh_command(app, common, action);
  mpumesh::tools::add_convert_command(app, common, action);
  mpumesh::tools::add_devices_command(app, common, action);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  // Core names options by their stable names; the message spells them as this command's flags.
  const std::string command = app.get_subcommands().empty() ? "" : app.get_subcommands().front()->get_name();
  const auto message = [&](const std::exception& e) { return mpumesh::tools::cli_text(e.what(), command); };
  try {
    action();
    return 0;
  } catch (const mpumesh::InputError& e) {
    std::fprintf(stderr, "mpumesh: error: %s\n", message(e).c_str());
  } catch (const mpumesh::vk::NoVulkanDevice& e) {
    std::fprintf(stderr, "mpumesh: error: %s (use --backend cpu or auto)\n", e.what());
  } catch (const mpumesh::vk::VulkanError& e) {
    std::fprintf(stderr, "mpumesh: error: %s\n", e.what());
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "mpumesh: error: out of memory\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mpumesh: error: %s\n", message(e).c_str());
  }
  mpumesh::remove_pending_temporaries();
  return 1;
}
