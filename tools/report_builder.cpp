#include "report_builder.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "common/error.h"
#include "mesh/quality.h"
#include "mesh/surface_attributes.h"
#include "particles/spacing_stats.h"
#include "render/mesh_render_vk.h"
#include "render/render_scene.h"
#include "report/html_report.h"

namespace mpumesh::tools {
namespace {

const char* const kColours[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e"};

struct PerTriangle {
  std::vector<double> min_angle, radius_ratio;
};

PerTriangle per_triangle(const TriangleMesh& m) {
  PerTriangle p;
  p.min_angle.reserve(m.triangles.size());
  p.radius_ratio.reserve(m.triangles.size());
  for (const auto& t : m.triangles) {
    const auto &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    p.min_angle.push_back(triangle_min_angle_deg(a, b, c));
    p.radius_ratio.push_back(triangle_radius_ratio(a, b, c));
  }
  return p;
}

// Normals and curvature: the mesh's own (from the MPU surface) or estimated.
TriangleMesh with_attributes(const TriangleMesh& m) {
  TriangleMesh out = m;
  if (out.normals.size() != out.vertices.size() || out.curvature.size() != out.vertices.size())
    estimate_mesh_curvature(out);
  return out;
}

// The Fig. 4 region: the cell (of size r) of the mesh with the largest integrated |K|
// among cells holding at least 30 vertices of the outer surface (the farthest third from
// the centre, facing away from it: inner structures are hidden from any view); looked
// at along its mean normal.
struct Region {
  Eigen::Vector3d centre, view;
  double radius;
};

Region pick_region(const TriangleMesh& m) {
  Eigen::Vector3d lo = m.vertices[0], hi = m.vertices[0];
  for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const double r = std::max(0.04 * (hi - lo).norm(), 1e-3);
  std::vector<double> area(m.vertices.size(), 0.0);
  for (const auto& t : m.triangles) {
    const double a = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm() / 6;
    for (uint32_t i : t) area[i] += a;
  }
  struct Cell {
    double score = 0;
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::Zero();
    double weight = 0;
    int count = 0;
  };
  const Eigen::Vector3d mid = (lo + hi) / 2;
  std::vector<double> dist(m.vertices.size());
  for (size_t i = 0; i < m.vertices.size(); ++i) dist[i] = (m.vertices[i] - mid).norm();
  std::vector<double> sorted = dist;
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() * 2 / 3), sorted.end());
  const double outer = sorted[sorted.size() * 2 / 3];
  std::unordered_map<uint64_t, Cell> cells;
  for (size_t i = 0; i < m.vertices.size(); ++i) {
    const Eigen::Vector3d out = m.vertices[i] - mid;
    if (dist[i] < outer || m.normals[i].cast<double>().dot(out) < 0.5 * dist[i]) continue;
    const Eigen::Vector3d g = ((m.vertices[i] - lo) / r).array().floor();
    const uint64_t key = (uint64_t(g.x()) << 42) | (uint64_t(g.y()) << 21) | uint64_t(g.z());
    Cell& c = cells[key];
    const double w = std::abs(double(m.curvature[i][2])) * area[i];
    c.score += w;
    c.weighted += (w + 1e-12) * m.vertices[i];
    c.weight += w + 1e-12;
    c.normal += m.normals[i].cast<double>();
    ++c.count;
  }
  const Cell* best = nullptr;
  for (const auto& [k, c] : cells)
    if (c.count >= 30 && (!best || c.score > best->score)) best = &c;
  if (!best)
    for (const auto& [k, c] : cells)
      if (!best || c.count > best->count) best = &c;
  if (!best) return {mid, Eigen::Vector3d(1, -1, 1).normalized(), r};
  Region reg;
  const Eigen::Vector3d target = best->weighted / best->weight;
  size_t nearest = 0;
  for (size_t i = 1; i < m.vertices.size(); ++i)
    if ((m.vertices[i] - target).squaredNorm() < (m.vertices[nearest] - target).squaredNorm()) nearest = i;
  reg.centre = m.vertices[nearest];
  reg.view = best->normal.norm() > 0 ? Eigen::Vector3d(best->normal.normalized()) : Eigen::Vector3d(1, -1, 1).normalized();
  reg.radius = r;
  return reg;
}

std::string render_png(ComputeBackend& backend, const TriangleMesh& m, render::RenderOptions ro) {
  const render::RenderScene scene = render::build_scene(m, ro);
  return render::encode_png(vk::render_image(backend, scene));
}

std::string fmt_num(const nlohmann::json& j) {
  if (j.is_number_float()) return fmt::format("{:.4g}", j.get<double>());
  if (j.is_string()) return j.get<std::string>();
  return j.dump();
}

// Input and summary: the version and device, what run changed on its own and what it
// advises, the input, the fit's tolerance and the particles removed off the data. (A run
// report given to `mpumesh report` may be any JSON: only the expected shapes are read.)
void add_summary(report::HtmlPage& page, const nlohmann::json& run) {
  std::string intro = "mpumesh " + report::escape_html(MPUMESH_VERSION);
  if (run.contains("backend")) intro += "; device: " + report::escape_html(fmt_num(run["backend"].value("device", "")));
  page.paragraph(intro);
  // What run changed on its own, and what it advises: first in the page. (A run report
  // given to `mpumesh report` may be any JSON: only the expected shapes are read.)
  const auto count = [](const nlohmann::json& r, const char* key) {
    return r.contains(key) && r[key].is_number_integer() ? r[key].get<int64_t>() : int64_t(0);
  };
  if (run.is_object() && run.contains("particles") && run["particles"].is_object() &&
      run["particles"].contains("count_raises") && run["particles"]["count_raises"].is_array())
    for (const auto& r : run["particles"]["count_raises"])
      if (r.is_object()) {
        const double spacing = r.contains("next_requested_spacing_mm") && r["next_requested_spacing_mm"].is_number()
                                   ? r["next_requested_spacing_mm"].get<double>()
                                   : 0.0;
        const int64_t next = count(r, "next_requested_particles");
        const std::string again = spacing > 0 ? fmt::format(" at a spacing of {:.3f} mm", spacing)
                                  : next > 0  ? fmt::format(" with {} particles asked", next)
                                              : std::string(" with more particles");
        page.paragraph(report::escape_html(fmt::format(
            "The particle count was raised: {} repair points for {} particles showed too sparse a sample for the "
            "surface's thin plates, so the particles were sampled again{}.",
            count(r, "repair_points"), count(r, "particles"), again)));
      }
  if (run.is_object() && run.contains("optimization") && run["optimization"].is_object() &&
      count(run["optimization"], "rounds") > 0) {
    const auto& o = run["optimization"];
    const auto figure = [](const nlohmann::json& part, const char* key) {
      return part.is_object() && part.contains(key) && part[key].is_number() ? part[key].get<double>() : NAN;
    };
    const nlohmann::json none = nlohmann::json::object();
    const auto& b = o.contains("before") ? o["before"] : none;
    const auto& a = o.contains("after") ? o["after"] : none;
    page.paragraph(report::escape_html(fmt::format(
        "Mesh optimisation: {} rounds of Delaunay flips, collapses of poor triangles' shortest edges and centroidal "
        "relaxation on the surface, with flips for smoothness in the last rounds, then moves of the poorest triangles' "
        "vertices ({} flips, {} flips for smoothness, {} collapses, {} moves, {} polishing moves, {:.2f} s): smallest "
        "angle {:.1f}° before, {:.1f}° after; triangles under 30° {:.2f}% before, {:.2f}% after; "
        "mean radius ratio {:.3f} before, {:.3f} after.",
        count(o, "rounds"), count(o, "flips"), count(o, "smoothing_flips"), count(o, "collapses"), count(o, "moves"),
        count(o, "polish_moves"), figure(o, "seconds"), figure(b, "min_angle_deg"),
        figure(a, "min_angle_deg"), figure(b, "pct_below_30_deg"), figure(a, "pct_below_30_deg"),
        figure(b, "radius_ratio_mean"), figure(a, "radius_ratio_mean"))));
  }
  if (run.is_object() && run.contains("components_filter") && run["components_filter"].is_object()) {
    const auto& c = run["components_filter"];
    std::string text = fmt::format("Structures kept: {} (", count(c, "kept"));
    text += count(c, "largest") > 0 ? fmt::format("the {} largest", count(c, "largest")) : std::string("all");
    if (c.contains("min_volume_mm3") && c["min_volume_mm3"].is_number() && c["min_volume_mm3"].get<double>() > 0)
      text += fmt::format(" of at least {:.1f} mm3", c["min_volume_mm3"].get<double>());
    text += ")";
    if (c.contains("dropped") && c["dropped"].is_array()) {
      text += fmt::format("; dropped {}", c["dropped"].size());
      for (size_t i = 0; i < c["dropped"].size() && i < 5; ++i) {
        const auto& d = c["dropped"][i];
        if (d.is_object() && d.contains("volume_mm3") && d["volume_mm3"].is_number())
          text += fmt::format("{} {:.1f} mm3 ({} triangles)", i == 0 ? ":" : ",", d["volume_mm3"].get<double>(),
                              count(d, "triangles"));
      }
      if (c["dropped"].size() > 5) text += ", ...";
    }
    page.paragraph(report::escape_html(text + "."));
  }
  if (run.is_object() && run.contains("notes") && run["notes"].is_array())
    for (const auto& n : run["notes"])
      if (n.is_string()) page.paragraph("Note: " + report::escape_html(n.get<std::string>()));
  if (run.contains("input")) {
    std::vector<std::vector<std::string>> rows;
    for (const auto& [k, v] : run["input"].items()) rows.push_back({k, fmt_num(v)});
    page.heading("Input");
    page.table({"", ""}, rows);
  }
  if (run.contains("fit") && run["fit"].is_object() && run["fit"].contains("eps_mm")) {
    const auto& f = run["fit"];
    page.paragraph(report::escape_html(
        fmt::format("The fit's tolerance ε0 is {:.3f} mm: {}.", f["eps_mm"].get<double>(),
                    f.contains("eps_source") ? f["eps_source"].get<std::string>() : std::string("given"))));
  }
  if (run.contains("particles") && run["particles"].is_object() && run["particles"].contains("off_data_removed"))
    page.paragraph(report::escape_html(fmt::format(
        "{} particles were removed for lying on a zero set of the fit away from every input point (a spurious "
        "sheet).",
        run["particles"]["off_data_removed"].get<int64_t>())));
}

// One row of figures per mesh; each mesh's per-triangle shapes, for the sections below.
std::vector<PerTriangle> add_mesh_table(report::HtmlPage& page, const std::vector<ReportMesh>& all) {
  std::vector<PerTriangle> shapes;
  std::vector<std::vector<std::string>> rows;
  for (const auto& rm : all) {
    QualityOptions qo;
    qo.self_intersections = false;
    const Quality q = measure_quality(*rm.mesh, qo);
    shapes.push_back(per_triangle(*rm.mesh));
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
                const std::vector<PerTriangle>& shapes, ComputeBackend& backend) {
  const Region reg = pick_region(ours);
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
    const auto& s = shapes[i].min_angle;
    const double below30 = 100.0 * double(std::count_if(s.begin(), s.end(), [](double a) { return a < 30; })) /
                           double(std::max<size_t>(s.size(), 1));
    figs.push_back({render_png(backend, *all[i].mesh, zo),
                    fmt::format("{}: {} triangles, smallest angle {:.1f} deg, {:.1f}% under 30 deg", all[i].name,
                                all[i].mesh->triangles.size(), *std::min_element(s.begin(), s.end()), below30)});
  }
  page.figures(figs);

}

void add_histograms(report::HtmlPage& page, const std::vector<ReportMesh>& all,
                    const std::vector<PerTriangle>& shapes) {
  page.heading("Triangle shape");
  std::vector<report::Series> angle, ratio;
  for (size_t i = 0; i < all.size(); ++i) {
    angle.push_back({all[i].name, kColours[i % 5], shapes[i].min_angle});
    ratio.push_back({all[i].name, kColours[i % 5], shapes[i].radius_ratio});
  }
  page.svg(report::svg_histogram("Smallest angle of each triangle", "degrees", angle, 0, 60, 30));
  page.svg(report::svg_histogram("Radius ratio 2 r_in / r_circ", "radius ratio", ratio, 0, 1, 25));

}

// Spacing (mean incident edge length) against |K| at the sampling's scale on our mesh,
// and the particles' figures from run's report.
void add_adaptivity(report::HtmlPage& page, const TriangleMesh& ours, const nlohmann::json& run,
                    const std::string& k_source) {
  const std::vector<double> gauss = gauss_at_mesh_scale(ours), edge = mean_edge_lengths(ours);
  std::vector<double> absk, spacing;
  for (size_t i = 0; i < ours.vertices.size(); ++i)
    if (edge[i] > 0) absk.push_back(std::abs(gauss[i])), spacing.push_back(edge[i]);
  const double rho = particles::rank_correlation(absk, spacing);
  std::vector<double> sx, sy;
  const size_t stride = std::max<size_t>(1, absk.size() / 4000);
  for (size_t i = 0; i < absk.size(); i += stride) sx.push_back(absk[i]), sy.push_back(spacing[i]);
  page.heading("Adaptivity");
  page.paragraph(report::escape_html(fmt::format(
      "Spacing at each vertex of our mesh (mean length of its edges) against |K| there ({}), averaged over the "
      "vertices within that spacing (the curvature at the sampling's scale, which the spacing follows); rank "
      "correlation {:.3f} over {} vertices ({} drawn).",
      k_source, rho, absk.size(), sx.size())));
  page.svg(report::svg_scatter("Vertex spacing against Gaussian curvature", "|K| (1/mm^2, log scale)",
                               "spacing (mm)", sx, sy, true));
  // The particles whose spacing their curvature sets, apart from those that a plate's
  // thickness sets (run's JSON report; only the expected shapes are read): thin plates
  // are flat and sampled densely, which can turn the correlation above positive.
  const auto member = [](const nlohmann::json& r, const char* key) -> const nlohmann::json* {
    return r.is_object() && r.contains(key) ? &r[key] : nullptr;
  };
  const auto number = [](const nlohmann::json* r, const char* key) {
    return r && r->is_object() && r->contains(key) && (*r)[key].is_number() ? (*r)[key].get<double>() : NAN;
  };
  const nlohmann::json* p = member(run, "particles");
  const nlohmann::json* curved = p ? member(*p, "spacing_where_curvature_sets") : nullptr;
  const nlohmann::json* every = p ? member(*p, "spacing") : nullptr;
  const double n_all = number(p, "particles"), n_curved = number(curved, "particles");
  const double rho_curved = number(curved, "rank_correlation_with_abs_K"), ratio_curved = number(curved, "high_over_low");
  if (std::isfinite(n_all) && std::isfinite(n_curved) && std::isfinite(rho_curved) && std::isfinite(ratio_curved)) {
    const double rho_all = number(every, "rank_correlation_with_abs_K"), ratio_all = number(every, "high_over_low");
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

}

// The volume mesh's figures (run --volume) and a histogram of its dihedral angles.
void add_volume_mesh(report::HtmlPage& page, const nlohmann::json& run) {
  if (!run.is_object() || !run.contains("volume_mesh") || !run["volume_mesh"].is_object()) return;
  const auto& v = run["volume_mesh"];
  const auto num = [&](const char* key) { return v.contains(key) && v[key].is_number() ? v[key].get<double>() : NAN; };
  page.heading("Volume mesh");
  page.paragraph(report::escape_html(fmt::format(
      "{:.0f} linear tetrahedra on {:.0f} nodes in {:.0f} regions ({}, {:.2f} s), the surface's triangles their "
      "boundary ({:.0f} points added on it); edges up to {:.2f} mm inside, growing by {:.2f} mm per mm from the "
      "surface.",
      num("tetrahedra"), num("nodes"), num("regions"), fmt_num(v.value("engine", "")), num("seconds"),
      num("boundary_points_added"), num("size_mm"), num("grading"))));
  page.table({"smallest dihedral", "largest dihedral", "tets under 10°", "under 15°", "mean radius ratio",
              "inverted", "volume", "surface's volume"},
             {{fmt::format("{:.2f}°", num("min_dihedral_deg")), fmt::format("{:.2f}°", num("max_dihedral_deg")),
               fmt::format("{:.3f}%", num("pct_min_dihedral_below_10")),
               fmt::format("{:.3f}%", num("pct_min_dihedral_below_15")), fmt::format("{:.3f}", num("radius_ratio_mean")),
               fmt::format("{:.0f}", num("inverted")), fmt::format("{:.1f} mm3", num("volume_mm3")),
               fmt::format("{:.1f} mm3 ({:+.4f}%)", num("surface_volume_mm3"), num("volume_difference_pct"))}});
  // The histogram's counts as values at the bins' centres, scaled to at most 20,000 (a bin
  // that holds any keeps one, so that a few slivers show).
  if (!v.contains("dihedral_histogram_5deg") || !v["dihedral_histogram_5deg"].is_array()) return;
  const auto& h = v["dihedral_histogram_5deg"];
  double total = 0;
  for (const auto& c : h) total += c.is_number() ? c.get<double>() : 0;
  const double scale = total > 20000 ? 20000 / total : 1.0;
  report::Series s{"dihedral angles", kColours[0], {}};
  for (size_t b = 0; b < h.size(); ++b) {
    const double c = h[b].is_number() ? h[b].get<double>() : 0;
    const int64_t n = c > 0 ? std::max<int64_t>(1, std::llround(c * scale)) : 0;
    s.values.insert(s.values.end(), size_t(n), 5.0 * double(b) + 2.5);
  }
  page.svg(report::svg_histogram("Dihedral angles of the tetrahedra", "degrees", {s}, 0, 180, 36));
}

void add_stage_times(report::HtmlPage& page, const nlohmann::json& run) {
  if (run.contains("stage_seconds")) {
    std::vector<std::pair<std::string, double>> bars;
    for (const auto& [k, v] : run["stage_seconds"].items())
      if (v.is_number()) bars.push_back({k, v.get<double>()});
    const std::string device = run.contains("backend") ? fmt_num(run["backend"].value("device", "")) : "";
    page.heading("Time by stage");
    page.svg(report::svg_bars("Stage times on " + device, bars, "s"));
  }

}

void add_parameters(report::HtmlPage& page, const nlohmann::json& run) {
  nlohmann::json params = nlohmann::json::object();
  for (const char* key : {"segmentation", "fit", "particles", "triangulation", "optimization"})
    if (run.contains(key)) {
      params[key] = run[key];
      if (params[key].is_object()) params[key].erase("history");
    }
  if (!params.empty()) {
    page.heading("Parameters and stage figures");
    page.pre(params.dump(2));
  }
}

}  // namespace

std::string build_report(const ReportInputs& in, ComputeBackend& backend) {
  const TriangleMesh ours = with_attributes(*in.ours.mesh);
  if (ours.triangles.empty()) throw InputError(in.ours.name + ": the mesh has no triangles to report on");
  const bool mpu_curvature = in.ours.mesh->curvature.size() == in.ours.mesh->vertices.size();
  const std::string k_source = mpu_curvature ? "from the MPU surface" : "estimated from the mesh";
  report::HtmlPage page("mpumesh report: " + in.ours.name);
  add_summary(page, in.run);
  std::vector<ReportMesh> all = {in.ours};
  for (const auto& b : in.baselines) all.push_back(b);
  const std::vector<PerTriangle> shapes = add_mesh_table(page, all);
  add_renders(page, ours, k_source, backend);
  add_region(page, ours, all, shapes, backend);
  add_histograms(page, all, shapes);
  add_adaptivity(page, ours, in.run, k_source);
  add_volume_mesh(page, in.run);
  add_stage_times(page, in.run);
  add_parameters(page, in.run);
  return page.html();
}

}  // namespace mpumesh::tools
