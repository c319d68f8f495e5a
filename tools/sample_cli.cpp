#include "sample_cli.h"

#include <cmath>

#include "particles/spacing_stats.h"

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

nlohmann::json sample_json(const particles::SampleOptions& o, const particles::SampleStats& st,
                           const particles::ParticleState& ps) {
  // |K| at the sampling's scale, the curvature the spacing follows (particles/sizing_field.h).
  std::vector<double> absk(ps.size());
  for (size_t i = 0; i < ps.size(); ++i)
    absk[i] = std::abs(i < st.gauss_at_scale.size() ? st.gauss_at_scale[i] : ps.curv[i].gauss);
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

}  // namespace mpumesh::tools
