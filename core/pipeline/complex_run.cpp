#include "pipeline/complex_run.h"

#include <fmt/format.h>

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "common/error.h"
#include "common/lap_timer.h"
#include "mesh/component_filter.h"
#include "mesh/topology.h"
#include "points/mesh_points.h"
#include "multi/complex_optimize.h"
#include "multi/complex_specks.h"
#include "multi/complex_tetrahedralize.h"
#include "multi/material_field.h"
#include "multi/volume_match.h"

namespace mpumesh::pipeline {
namespace {

// The labels meshed as one label (1) of a map of the same grid, the rest 0.
Volume union_of(const Volume& v, const std::vector<int64_t>& labels) {
  const std::set<int64_t> in(labels.begin(), labels.end());
  Volume u = v;
  for (float& x : u.voxels) x = in.count(int64_t(x)) ? 1.0f : 0.0f;
  return u;
}

// Whether two of the labels hold face-adjacent voxels.
bool labels_touch(const Volume& v, const std::vector<int64_t>& labels) {
  const std::set<int64_t> in(labels.begin(), labels.end());
  const int64_t step[3] = {1, v.dims[0], v.dims[0] * v.dims[1]};
  for (int64_t k = 0; k < v.dims[2]; ++k)
    for (int64_t j = 0; j < v.dims[1]; ++j)
      for (int64_t i = 0; i < v.dims[0]; ++i) {
        const int64_t at = v.index(i, j, k);
        const int64_t l = std::lround(v.voxels[size_t(at)]);
        if (l == 0 || !in.count(l)) continue;
        const int64_t idx[3] = {i, j, k};
        for (int d = 0; d < 3; ++d) {
          if (idx[d] + 1 >= v.dims[size_t(d)]) continue;
          const int64_t m = std::lround(v.voxels[size_t(at + step[d])]);
          if (m != l && m != 0 && in.count(m)) return true;
        }
      }
  return false;
}

// A mesh's vertices as seeds on the surface of region `source`, each with its mean edge
// length as its spacing.
void add_seeds(const TriangleMesh& m, int source, std::vector<multi::Seed>& out) {
  const std::vector<double> spacing = mean_edge_lengths(m);
  for (size_t i = 0; i < m.vertices.size(); ++i)
    if (spacing[i] > 0) out.push_back({m.vertices[i], spacing[i], source});
}

// The sampling, the triangulation, the specks' merging (pieces under `speck_mm3`;
// multi/complex_specks.h) and the optimisation of the complex of `field` from `seeds`
// (`resolve_gaps`: multi/material_delaunay.h).
void mesh_complex(const multi::MaterialField& field, const std::vector<multi::Seed>& seeds, bool resolve_gaps,
                  double speck_mm3, ComputeBackend& backend, Observer& obs, ComplexResult& out) {
  obs.begin("complex");
  const std::vector<multi::ComplexParticle> particles =
      multi::sample_complex(field, seeds, multi::ComplexSampleOptions{}, backend, &out.sample);
  out.complex = multi::material_delaunay(field, particles, &out.triangulation, resolve_gaps);
  out.specks = multi::merge_specks(out.complex.mesh, speck_mm3);
  obs.end();
  obs.begin("optimize complex");
  multi::optimize_complex(field, out.complex.mesh, multi::kComplexOptimizeRounds, &out.optimization);
  obs.end();
}

// The complex's volume mesh, when `base` asks for one (`name` names the input in errors).
void fill_complex(const RunOptions& base, const std::string& name, Observer& obs, ComplexResult& out) {
  if (!base.volume_mesh) return;
  obs.begin("volume mesh");
  VolumeMeshResult v;
  v.options = *base.volume_mesh;
  try {
    v.mesh = multi::tetrahedralize_complex(out.complex.mesh, v.options, &v.stats, obs.progress_of("volume mesh"));
  } catch (const InputError& e) {
    throw volume_mesh_error(name, e);
  }
  out.volume = std::move(v);
  obs.end();
}

// A closed part's mesh added to a complex as the boundary of label `label` against the
// background (its triangles oriented from the background into it).
void add_part_mesh(const TriangleMesh& part, int64_t label, TriangleMesh& complex) {
  const uint32_t base = uint32_t(complex.vertices.size());
  complex.vertices.insert(complex.vertices.end(), part.vertices.begin(), part.vertices.end());
  for (const auto& t : part.triangles) {
    complex.triangles.push_back({t[0] + base, t[2] + base, t[1] + base});
    complex.face_labels.push_back({0, int32_t(label)});
  }
}

// A part's count when neither a count nor a spacing is asked: a share of the default by
// area, at least this many (fewer leave a small part's curvature too coarsely sampled).
constexpr int64_t kMinPartParticles = 500;

// The run of part k of `parts` with `base`: one shell kept, the count its share by area.
RunOptions part_options(const RunOptions& base, const std::vector<MeshPart>& parts, size_t k) {
  RunOptions each = base;
  each.components.largest = 1;
  each.volume_mesh.reset();  // the complex's, not the part's
  if (base.sample.spacing > 0) return each;
  double area = 0;
  for (const MeshPart& p : parts) area += p.area_mm2;
  const bool asked = base.sample.particles > 0;
  const double all = double(asked ? base.sample.particles : particles::kDefaultParticles);
  each.sample.particles = std::max(kMinPartParticles, int64_t(std::llround(all * parts[k].area_mm2 / area)));
  if (each.count_retries < 0) each.count_retries = asked ? 0 : 2;
  return each;
}

// The parts in contact (a part's mesh vertex within `contact` of another part's fit),
// grouped: group[r - 1] for region r of `field`, -1 for a part in contact with none.
std::vector<int> contact_groups(const multi::MaterialField& field, const std::vector<multi::Seed>& seeds,
                                double contact, int* groups) {
  const int n = field.regions() - 1;
  std::vector<int> root(size_t(n + 1));
  for (int r = 0; r <= n; ++r) root[size_t(r)] = r;
  auto find = [&](int r) {
    while (root[size_t(r)] != r) r = root[size_t(r)] = root[size_t(root[size_t(r)])];
    return r;
  };
  std::vector<double> f;
  for (const multi::Seed& s : seeds) {
    field.values(s.p, f);
    for (int r = 1; r <= n; ++r)
      if (r != s.source && f[size_t(r)] < contact) root[size_t(find(r))] = find(s.source);
  }
  std::vector<int> size(size_t(n + 1), 0), index(size_t(n + 1), -1), group(size_t(n), -1);
  for (int r = 1; r <= n; ++r) ++size[size_t(find(r))];
  *groups = 0;
  for (int r = 1; r <= n; ++r) {
    const int g = find(r);
    if (size[size_t(g)] < 2) continue;
    if (index[size_t(g)] < 0) index[size_t(g)] = (*groups)++;
    group[size_t(r - 1)] = index[size_t(g)];
  }
  return group;
}

// The outside of group g: the points of its parts' input meshes (`meshes[k]` region
// k + 1's; vertices and triangle centroids, with their normals) farther than `contact`
// from every other part of the group, so that the faces the parts share are no data of it, fitted as one surface with
// `fit` (the parts' options at the parts' largest tolerance).
mpu::MpuSurface fit_group_union(const multi::MaterialField& field, const std::vector<const TriangleMesh*>& meshes,
                                const std::vector<int>& group, int g, double contact, mpu::FitOptions fit,
                                const std::string& name) {
  PointCloud cloud;
  std::vector<double> f;
  for (size_t k = 0; k < meshes.size(); ++k) {
    if (group[k] != g) continue;
    const PointCloud own = pts::mesh_points(*meshes[k]);
    for (size_t i = 0; i < own.size(); ++i) {
      field.values(own.positions[i], f);
      bool alone = true;
      for (size_t s = 0; s < meshes.size() && alone; ++s)
        alone = s == k || group[s] != g || f[s + 1] >= contact;
      if (!alone) continue;
      cloud.positions.push_back(own.positions[i]);
      cloud.normals.push_back(own.normals[i]);
    }
  }
  if (cloud.size() < size_t(fit.nmin))
    throw InputError(fmt::format("{}: parts in contact leave {} points of their outside, fewer than a fit needs "
                                 "({}); remesh them with --separate",
                                 name, cloud.size(), fit.nmin));
  fit.eps = contact;
  return mpu::fit_mpu(cloud, fit);
}

// The parts' own runs: each part's fit and mesh, its seeds, and the contact distance (the
// parts' largest fit tolerance).
struct PartRuns {
  std::vector<RunResult> runs;  // the parts meshed; run j is region j + 1 of their field
  std::vector<size_t> part;     // run j's index in the parts
  std::vector<const mpu::MpuSurface*> fits;
  std::vector<int64_t> labels;
  std::vector<multi::Seed> seeds;
  double contact = 0;
};

// A part whose run fails on its own (too small to fit, a sample that cannot close) is
// skipped with the reason, as --labels all skips a label; the others are meshed.
PartRuns run_parts(const std::vector<MeshPart>& parts, const std::string& name, const RunOptions& base,
                   const BackendOpener& open_backend, Observer& obs, ComplexResult& out) {
  PartRuns p;
  for (size_t k = 0; k < parts.size(); ++k) {
    obs.progress("parts", double(k) / double(parts.size()));
    const int64_t label = int64_t(k) + 1;
    const std::string part = fmt::format("{} (part {})", name, label);
    try {
      p.runs.push_back(run_pipeline(parts[k].mesh, part, part_options(base, parts, k), open_backend, &obs));
    } catch (const InputError& e) {
      out.labels.skipped.push_back({label, 0, e.what()});
      obs.note("note: " + part + ": skipped: " + e.what());
      continue;
    } catch (const NumericalError& e) {
      out.labels.skipped.push_back({label, 0, e.what()});
      obs.note("note: " + part + ": skipped: " + e.what());
      continue;
    }
    const RunResult& r = p.runs.back();
    if (r.components) out.shells_removed += int64_t(r.components->dropped.size());
    p.contact = std::max(p.contact, r.fit.eps);
    add_seeds(r.mesh, int(p.runs.size()), p.seeds);
    p.part.push_back(k);
    p.labels.push_back(label);
    out.labels.meshed.push_back(label);
    out.regions.push_back({label, 0, parts[k].volume_mm3});
  }
  for (const RunResult& r : p.runs) p.fits.push_back(&r.surface);
  obs.progress("parts", 1);
  return p;
}

// The parts in contact, grouped (group[j] for run j, -1 for none), each group's union
// fitted.
struct ContactGroups {
  std::vector<int> group;
  std::vector<mpu::MpuSurface> unions;
};

ContactGroups contact_units(const PartRuns& p, const std::vector<MeshPart>& parts, const std::string& name,
                            Observer& obs) {
  ContactGroups c;
  int groups = 0;
  const multi::MaterialField apart(p.labels, p.fits, p.contact);
  c.group = contact_groups(apart, p.seeds, p.contact, &groups);
  if (groups == 0) return c;
  std::vector<const TriangleMesh*> meshes;
  for (size_t k : p.part) meshes.push_back(&parts[k].mesh);
  obs.begin("fit contact unions");
  for (int g = 0; g < groups; ++g)
    c.unions.push_back(fit_group_union(apart, meshes, c.group, g, p.contact, p.runs.front().derived.fit, name));
  obs.end();
  return c;
}

// The groups in contact through the complex, over their parts alone; a part in contact
// with none is bounded by its own fit, which its run has meshed and optimised already,
// and joins the complex as it is.
void assemble_parts(const PartRuns& p, const ContactGroups& c, ComputeBackend& backend, Observer& obs,
                    ComplexResult& out) {
  std::vector<int64_t> labels;
  std::vector<const mpu::MpuSurface*> fits;
  multi::PartUnions unions;
  std::vector<int> region(p.labels.size() + 1, 0);  // a region of the parts' field: its region in the complex
  for (size_t k = 0; k < p.labels.size(); ++k) {
    if (c.group[k] < 0) continue;
    labels.push_back(p.labels[k]);
    fits.push_back(p.fits[k]);
    unions.group.push_back(c.group[k]);
    region[k + 1] = int(labels.size());
  }
  for (const mpu::MpuSurface& u : c.unions) unions.fits.push_back(&u);
  if (!labels.empty()) {
    std::vector<multi::Seed> seeds;
    for (const multi::Seed& s : p.seeds)
      if (region[size_t(s.source)] > 0) seeds.push_back({s.p, s.spacing, region[size_t(s.source)]});
    mesh_complex(multi::MaterialField(labels, fits, p.contact, unions), seeds, /*resolve_gaps=*/true, 0, backend, obs,
                 out);
  }
  for (size_t k = 0; k < p.labels.size(); ++k)
    if (c.group[k] < 0) add_part_mesh(p.runs[k].mesh, p.labels[k], out.complex.mesh);
}

}  // namespace

ComplexResult run_parts_complex(const TriangleMesh& mesh, const std::string& name, const RunOptions& base,
                                const BackendOpener& open_backend, Observer* observer) {
  Observer quiet;
  Observer& obs = observer ? *observer : quiet;
  const auto t0 = std::chrono::steady_clock::now();
  LapTimer timer(t0);
  require_closed_manifold(mesh, name, "the input mesh", "remeshing needs a closed surface");
  const std::vector<MeshPart> parts = split_parts(mesh);
  if (parts.size() < 2) throw InputError(name + ": a complex of parts needs a mesh of two or more closed parts");
  ComplexResult out;
  out.from_mesh = true;
  const PartRuns runs = run_parts(parts, name, base, open_backend, obs, out);
  if (runs.runs.empty()) throw InputError(name + ": no part could be meshed: " + out.labels.skipped.front().reason);
  out.seconds_labels = timer.lap();
  const ContactGroups contact = contact_units(runs, parts, name, obs);
  out.seconds_union = timer.lap();
  assemble_parts(runs, contact, open_backend(), obs, out);
  out.figures = multi::measure_complex(out.complex.mesh);
  out.seconds_complex = timer.lap();
  fill_complex(base, name, obs, out);
  out.seconds_volume = timer.lap();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

ComplexResult run_complex(const Volume& vol, const std::vector<int64_t>& labels, bool skip_failures,
                          const RunOptions& base, const BackendOpener& open_backend, Observer* observer,
                          const std::function<void(LabelRun&)>& on_label) {
  Observer quiet;
  Observer& obs = observer ? *observer : quiet;
  const auto t0 = std::chrono::steady_clock::now();
  LapTimer timer(t0);
  ComplexResult out;
  std::vector<std::unique_ptr<mpu::MpuSurface>> fits;
  std::vector<TriangleMesh> meshes;
  // Each label's fit passes through the faces it shares with its neighbours, so that two
  // touching labels' fits meet there.
  RunOptions each = base;
  each.label_shares_faces = true;
  each.volume_mesh.reset();  // the complex's, not the label's
  out.labels = run_labels(
      vol, labels, skip_failures, each, open_backend, &obs,
      [&](LabelRun& run) {
        on_label(run);  // before the fit and the mesh are taken from the run
        if (run.result.components) out.shells_removed += int64_t(run.result.components->dropped.size());
        fits.push_back(std::make_unique<mpu::MpuSurface>(std::move(run.result.surface)));
        meshes.push_back(std::move(run.result.mesh));
      },
      /*separate=*/false);
  out.seconds_labels = timer.lap();
  // Where labels touch, the union of the labels meshed gives the background's function:
  // two fits that meet at their shared faces only to within their noise would leave the
  // background slivers between them, and the union is inside across those. Where none
  // touch, the background is what no label holds (its function -min f_r), each label's
  // boundary its own fit, without a second fit's noise.
  std::optional<RunResult> union_run;
  if (labels_touch(vol, out.labels.meshed)) {
    RunOptions whole = base;
    whole.label = 1;
    whole.fit_only = true;
    Volume u = union_of(vol, out.labels.meshed);
    u.source = vol.source + " (the labels' union)";
    union_run = run_pipeline(u, whole, open_backend, &obs);
  }
  out.seconds_union = timer.lap();
  std::vector<int64_t> ids = out.labels.meshed;
  std::vector<const mpu::MpuSurface*> fit_of;
  // Regions in ascending label order.
  std::vector<size_t> order(ids.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return ids[a] < ids[b]; });
  std::vector<int64_t> sorted;
  std::vector<multi::Seed> seeds;
  const std::map<int64_t, int64_t>& counts = out.labels.voxel_counts;
  const double voxel_mm3 = vol.spacing.prod();
  for (size_t k = 0; k < order.size(); ++k) {
    sorted.push_back(ids[order[k]]);
    fit_of.push_back(fits[order[k]].get());
    add_seeds(meshes[order[k]], int(k) + 1, seeds);
    const int64_t n = counts.count(sorted.back()) ? counts.at(sorted.back()) : 0;
    out.regions.push_back({sorted.back(), n, double(n) * voxel_mm3});
  }
  const multi::RegionSupport support(vol, sorted);
  const multi::MaterialField field(sorted, fit_of, union_run ? &union_run->surface : nullptr, &support,
                                   multi::kLabelDepthVoxels * vol.in_plane_spacing());
  mesh_complex(field, seeds, /*resolve_gaps=*/false, base.speck_voxels * voxel_mm3, open_backend(), obs, out);
  std::map<int64_t, double> voxel_volumes;
  for (const ComplexRegion& r : out.regions) voxel_volumes[r.label] = r.reference_volume_mm3;
  out.volume_match = multi::match_label_volumes(out.complex.mesh, voxel_volumes,
                                                multi::kVolumeShiftVoxels * vol.in_plane_spacing());
  out.figures = multi::measure_complex(out.complex.mesh);
  out.seconds_complex = timer.lap();
  fill_complex(base, vol.source, obs, out);
  out.seconds_volume = timer.lap();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace mpumesh::pipeline
