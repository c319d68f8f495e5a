#include "complex_report.h"

#include <fmt/format.h>

#include "common/error.h"
#include "mesh/quality.h"
#include "report/html_report.h"
#include "report_sections.h"

namespace mpumesh::tools {
namespace {

std::string yes_no(bool b) { return b ? "yes" : "no"; }

// What the complex is and what was left out: the device, the labels skipped, the shells
// removed.
void add_complex_summary(report::HtmlPage& page, const ComplexReportInputs& in) {
  const pipeline::ComplexResult& r = *in.result;
  std::string intro = "mpumesh " + report::escape_html(MPUMESH_VERSION);
  if (!in.device.empty()) intro += "; device: " + report::escape_html(in.device);
  page.paragraph(intro);
  const multi::ComplexFigures& f = r.figures;
  page.paragraph(report::escape_html(fmt::format(
      "{}: {} {} of {} meshed as one multi-material complex of {} triangles on {} vertices; every interface between "
      "two regions (the background is region 0) is one surface, each triangle tagged with the two labels it "
      "separates.",
      in.name, r.regions.size(), r.from_mesh ? "closed parts" : "labels", in.input, r.complex.mesh.triangles.size(),
      r.complex.mesh.vertices.size())));
  for (const pipeline::SkippedLabel& s : r.labels.skipped)
    page.paragraph(report::escape_html(
        fmt::format("{} {} was skipped: {}", r.from_mesh ? "Part" : "Label", s.label, s.reason)));
  page.paragraph(report::escape_html(fmt::format(
      "Junction curves (where three or more regions meet): {} curves of {} edges, {:.1f} mm in all. Triangle pairs "
      "that cross: {}. Closed shells removed (away from the data, or thinner than the fit resolves): {}. Pieces of "
      "a label smaller than the scan resolves, merged into the neighbour they share the most area with: {} "
      "({:.2f} mm3 in all).",
      f.junction_curves, f.junction_edges, f.junction_length_mm, f.crossing_pairs, r.shells_removed, r.specks.merged,
      r.specks.volume_mm3)));
  if (!r.from_mesh)
    page.paragraph(report::escape_html(fmt::format(
        "Each label made to hold its voxels' volume: the worst label {:.2f}% off before, {:.2f}% after; the "
        "interfaces moved {:.3f} mm at most, {} vertices held for their triangles' angles, their wedges at "
        "junctions or crossings.",
        100 * r.volume_match.worst_before, 100 * r.volume_match.worst_after, r.volume_match.largest_shift_mm,
        r.volume_match.frozen)));
}

// A label's tetrahedra: how many, their volume, smallest dihedral overall, next to the
// complex and next to a junction curve (none there: "-"), mean radius ratio.
std::vector<std::string> tet_cells(const TetStats& st, int64_t label) {
  const auto angle = [](double deg) { return deg < 180 ? fmt::format("{:.2f}°", deg) : std::string("-"); };
  for (const LabelTetFigures& t : st.labels)
    if (t.label == label)
      return {fmt::format("{}", t.quality.tets), fmt::format("{:.1f} mm3", t.quality.volume_mm3),
              angle(t.quality.min_dihedral_deg), angle(t.min_dihedral_at_interfaces),
              angle(t.min_dihedral_at_junctions), fmt::format("{:.3f}", t.quality.radius_ratio_mean)};
  return std::vector<std::string>(6, "-");
}

// Per label: its boundary's triangles, enclosed volume against its reference (voxels or
// the input part), closedness, pinched vertices, pieces, wedges at junction curves (a tetrahedron there is
// no better); with a volume mesh, its tetrahedra.
void add_label_table(report::HtmlPage& page, const pipeline::ComplexResult& r) {
  const std::string against = r.from_mesh ? "input part's volume" : "voxels' volume";
  std::vector<std::string> header = {r.from_mesh ? "part" : "label", "triangles", "enclosed volume", against,
                                     "difference", "closed oriented manifold", "open edges", "pinched vertices", "pieces",
                                     "smallest wedge at junctions", "wedges under 10°"};
  if (r.volume)
    header.insert(header.end(), {"tetrahedra", "tetrahedra's volume", "smallest dihedral", "at its interfaces",
                                 "at junction curves", "mean radius ratio"});
  std::vector<std::vector<std::string>> rows;
  for (const pipeline::ComplexRegion& g : r.regions) {
    for (const multi::RegionFigures& x : r.figures.regions) {
      if (x.label != g.label) continue;
      const double diff = g.reference_volume_mm3 > 0 ? 100 * (x.volume_mm3 / g.reference_volume_mm3 - 1) : 0.0;
      std::vector<std::string> row = {fmt::format("{}", g.label),
                                      fmt::format("{}", x.triangles),
                                      fmt::format("{:.1f} mm3", x.volume_mm3),
                                      fmt::format("{:.1f} mm3", g.reference_volume_mm3),
                                      fmt::format("{:+.2f}%", diff),
                                      yes_no(x.defects == 0 && x.pinched_vertices == 0),
                                      fmt::format("{}", x.defects),
                                      fmt::format("{}", x.pinched_vertices),
                                      fmt::format("{}", x.components),
                                      x.min_wedge_deg < 360 ? fmt::format("{:.2f}°", x.min_wedge_deg) : "-",
                                      fmt::format("{}", x.wedges_under_10)};
      if (r.volume) {
        const std::vector<std::string> tets = tet_cells(r.volume->stats, g.label);
        row.insert(row.end(), tets.begin(), tets.end());
      }
      rows.push_back(row);
    }
  }
  page.heading(r.from_mesh ? "Parts" : "Labels");
  page.table(header, rows);
}

// Per interface (a, b): its triangles, area and their shape; and the whole's shape.
void add_interface_table(report::HtmlPage& page, const multi::ComplexFigures& f) {
  std::vector<std::vector<std::string>> rows;
  for (const multi::InterfaceFigures& x : f.interfaces)
    rows.push_back({fmt::format("{} | {}", x.label_a, x.label_b), fmt::format("{}", x.triangles),
                    fmt::format("{:.1f} mm2", x.area_mm2), fmt::format("{:.2f}°", x.min_angle_deg),
                    fmt::format("{:.3f}", x.mean_radius_ratio)});
  page.heading("Interfaces");
  page.table({"labels a | b", "triangles", "area", "smallest angle", "mean radius ratio"}, rows);
  page.paragraph(report::escape_html(fmt::format(
      "All triangles: smallest angle {:.2f}° ({:.2f}° away from the junction curves), mean radius ratio {:.3f}.",
      f.min_angle_deg, f.min_angle_off_junction_deg, f.mean_radius_ratio)));
}

// The complex's outside coloured by label from two sides, one with its edges.
void add_label_renders(report::HtmlPage& page, const TriangleMesh& complex, ComputeBackend& backend) {
  page.heading("The complex");
  render::RenderOptions ro;
  ro.width = 800, ro.height = 600;
  ro.color = render::ColorBy::kLabel;
  ro.view = Eigen::Vector3d(1, -1, 1).normalized();
  std::vector<report::HtmlPage::Figure> figs;
  figs.push_back({render_png(backend, complex, ro), "each label's outer boundary coloured by label, view (1,-1,1)"});
  ro.view = Eigen::Vector3d(-1, 1, 1).normalized();
  ro.wireframe = true;
  figs.push_back({render_png(backend, complex, ro), "coloured by label, view (-1,1,1), with edges"});
  page.figures(figs);
}

void add_shape_histograms(report::HtmlPage& page, const TriangleMesh& complex) {
  const TriangleShapes shapes = triangle_shapes(complex);
  page.heading("Triangle shape");
  page.svg(report::svg_histogram("Smallest angle of each triangle", "degrees",
                                 {{"complex", kReportColours[0], shapes.min_angle_deg}}, 0, 60, 30));
  page.svg(report::svg_histogram("Radius ratio 2 r_in / r_circ", "radius ratio",
                                 {{"complex", kReportColours[0], shapes.radius_ratio}}, 0, 1, 25));
}

}  // namespace

std::string build_complex_report(const ComplexReportInputs& in, ComputeBackend& backend) {
  const pipeline::ComplexResult& r = *in.result;
  if (r.complex.mesh.triangles.empty()) throw InputError(in.name + ": the complex has no triangles to report on");
  report::HtmlPage page("mpumesh report: " + in.name);
  add_complex_summary(page, in);
  add_label_table(page, r);
  add_interface_table(page, r.figures);
  add_label_renders(page, r.complex.mesh, backend);
  add_shape_histograms(page, r.complex.mesh);
  if (r.volume) add_volume_mesh(page, *r.volume);
  add_stage_times(page, in.device, in.stage_seconds);
  add_parameters(page, in.parameters);
  return page.html();
}

}  // namespace mpumesh::tools
