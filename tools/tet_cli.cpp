#include "tet_cli.h"

#include <fmt/format.h>

namespace mpumesh::tools {

void add_tet_options(CLI::App* cmd, TetOptions& o, const std::string& prefix) {
  cmd->add_option("--" + prefix + "size", o.size,
                  "largest tetrahedron edge inside (mm); 0: four times the surface's median edge")
      ->capture_default_str();
  cmd->add_option("--" + prefix + "grading", o.grading,
                  "how fast the tetrahedra grow away from the surface: the edge length grows by at most this many mm "
                  "per mm of distance from the surface, from the surface's own spacing there")
      ->capture_default_str();
  cmd->add_flag("--" + prefix + "background", o.background,
                "the background meshed too, as label 0, in a box around the complex or the surface, larger on "
                "every side by 10% of its largest extent or the inner size, whichever is more (a surface is then "
                "label 1), for models of the surrounding tissue");
}

nlohmann::json tet_quality_json(const TetQuality& q) {
  return {{"nodes", q.nodes},
          {"tetrahedra", q.tets},
          {"regions", q.regions},
          {"boundary_triangles", q.boundary_triangles},
          {"inverted", q.inverted},
          {"volume_mm3", q.volume_mm3},
          {"min_dihedral_deg", q.min_dihedral_deg},
          {"max_dihedral_deg", q.max_dihedral_deg},
          {"pct_min_dihedral_below_10", q.pct_min_dihedral_below_10},
          {"pct_min_dihedral_below_15", q.pct_min_dihedral_below_15},
          {"radius_ratio_mean", q.radius_ratio_mean},
          {"radius_ratio_min", q.radius_ratio_min},
          {"dihedral_histogram_5deg", q.dihedral_histogram}};
}

nlohmann::json tet_json(const TetOptions& o, const TetStats& st) {
  nlohmann::json j = tet_quality_json(st.quality);
  j["engine"] = "TetGen 1.5";
  j["size_mm"] = st.size;
  j["size_asked_mm"] = o.size;
  j["grading"] = o.grading;
  j["radius_edge_bound"] = o.radius_edge;
  j["surface_points"] = st.surface_points;
  j["boundary_points_added"] = st.boundary_points;
  j["interior_points"] = st.interior_points;
  j["cavities_removed"] = st.cavities_removed;
  j["nodes_perturbed"] = st.perturbed;
  j["sliver_cavities_refilled"] = st.sliver_cavities;
  j["points_for_flat_tetrahedra"] = st.flat_tet_points;
  j["surface_volume_mm3"] = st.surface_volume;
  j["volume_difference_pct"] = st.volume_difference_pct();
  j["seconds"] = st.seconds;
  if (!st.labels.empty()) {
    j["background_meshed"] = o.background;
    j["labels"] = nlohmann::json::array();
    // The smallest dihedral angle next to the interfaces and the junction curves (null
    // where a label has none).
    auto angle = [](double a) { return a < 180 ? nlohmann::json(a) : nlohmann::json(); };
    for (const LabelTetFigures& f : st.labels) {
      nlohmann::json l = tet_quality_json(f.quality);
      l.erase("nodes");
      l.erase("regions");
      l.erase("boundary_triangles");
      l["label"] = f.label;
      l["boundary_volume_mm3"] = f.boundary_volume;
      l["min_dihedral_at_interfaces_deg"] = angle(f.min_dihedral_at_interfaces);
      l["min_dihedral_at_junctions_deg"] = angle(f.min_dihedral_at_junctions);
      j["labels"].push_back(l);
    }
  }
  return j;
}

std::string tet_quality_text(const TetQuality& q) {
  return fmt::format(
      "nodes               {}\ntetrahedra          {}\nregions             {}\n"
      "dihedral angles     min {:.2f} max {:.2f} deg; tetrahedra with one under 10 deg {:.3f}%, under 15 deg {:.3f}%\n"
      "radius ratio        mean {:.3f} min {:.3f} (3 r_in / r_circ)\n"
      "volume              {:.2f} mm3, {} inverted\n",
      q.nodes, q.tets, q.regions, q.min_dihedral_deg, q.max_dihedral_deg, q.pct_min_dihedral_below_10,
      q.pct_min_dihedral_below_15, q.radius_ratio_mean, q.radius_ratio_min, q.volume_mm3, q.inverted);
}

namespace {

// A complex's labels, a line each.
std::string tet_labels_text(const TetStats& st) {
  std::string s;
  for (const LabelTetFigures& f : st.labels) {
    const TetQuality& q = f.quality;
    s += fmt::format("label {:<13} {} tetrahedra, {:.2f} mm3 ({:+.2e} of its boundary's); dihedral min {:.2f} deg "
                     "({:.2f} next to interfaces), under 15 deg {:.3f}%; radius ratio mean {:.3f}\n",
                     f.label, q.tets, q.volume_mm3, q.volume_mm3 / f.boundary_volume - 1, q.min_dihedral_deg,
                     f.min_dihedral_at_interfaces, q.pct_min_dihedral_below_15, q.radius_ratio_mean);
  }
  return s;
}

}  // namespace

std::string tet_text(const std::string& path, const TetStats& st) {
  const TetQuality& q = st.quality;
  return fmt::format(
      "{}: {} tetrahedra, {} nodes ({} added on the surface), {} regions, {:.2f} s\n"
      "dihedral angles     min {:.2f} max {:.2f} deg; tetrahedra with one under 10 deg {:.3f}%, under 15 deg {:.3f}%\n"
      "radius ratio        mean {:.3f} min {:.3f} (3 r_in / r_circ)\n"
      "volume              {:.2f} mm3 ({:+.4f}% of the surface's {:.2f}), {} inverted\n",
      path, q.tets, q.nodes, st.boundary_points, q.regions, st.seconds, q.min_dihedral_deg, q.max_dihedral_deg,
      q.pct_min_dihedral_below_10, q.pct_min_dihedral_below_15, q.radius_ratio_mean, q.radius_ratio_min, q.volume_mm3,
      100 * (q.volume_mm3 - st.surface_volume) / st.surface_volume, st.surface_volume, q.inverted) +
         tet_labels_text(st);
}

}  // namespace mpumesh::tools
