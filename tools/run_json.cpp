#include "run_json.h"

#include <cmath>

#include "cli_util.h"
#include "common/error.h"
#include "common/option_names.h"
#include "common/memory.h"
#include "component_cli.h"
#include "mpu_cli.h"
#include "seg_cli.h"
#include "tet_cli.h"

namespace mpumesh::tools {
namespace {

nlohmann::json spacing_json(const particles::SpacingStats& x) {
  return nlohmann::json{{"mean_mm", x.mean},
                        {"cv", x.cv},
                        {"median_high_K_mm", x.high_k_median},
                        {"median_low_K_mm", x.low_k_median},
                        {"high_over_low", x.ratio},
                        {"rank_correlation_with_abs_K", x.rank_correlation}};
}

nlohmann::json raises_json(const std::vector<pipeline::CountRaise>& raises) {
  nlohmann::json out = nlohmann::json::array();
  for (const pipeline::CountRaise& c : raises)
    out.push_back({{"requested_particles", c.requested_particles},
                   {"requested_spacing_mm", c.requested_spacing_mm},
                   {"asked_particles", c.asked_particles},
                   {"particles", c.particles},
                   {"repair_points", c.repair_points},
                   {"next_requested_particles", c.next_requested_particles},
                   {"next_requested_spacing_mm", c.next_requested_spacing_mm}});
  return out;
}

nlohmann::json shape_json(const ShapeFigures& f) {
  return {{"min_angle_deg", f.min_angle_deg}, {"pct_below_30_deg", f.pct_below_30}, {"radius_ratio_mean", f.radius_ratio}};
}

nlohmann::json optimization_json(const OptimizeStats& op) {
  return {{"rounds", op.rounds},
          {"flips", op.flips},
          {"smoothing_flips", op.smooth_flips},
          {"moves", op.moves},
          {"collapses", op.collapses},
          {"polish_moves", op.polish_moves},
          {"retries", op.retries},
          {"frozen", op.frozen},
          {"seconds", op.seconds},
          {"before", shape_json(op.before)},
          {"after", shape_json(op.after)}};
}

nlohmann::json fit_section(const pipeline::RunResult& r, const OptionSpelling& spell) {
  const pipeline::Derived& d = r.derived;
  nlohmann::json j = fit_json(d.fit, r.fit);
  j["eps_source"] = spell_options(d.tolerance.source, spell);
  if (d.tolerance.noise > 0) j["point_noise_mm"] = d.tolerance.noise;
  if (d.curvature_scale_mm > 0) j["curvature_scale_mm"] = d.curvature_scale_mm;
  return j;
}

nlohmann::json particles_section(const pipeline::RunResult& r) {
  nlohmann::json j = sample_json(r.derived.sample, r.sample, r.spacing ? &*r.spacing : nullptr);
  j["kernel_ms"] = r.particle_kernel_ms;
  j["count_raises"] = raises_json(r.raises);
  return j;
}

std::vector<std::string> spelled(const std::vector<std::string>& lines, const OptionSpelling& spell) {
  std::vector<std::string> out;
  for (const std::string& l : lines) out.push_back(spell_options(l, spell));
  return out;
}

}  // namespace

nlohmann::json input_json(const pipeline::InputInfo& in) {
  if (in.mesh) {
    nlohmann::json j = {{"path", in.path},
                        {"kind", "mesh"},
                        {"vertices", in.mesh->vertices},
                        {"triangles", in.mesh->triangles}};
    if (in.mesh->parts > 0) j["parts"] = in.mesh->parts;  // not counted for a marching-cubes surface
    return j;
  }
  const pipeline::VolumeInput v = in.volume.value_or(pipeline::VolumeInput{});
  return {{"path", in.path},
          {"kind", "volume"},
          {"dims", v.dims},
          {"spacing_mm", {v.spacing.x(), v.spacing.y(), v.spacing.z()}},
          {"modality", v.modality},
          {"read_notes", v.read_notes}};
}

nlohmann::json sample_json(const particles::SampleOptions& o, const particles::SampleStats& st,
                           const particles::SpacingSummary* spacing) {
  nlohmann::json hist = nlohmann::json::array();
  for (const auto& h : st.history)
    hist.push_back({{"iteration", h.iteration}, {"count", h.count}, {"births", h.births}, {"deaths", h.deaths},
                    {"mean_energy", h.mean_energy}, {"mean_move", h.mean_move}});
  nlohmann::json j = {
      {"particles", st.particles},
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
      {"seconds", {{"seed", st.seconds_seed}, {"iterate", st.seconds_iterate}, {"population", st.seconds_population}}},
      {"history", hist}};
  if (spacing) {
    j["spacing"] = spacing_json(spacing->all);
    j["spacing_where_curvature_sets"] = spacing_json(spacing->curved);
    j["spacing_where_curvature_sets"]["particles"] = spacing->curved_particles;
  }
  return j;
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

nlohmann::json run_json(const pipeline::RunResult& r, const RunReportContext& ctx) {
  nlohmann::json j;
  j["input"] = input_json(r.input);
  if (!r.input.mesh) j["segmentation"] = segment_json(r.derived.segment, r.segmentation);
  j["points"] = r.points;
  j["fit"] = fit_section(r, ctx.spell);
  j["particles"] = particles_section(r);
  j["triangulation"] = triangulation_json(r.triangulation);
  j["optimization"] = optimization_json(r.optimization);
  if (ctx.backend) {
    j["backend"] = backend_json(*ctx.backend);
    j["kernel_ms"] = ctx.backend->backend->kernel_ms();
  }
  j["output"] = ctx.output;
  j["vertices"] = r.mesh.vertices.size();
  j["triangles"] = r.mesh.triangles.size();
  if (r.components)
    j["components_filter"] = components_json(r.derived.components, r.components->kept, r.components->dropped);
  if (r.volume) {
    j["volume_mesh"] = tet_json(r.volume->options, r.volume->stats);
    j["volume_mesh"]["output"] = ctx.volume_output;
  }
  if (r.quality) j["quality"] = quality_to_json(*r.quality);
  if (r.slice_phase)
    j["slice_phase"] = {{"modulation", r.slice_phase->modulation},
                        {"mean_abs_h_per_mm", r.slice_phase->mean_abs_h},
                        {"bin_mean_abs_h_per_mm", r.slice_phase->bin_mean_abs_h},
                        {"bin_vertices", r.slice_phase->bin_vertices}};
  j["notes"] = spelled(r.notes, ctx.spell);
  j["version"] = MPUMESH_VERSION;
  return j;
}

nlohmann::json memory_json(const pipeline::RunResult& r) {
  return {{"estimate_gib", double(r.derived.memory_estimate) / double(1ull << 30)},
          {"available_gib", double(available_memory_bytes()) / double(1ull << 30)},
          {"peak_rss_gib", double(peak_rss_bytes()) / double(1ull << 30)},
          {"malloc_huge_pages", malloc_huge_pages()}};
}

nlohmann::json stage_seconds_json(const std::vector<std::pair<std::string, double>>& pipeline_stages,
                                  const Progress& own) {
  nlohmann::json s = nlohmann::json::object();
  for (const auto* list : {&pipeline_stages, &own.stage_seconds()})
    for (const auto& [name, sec] : *list) s[name] = s.value(name, 0.0) + sec;
  return s;
}

void add_label_json(nlohmann::json& j, const pipeline::LabelRun& run) {
  j["label"] = run.label;
  if (!run.separation) return;
  const SeparationStats& s = run.separation->stats;
  j["separation"] = {{"against_labels", run.separation->against}, {"crossings_before", s.crossings_before},
                     {"crossings_after", s.crossings_after},      {"moved_vertices", s.moved_vertices},
                     {"reverted_vertices", s.reverted_vertices},  {"rounds", s.rounds},
                     {"max_move_mm", s.max_move_mm}};
}

nlohmann::json skipped_labels_json(const std::vector<pipeline::SkippedLabel>& skipped) {
  nlohmann::json out = nlohmann::json::array();
  for (const pipeline::SkippedLabel& s : skipped)
    out.push_back({{"label", s.label}, {"voxels", s.voxels}, {"reason", s.reason}});
  return out;
}

nlohmann::json label_crossings_json(const std::vector<pipeline::LabelCrossing>& crossings) {
  nlohmann::json out = nlohmann::json::array();
  for (const pipeline::LabelCrossing& c : crossings)
    out.push_back({{"labels", {c.a, c.b}}, {"triangle_pairs", c.triangle_pairs}});
  return out;
}

}  // namespace mpumesh::tools

namespace mpumesh::tools {

nlohmann::json complex_json(const pipeline::ComplexResult& r) {
  const multi::ComplexFigures& f = r.figures;
  nlohmann::json labels = nlohmann::json::array();
  for (const pipeline::ComplexRegion& g : r.regions) {
    // A label map's labels are measured against their voxels, a mesh's parts against the
    // input parts.
    const std::string against = r.from_mesh ? "input" : "voxels";
    nlohmann::json l = {{"label", g.label}};
    if (!r.from_mesh) l["voxels"] = g.voxels;
    l[r.from_mesh ? "input_volume_mm3" : "voxel_volume_mm3"] = g.reference_volume_mm3;
    for (const multi::RegionFigures& x : f.regions)
      if (x.label == g.label)
        l.update({{"volume_mm3", x.volume_mm3},
                  {"volume_vs_" + against,
                   g.reference_volume_mm3 > 0 ? x.volume_mm3 / g.reference_volume_mm3 - 1 : 0.0},
                  {"triangles", x.triangles},
                  {"closed", x.defects == 0},
                  {"open_edges", x.defects},
                  {"components", x.components},
                  {"pinched_vertices", x.pinched_vertices},
                  {"min_wedge_deg", x.min_wedge_deg},
                  {"wedges_under_10_deg", x.wedges_under_10}});
    if (r.volume)  // the tetrahedra's volume against the same reference
      for (const LabelTetFigures& t : r.volume->stats.labels)
        if (t.label == g.label)
          l.update({{"tetrahedra", t.quality.tets},
                    {"tetrahedra_volume_mm3", t.quality.volume_mm3},
                    {"tetrahedra_volume_vs_" + against,
                     g.reference_volume_mm3 > 0 ? t.quality.volume_mm3 / g.reference_volume_mm3 - 1 : 0.0}});
    labels.push_back(l);
  }
  nlohmann::json interfaces = nlohmann::json::array();
  for (const multi::InterfaceFigures& x : f.interfaces)
    interfaces.push_back({{"labels", {x.label_a, x.label_b}},
                          {"triangles", x.triangles},
                          {"area_mm2", x.area_mm2},
                          {"min_angle_deg", x.min_angle_deg},
                          {"mean_radius_ratio", x.mean_radius_ratio}});
  const multi::ComplexSampleStats& s = r.sample;
  const multi::ComplexDelaunayStats& t = r.triangulation;
  return {{"vertices", r.complex.mesh.vertices.size()},
          {"triangles", r.complex.mesh.triangles.size()},
          {"labels", labels},
          {"interfaces", interfaces},
          {"junctions", {{"curves", f.junction_curves}, {"edges", f.junction_edges}, {"length_mm", f.junction_length_mm}}},
          {"min_angle_deg", f.min_angle_deg},
          {"min_angle_off_junctions_deg", f.min_angle_off_junction_deg},
          {"mean_radius_ratio", f.mean_radius_ratio},
          {"crossing_pairs", f.crossing_pairs},
          {"shells_removed", r.shells_removed},
          {"sample",
           {{"seeds", s.seeds},
            {"off_interface", s.off_interface},
            {"other_sampling", s.other_source},
            {"merged", s.merged},
            {"interface_particles", s.interface_particles},
            {"junction_particles", s.junction_particles},
            {"corners", s.corners},
            {"seconds", s.seconds}}},
          {"optimization",
           {{"rounds", r.optimization.rounds},
            {"flips", r.optimization.flips},
            {"moves", r.optimization.moves},
            {"min_angle_before_deg", r.optimization.min_angle_before_deg},
            {"min_angle_after_deg", r.optimization.min_angle_after_deg},
            {"reverted", r.optimization.reverted},
            {"seconds", r.optimization.seconds}}},
          {"specks", {{"merged", r.specks.merged}, {"volume_mm3", r.specks.volume_mm3}}},
          {"volume_match",
           {{"worst_error_before", r.volume_match.worst_before},
            {"worst_error_after", r.volume_match.worst_after},
            {"largest_shift_mm", r.volume_match.largest_shift_mm},
            {"frozen_vertices", r.volume_match.frozen},
            {"reverted", r.volume_match.reverted}}},
          {"triangulation",
           {{"points", t.points},
            {"repair_points", t.repair_points},
            {"repair_rounds", t.repair_rounds},
            {"refine_points", t.refine_points},
            {"refine_rounds", t.refine_rounds},
            {"trimmed_cells", t.trimmed_cells},
            {"trim_rounds", t.trim_rounds},
            {"open_edges_left", t.bad_edges},
            {"pinched_vertices_found", t.pinches_found},
            {"pinched_vertices_left", t.pinches},
            {"seconds", t.seconds}}},
          {"seconds",
           {{"labels", r.seconds_labels},
            {"union", r.seconds_union},
            {"complex", r.seconds_complex},
            {"volume_mesh", r.seconds_volume}}}};
}

nlohmann::json complex_run_json(const pipeline::ComplexResult& r, const std::string& input,
                                const RunReportContext& ctx) {
  nlohmann::json j = {{"input", input},
                      {"output", ctx.output},
                      {"complex", complex_json(r)},
                      {"meshed", r.labels.meshed},
                      {"version", MPUMESH_VERSION}};
  j["skipped"] = skipped_labels_json(r.labels.skipped);
  if (ctx.backend) {
    j["backend"] = backend_json(*ctx.backend);
    j["kernel_ms"] = ctx.backend->backend->kernel_ms();
  }
  if (r.volume) {
    j["volume_mesh"] = tet_json(r.volume->options, r.volume->stats);
    j["volume_mesh"]["output"] = ctx.volume_output;
  }
  return j;
}

}  // namespace mpumesh::tools
