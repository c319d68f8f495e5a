#include "sample_cli.h"

#include <cmath>


namespace mpumesh::tools {

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
  cmd->add_option_function<double>(
         "--normal-turn", [&o](double deg) { o.normal_turn = deg * M_PI / 180; },
         "largest turn of the surface's normal across one spacing (degrees): spacing at most this over the larger "
         "principal curvature; 0: no such bound")
      ->default_str("0");
  cmd->add_option("--spacing-grade", o.spacing_grade,
                  "largest change of the target spacing per mm along the surface (0: ungraded)")
      ->capture_default_str();
  cmd->add_option(iterations_flag, o.iterations, "particle iteration cap")->capture_default_str();
  cmd->add_option("--seed", o.seed, "seed of the random choices (splits, deaths, seeding order)")->capture_default_str();
}

}  // namespace mpumesh::tools
