// read_run_json (run_json.h): the parts of a run's JSON report that the HTML page shows,
// back into the typed summary. A report given to `mpumesh report` may be any JSON: each
// part is read where it has the shape run_json writes, and passed over otherwise.
#include <cmath>

#include "run_json.h"

namespace mpumesh::tools {
namespace {

using nlohmann::json;

const json* member(const json& j, const char* key) { return j.is_object() && j.contains(key) ? &j[key] : nullptr; }

double number(const json* j, const char* key, double otherwise = NAN) {
  const json* v = j ? member(*j, key) : nullptr;
  return v && v->is_number() ? v->get<double>() : otherwise;
}

int64_t count(const json* j, const char* key) {
  const json* v = j ? member(*j, key) : nullptr;
  return v && v->is_number_integer() ? v->get<int64_t>() : 0;
}

std::string text(const json* j, const char* key) {
  const json* v = j ? member(*j, key) : nullptr;
  return v && v->is_string() ? v->get<std::string>() : std::string();
}

pipeline::InputInfo read_input(const json& j) {
  pipeline::InputInfo in;
  in.path = text(&j, "path");
  if (text(&j, "kind") == "mesh") {
    in.mesh = pipeline::MeshInput{size_t(count(&j, "vertices")), size_t(count(&j, "triangles"))};
    return in;
  }
  pipeline::VolumeInput v;
  if (const json* dims = member(j, "dims"); dims && dims->is_array() && dims->size() == 3)
    for (size_t k = 0; k < 3; ++k) v.dims[k] = (*dims)[k].is_number_integer() ? (*dims)[k].get<int64_t>() : 0;
  if (const json* sp = member(j, "spacing_mm"); sp && sp->is_array() && sp->size() == 3)
    for (size_t k = 0; k < 3; ++k) v.spacing[Eigen::Index(k)] = (*sp)[k].is_number() ? (*sp)[k].get<double>() : 0.0;
  v.modality = text(&j, "modality");
  if (const json* notes = member(j, "read_notes"); notes && notes->is_array())
    for (const json& n : *notes)
      if (n.is_string()) v.read_notes.push_back(n.get<std::string>());
  in.volume = v;
  return in;
}

ShapeFigures read_shape(const json* j) {
  return {number(j, "min_angle_deg"), number(j, "pct_below_30_deg"), number(j, "radius_ratio_mean")};
}

void read_optimization(const json& o, OptimizeStats& op) {
  op.rounds = int(count(&o, "rounds"));
  op.flips = count(&o, "flips");
  op.smooth_flips = count(&o, "smoothing_flips");
  op.moves = count(&o, "moves");
  op.collapses = count(&o, "collapses");
  op.polish_moves = count(&o, "polish_moves");
  op.seconds = number(&o, "seconds");
  op.before = read_shape(member(o, "before"));
  op.after = read_shape(member(o, "after"));
}

void read_components(const json& c, pipeline::RunResult& r) {
  r.derived.components.largest = count(&c, "largest");
  r.derived.components.min_volume_mm3 = number(&c, "min_volume_mm3", 0.0);
  pipeline::ComponentsKept kept;
  kept.kept = count(&c, "kept");
  if (const json* dropped = member(c, "dropped"); dropped && dropped->is_array())
    for (const json& d : *dropped) {
      if (!d.is_object() || !member(d, "volume_mm3") || !d["volume_mm3"].is_number()) continue;
      DroppedComponent x;
      x.volume_mm3 = d["volume_mm3"].get<double>();
      x.triangles = count(&d, "triangles");
      x.vertices = count(&d, "vertices");
      kept.dropped.push_back(x);
    }
  r.components = kept;
}

particles::SpacingStats read_spacing(const json* j) {
  particles::SpacingStats s;
  s.mean = number(j, "mean_mm");
  s.cv = number(j, "cv");
  s.high_k_median = number(j, "median_high_K_mm");
  s.low_k_median = number(j, "median_low_K_mm");
  s.ratio = number(j, "high_over_low");
  s.rank_correlation = number(j, "rank_correlation_with_abs_K");
  return s;
}

void read_particles(const json& p, pipeline::RunResult& r) {
  r.sample.particles = count(&p, "particles");
  r.sample.off_data = count(&p, "off_data_removed");
  if (const json* raises = member(p, "count_raises"); raises && raises->is_array())
    for (const json& c : *raises) {
      if (!c.is_object()) continue;
      pipeline::CountRaise x;
      x.particles = count(&c, "particles");
      x.repair_points = count(&c, "repair_points");
      x.next_requested_particles = count(&c, "next_requested_particles");
      x.next_requested_spacing_mm = number(&c, "next_requested_spacing_mm", 0.0);
      r.raises.push_back(x);
    }
  const json* curved = member(p, "spacing_where_curvature_sets");
  if (!member(p, "particles") || !p["particles"].is_number() || !curved || !curved->is_object() ||
      !member(*curved, "particles") || !(*curved)["particles"].is_number())
    return;
  particles::SpacingSummary s;
  s.all = read_spacing(member(p, "spacing"));
  s.curved = read_spacing(curved);
  s.curved_particles = int64_t(number(curved, "particles"));
  r.sample.particles = int64_t(number(&p, "particles"));
  r.spacing = s;
}

void read_volume_mesh(const json& v, pipeline::RunResult& r) {
  pipeline::VolumeMeshResult m;
  m.options.grading = number(&v, "grading");
  m.stats.size = number(&v, "size_mm");
  m.stats.seconds = number(&v, "seconds");
  m.stats.boundary_points = count(&v, "boundary_points_added");
  m.stats.surface_volume = number(&v, "surface_volume_mm3");
  TetQuality& q = m.stats.quality;
  q.tets = count(&v, "tetrahedra");
  q.nodes = count(&v, "nodes");
  q.regions = count(&v, "regions");
  q.inverted = count(&v, "inverted");
  q.volume_mm3 = number(&v, "volume_mm3");
  q.min_dihedral_deg = number(&v, "min_dihedral_deg");
  q.max_dihedral_deg = number(&v, "max_dihedral_deg");
  q.pct_min_dihedral_below_10 = number(&v, "pct_min_dihedral_below_10");
  q.pct_min_dihedral_below_15 = number(&v, "pct_min_dihedral_below_15");
  q.radius_ratio_mean = number(&v, "radius_ratio_mean");
  if (const json* h = member(v, "dihedral_histogram_5deg"); h && h->is_array())
    for (size_t b = 0; b < h->size() && b < q.dihedral_histogram.size(); ++b)
      q.dihedral_histogram[b] = (*h)[b].is_number_integer() ? (*h)[b].get<int64_t>() : 0;
  r.volume = std::move(m);
}

}  // namespace

RunReportRead read_run_json(const json& j, const std::string& /*path*/) {
  RunReportRead out;
  pipeline::RunResult& r = out.run;
  if (const json* b = member(j, "backend")) out.device = text(b, "device");
  if (const json* in = member(j, "input"); in && in->is_object()) r.input = read_input(*in);
  if (const json* f = member(j, "fit"); f && f->is_object() && member(*f, "eps_mm") && (*f)["eps_mm"].is_number()) {
    r.fit.eps = (*f)["eps_mm"].get<double>();
    r.derived.tolerance.source = text(f, "eps_source");
    if (const json* c = member(*f, "curvature_scale_mm"); c && c->is_number())
      r.derived.curvature_scale_mm = c->get<double>();
  }
  if (const json* p = member(j, "particles"); p && p->is_object()) read_particles(*p, r);
  if (const json* o = member(j, "optimization"); o && o->is_object()) read_optimization(*o, r.optimization);
  if (const json* c = member(j, "components_filter"); c && c->is_object()) read_components(*c, r);
  if (const json* n = member(j, "notes"); n && n->is_array())
    for (const json& line : *n)
      if (line.is_string()) r.notes.push_back(line.get<std::string>());
  if (const json* v = member(j, "volume_mesh"); v && v->is_object()) read_volume_mesh(*v, r);
  if (const json* p = member(j, "slice_phase"); p && p->is_object() && member(*p, "modulation") &&
                                                (*p)["modulation"].is_number()) {
    r.slice_phase = SlicePhase{};
    r.slice_phase->modulation = (*p)["modulation"].get<double>();
  }
  if (const json* s = member(j, "stage_seconds"); s && s->is_object())
    for (const auto& [name, sec] : s->items())
      if (sec.is_number()) out.stage_seconds.emplace_back(name, sec.get<double>());
  return out;
}

}  // namespace mpumesh::tools
