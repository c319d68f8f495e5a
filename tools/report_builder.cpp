#include "report_builder.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/option_names.h"
#include "mesh/quality.h"
#include "mesh/surface_attributes.h"
#include "particles/spacing_stats.h"
#include "report/report_figures.h"
#include "render/mesh_render_vk.h"
#include "render/render_scene.h"
#include "report/html_report.h"
#include "report_sections.h"

namespace mpumesh::tools {

const char* const kReportColours[5] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e"};

std::string render_png(ComputeBackend& backend, const TriangleMesh& m, render::RenderOptions ro) {
  const render::RenderScene scene = render::build_scene(m, ro);
  return render::encode_png(vk::render_image(backend, scene));
}

namespace {

// Normals and curvature: the mesh's own (from the MPU surface) or estimated.
TriangleMesh with_attributes(const TriangleMesh& m) {
  TriangleMesh out = m;
  if (out.normals.size() != out.vertices.size() || out.curvature.size() != out.vertices.size())
    estimate_mesh_curvature(out);
  return out;
}

std::string fmt_num(const nlohmann::json& j) {
  if (j.is_number_float()) return fmt::format("{:.4g}", j.get<double>());
  if (j.is_string()) return j.get<std::string>();
  return j.dump();
}

// The particle count raised because the sample was too sparse, each time.
void add_raises(report::HtmlPage& page, const std::vector<pipeline::CountRaise>& raises) {
  for (const pipeline::CountRaise& r : raises) {
    const std::string again = r.next_requested_spacing_mm > 0
                                  ? fmt::format(" at a spacing of {:.3f} mm", r.next_requested_spacing_mm)
                              : r.next_requested_particles > 0
                                  ? fmt::format(" with {} particles asked", r.next_requested_particles)
                                  : std::string(" with more particles");
    page.paragraph(report::escape_html(fmt::format(
        "The particle count was raised: {} repair points for {} particles showed too sparse a sample for the "
        "surface's thin plates, so the particles were sampled again{}.",
        r.repair_points, r.particles, again)));
  }
}

void add_optimization(report::HtmlPage& page, const OptimizeStats& o) {
  if (o.rounds <= 0) return;
  page.paragraph(report::escape_html(fmt::format(
      "Mesh optimisation: {} rounds of Delaunay flips, collapses of poor triangles' shortest edges and centroidal "
      "relaxation on the surface, with flips for smoothness in the last rounds, then moves of the poorest triangles' "
      "vertices ({} flips, {} flips for smoothness, {} collapses, {} moves, {} polishing moves, {:.2f} s): smallest "
      "angle {:.1f}° before, {:.1f}° after; triangles under 30° {:.2f}% before, {:.2f}% after; "
      "mean radius ratio {:.3f} before, {:.3f} after.",
      o.rounds, o.flips, o.smooth_flips, o.collapses, o.moves, o.polish_moves, o.seconds, o.before.min_angle_deg,
      o.after.min_angle_deg, o.before.pct_below_30, o.after.pct_below_30, o.before.radius_ratio,
      o.after.radius_ratio)));
}

void add_components(report::HtmlPage& page, const ComponentOptions& filter, const pipeline::ComponentsKept& c) {
  std::string text = fmt::format("Structures kept: {} (", c.kept);
  text += filter.largest > 0 ? fmt::format("the {} largest", filter.largest) : std::string("all");
  if (filter.min_volume_mm3 > 0) text += fmt::format(" of at least {:.1f} mm3", filter.min_volume_mm3);
  text += ")";
  text += fmt::format("; dropped {}", c.dropped.size());
  const auto thin = std::count_if(c.dropped.begin(), c.dropped.end(), [](const DroppedComponent& d) { return d.thin; });
  if (thin > 0)
    text += fmt::format(" ({} of them thinner on average than {:.3f} mm: sheets folded onto themselves, specks "
                        "under the fit's tolerance)",
                        thin, filter.min_thickness_mm);
  for (size_t i = 0; i < c.dropped.size() && i < 5; ++i)
    text += fmt::format("{} {:.1f} mm3 ({} triangles)", i == 0 ? ":" : ",", c.dropped[i].volume_mm3,
                        c.dropped[i].triangles);
  if (c.dropped.size() > 5) text += ", ...";
  page.paragraph(report::escape_html(text + "."));
}

void add_input(report::HtmlPage& page, const pipeline::InputInfo& in) {
  if (!in.volume && !in.mesh) return;
  std::vector<std::vector<std::string>> rows;
  const nlohmann::json j = input_json(in);
  for (const auto& [k, v] : j.items()) rows.push_back({k, fmt_num(v)});
  page.heading("Input");
  page.table({"", ""}, rows);
}

// Input and summary: the version and device, what run changed on its own and what it
// advises (first in the page), the input, the fit's tolerance and the particles removed
// off the data.
void add_summary(report::HtmlPage& page, const ReportRun& run) {
  std::string intro = "mpumesh " + report::escape_html(MPUMESH_VERSION);
  if (!run.device.empty()) intro += "; device: " + report::escape_html(run.device);
  page.paragraph(intro);
  if (!run.result) return;
  const pipeline::RunResult& r = *run.result;
  add_raises(page, r.raises);
  add_optimization(page, r.optimization);
  if (r.components) add_components(page, r.derived.components, *r.components);
  for (const std::string& n : r.notes) page.paragraph("Note: " + report::escape_html(spell_options(n, run.spell)));
  add_input(page, r.input);
  if (r.fit.eps > 0) {
    const std::string source = r.derived.tolerance.source.empty() ? std::string("given")
                                                                  : spell_options(r.derived.tolerance.source, run.spell);
    page.paragraph(report::escape_html(fmt::format("The fit's tolerance ε0 is {:.3f} mm: {}.", r.fit.eps, source)));
  }
  if (r.slice_phase)
    page.paragraph(report::escape_html(fmt::format(
        "Slice terraces: the mean curvature |H| at the vertices, averaged by their phase within the label map's slice "
        "period, varies by {:.2f} of its mean (a smooth surface shows under 0.2, a staircase 0.4 and more).",
        r.slice_phase->modulation)));
  if (r.sample.particles > 0 || r.sample.off_data > 0)
    page.paragraph(report::escape_html(fmt::format(
        "{} particles were removed for lying on a zero set of the fit away from every input point (a spurious "
        "sheet).",
        r.sample.off_data)));
}

// One row of figures per mesh; each mesh's per-triangle shapes, for the sections below.
std::vector<TriangleShapes> add_mesh_table(report::HtmlPage& page, const std::vector<ReportMesh>& all) {
  std::vector<TriangleShapes> shapes;
  std::vector<std::vector<std::string>> rows;
  for (const auto& rm : all) {
    QualityOptions qo;
    qo.self_intersections = false;
    const Quality q = measure_quality(*rm.mesh, qo);
    shapes.push_back(triangle_shapes(*rm.mesh));
    rows.push_back({rm.name, fmt::format("{}", rm.mesh->triangles.size()), fmt::format("{}", rm.mesh->vertices.size()),
                    q.topo.closed && q.topo.oriented ? "yes" : "no", fmt::format("{}", q.topo.genus),
                    fmt::format("{}", q.topo.components), fmt::format("{:.2f}", q.angle_min),
                    fmt::format("{:.2f}", q.pct_angle_below[2]), fmt::format("{:.3f}", q.radius_ratio_mean),
                    fmt::format("{:.2f}", q.dihedral_mean), fmt::format("{:.2f}", q.pct_area_axis_aligned)});
  }
  page.heading("Meshes");
  page.table({"mesh", "triangles", "vertices", "closed oriented manifold", "genus", "components", "min angle (deg)",
              "% triangles < 30 deg", "mean radius ratio", "mean dihedral (deg)", "% area axis-aligned"},
             rows);

  return shapes;
}

// Our mesh coloured by K, by smallest angle and by edge length.
void add_renders(report::HtmlPage& page, const TriangleMesh& ours, const std::string& k_source,
                 ComputeBackend& backend) {
  // Renders of the result.
  page.heading("The result");
  render::RenderOptions ro;
  ro.width = 800, ro.height = 600;
  ro.color = render::ColorBy::kCurvature;
  ro.view = Eigen::Vector3d(1, -1, 1).normalized();
  std::vector<report::HtmlPage::Figure> figs;
  figs.push_back({render_png(backend, ours, ro), "Gaussian curvature K (" + k_source + "), view (1,-1,1)"});
  ro.view = Eigen::Vector3d(-1, 1, 1).normalized();
  ro.wireframe = true;
  figs.push_back({render_png(backend, ours, ro), "Gaussian curvature K (" + k_source + "), view (-1,1,1), with edges"});
  page.figures(figs);
  figs.clear();
  ro.color = render::ColorBy::kMinAngle;
  ro.wireframe = true;
  ro.view = Eigen::Vector3d(-1, 1, 1).normalized();
  figs.push_back({render_png(backend, ours, ro), "smallest angle of each triangle, with edges"});
  ro.color = render::ColorBy::kEdgeLength;
  figs.push_back({render_png(backend, ours, ro), "mean edge length of each triangle (mm), with edges"});
  page.figures(figs);

}

// The same zoomed region of every mesh (the paper's Fig. 4).
void add_region(report::HtmlPage& page, const TriangleMesh& ours, const std::vector<ReportMesh>& all,
                const std::vector<TriangleShapes>& shapes, ComputeBackend& backend) {
  const report::ViewRegion reg = report::pick_region(ours);
  page.heading("The same region, side by side (the paper's Fig. 4)");
  page.paragraph(report::escape_html(fmt::format(
      "Region: the ball of radius {:.1f} mm at ({:.1f}, {:.1f}, {:.1f}) mm, where our mesh's integrated |K| is "
      "largest, seen along its mean normal ({:.2f}, {:.2f}, {:.2f}); triangles coloured by their smallest angle.",
      reg.radius, reg.centre.x(), reg.centre.y(), reg.centre.z(), reg.view.x(), reg.view.y(), reg.view.z())));
  std::vector<report::HtmlPage::Figure> figs;
  for (size_t i = 0; i < all.size(); ++i) {
    render::RenderOptions zo;
    zo.width = zo.height = 520;
    zo.view = reg.view;
    zo.zoom = std::make_pair(reg.centre, reg.radius);
    zo.wireframe = true;
    zo.color = render::ColorBy::kMinAngle;
    zo.title = all[i].name;
    const auto& s = shapes[i].min_angle_deg;
    const double below30 = 100.0 * double(std::count_if(s.begin(), s.end(), [](double a) { return a < 30; })) /
                           double(std::max<size_t>(s.size(), 1));
    figs.push_back({render_png(backend, *all[i].mesh, zo),
                    fmt::format("{}: {} triangles, smallest angle {:.1f} deg, {:.1f}% under 30 deg", all[i].name,
                                all[i].mesh->triangles.size(), *std::min_element(s.begin(), s.end()), below30)});
  }
  page.figures(figs);

}

void add_histograms(report::HtmlPage& page, const std::vector<ReportMesh>& all,
                    const std::vector<TriangleShapes>& shapes) {
  page.heading("Triangle shape");
  std::vector<report::Series> angle, ratio;
  for (size_t i = 0; i < all.size(); ++i) {
    angle.push_back({all[i].name, kReportColours[i % 5], shapes[i].min_angle_deg});
    ratio.push_back({all[i].name, kReportColours[i % 5], shapes[i].radius_ratio});
  }
  page.svg(report::svg_histogram("Smallest angle of each triangle", "degrees", angle, 0, 60, 30));
  page.svg(report::svg_histogram("Radius ratio 2 r_in / r_circ", "radius ratio", ratio, 0, 1, 25));

}

// Spacing (mean incident edge length) against |K| at the sampling's scale on our mesh,
// and the particles' figures from the run.
void add_adaptivity(report::HtmlPage& page, const TriangleMesh& ours, const pipeline::RunResult* run,
                    const std::string& k_source) {
  const report::VertexAdaptivity a = report::vertex_adaptivity(ours);
  std::vector<double> sx, sy;
  const size_t stride = std::max<size_t>(1, a.abs_gauss.size() / 4000);
  for (size_t i = 0; i < a.abs_gauss.size(); i += stride) sx.push_back(a.abs_gauss[i]), sy.push_back(a.spacing[i]);
  page.heading("Adaptivity");
  page.paragraph(report::escape_html(fmt::format(
      "Spacing at each vertex of our mesh (mean length of its edges) against |K| there ({}), averaged over the "
      "vertices within that spacing (the curvature at the sampling's scale, which the spacing follows); rank "
      "correlation {:.3f} over {} vertices ({} drawn).",
      k_source, a.rank_correlation, a.abs_gauss.size(), sx.size())));
  page.svg(report::svg_scatter("Vertex spacing against Gaussian curvature", "|K| (1/mm^2, log scale)",
                               "spacing (mm)", sx, sy, true));
  // The particles whose spacing their curvature sets, apart from those that a plate's
  // thickness sets: thin plates are flat and sampled densely, which can turn the
  // correlation above positive.
  if (!run || !run->spacing) return;
  const particles::SpacingSummary& sp = *run->spacing;
  const double n_all = double(run->sample.particles), n_curved = double(sp.curved_particles);
  const double rho_curved = sp.curved.rank_correlation, ratio_curved = sp.curved.ratio;
  if (!std::isfinite(rho_curved) || !std::isfinite(ratio_curved)) return;
  const double rho_all = sp.all.rank_correlation, ratio_all = sp.all.ratio;
  page.paragraph(report::escape_html(
      fmt::format("Of the {:.0f} particles, {:.0f} have their spacing set by the local thickness of a plate or gap "
                  "(the particles must sample both of its sides), the other {:.0f} by the curvature. Over those, "
                  "the spacing against |K| at the sampling's scale has rank correlation {:.3f}, and the median "
                  "spacing where |K| is in its highest tenth is {:.2f} times that in its lowest",
                  n_all, n_all - n_curved, n_curved, rho_curved, ratio_curved) +
      (std::isfinite(rho_all) && std::isfinite(ratio_all)
           ? fmt::format("; over all particles {:.3f} and {:.2f} times.", rho_all, ratio_all)
           : std::string("."))));
}

}  // namespace

// The volume mesh's figures (run --volume) and a histogram of its dihedral angles.
void add_volume_mesh(report::HtmlPage& page, const pipeline::VolumeMeshResult& v) {
  const TetQuality& q = v.stats.quality;
  page.heading("Volume mesh");
  page.paragraph(report::escape_html(fmt::format(
      "{} linear tetrahedra on {} nodes in {} regions (TetGen 1.5, {:.2f} s), the surface's triangles their "
      "boundary ({} points added on it); edges up to {:.2f} mm inside, growing by {:.2f} mm per mm from the "
      "surface.",
      q.tets, q.nodes, q.regions, v.stats.seconds, v.stats.boundary_points, v.stats.size, v.options.grading)));
  page.table({"smallest dihedral", "largest dihedral", "tets under 10°", "under 15°", "mean radius ratio",
              "inverted", "volume", "surface's volume"},
             {{fmt::format("{:.2f}°", q.min_dihedral_deg), fmt::format("{:.2f}°", q.max_dihedral_deg),
               fmt::format("{:.3f}%", q.pct_min_dihedral_below_10),
               fmt::format("{:.3f}%", q.pct_min_dihedral_below_15), fmt::format("{:.3f}", q.radius_ratio_mean),
               fmt::format("{}", q.inverted), fmt::format("{:.1f} mm3", q.volume_mm3),
               fmt::format("{:.1f} mm3 ({:+.4f}%)", v.stats.surface_volume, v.stats.volume_difference_pct())}});
  // The histogram's counts as values at the bins' centres, scaled to at most 20,000 (a bin
  // that holds any keeps one, so that a few slivers show).
  double total = 0;
  for (const int64_t c : q.dihedral_histogram) total += double(c);
  const double scale = total > 20000 ? 20000 / total : 1.0;
  report::Series s{"dihedral angles", kReportColours[0], {}};
  for (size_t b = 0; b < q.dihedral_histogram.size(); ++b) {
    const double c = double(q.dihedral_histogram[b]);
    const int64_t n = c > 0 ? std::max<int64_t>(1, std::llround(c * scale)) : 0;
    s.values.insert(s.values.end(), size_t(n), 5.0 * double(b) + 2.5);
  }
  page.svg(report::svg_histogram("Dihedral angles of the tetrahedra", "degrees", {s}, 0, 180, 36));
}

void add_stage_times(report::HtmlPage& page, const std::string& device,
                     const std::vector<std::pair<std::string, double>>& stage_seconds) {
  if (stage_seconds.empty()) return;
  std::vector<std::pair<std::string, double>> bars;
  for (const auto& stage : stage_seconds) {
    auto it = std::find_if(bars.begin(), bars.end(), [&](const auto& b) { return b.first == stage.first; });
    if (it == bars.end()) bars.push_back(stage);
    else it->second += stage.second;
  }
  std::sort(bars.begin(), bars.end());
  page.heading("Time by stage");
  page.svg(report::svg_bars("Stage times on " + device, bars, "s"));
}

void add_parameters(report::HtmlPage& page, const nlohmann::json& params) {
  if (params.empty()) return;
  page.heading("Parameters and stage figures");
  page.pre(params.dump(2));
}

nlohmann::json report_parameters(const nlohmann::json& run) {
  nlohmann::json params = nlohmann::json::object();
  for (const char* key : {"segmentation", "fit", "particles", "triangulation", "optimization"})
    if (run.is_object() && run.contains(key)) {
      params[key] = run[key];
      if (params[key].is_object()) params[key].erase("history");
    }
  return params;
}

std::string build_report(const ReportInputs& in, ComputeBackend& backend) {
  const TriangleMesh ours = with_attributes(*in.ours.mesh);
  if (ours.triangles.empty()) throw InputError(in.ours.name + ": the mesh has no triangles to report on");
  const bool mpu_curvature = in.ours.mesh->curvature.size() == in.ours.mesh->vertices.size();
  const std::string k_source = mpu_curvature ? "from the MPU surface" : "estimated from the mesh";
  const pipeline::RunResult* run = in.run.result;
  report::HtmlPage page("mpumesh report: " + in.ours.name);
  add_summary(page, in.run);
  std::vector<ReportMesh> all = {in.ours};
  for (const auto& b : in.baselines) all.push_back(b);
  const std::vector<TriangleShapes> shapes = add_mesh_table(page, all);
  add_renders(page, ours, k_source, backend);
  add_region(page, ours, all, shapes, backend);
  add_histograms(page, all, shapes);
  add_adaptivity(page, ours, run, k_source);
  if (run && run->volume) add_volume_mesh(page, *run->volume);
  add_stage_times(page, in.run.device, in.run.stage_seconds);
  add_parameters(page, in.run.parameters);
  return page.html();
}

}  // namespace mpumesh::tools
