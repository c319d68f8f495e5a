#include "pipeline/complex_run.h"

#include <fmt/format.h>

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "common/lap_timer.h"
#include "multi/material_field.h"
#include "segment/label_map.h"

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

}  // namespace

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
  out.labels = run_labels(
      vol, labels, skip_failures, each, open_backend, &obs,
      [&](LabelRun& run) {
        on_label(run);  // before the fit and the mesh are taken from the run
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
  const std::map<int64_t, int64_t> counts = seg::label_voxel_counts(vol);
  const double voxel_mm3 = vol.spacing.prod();
  for (size_t k = 0; k < order.size(); ++k) {
    sorted.push_back(ids[order[k]]);
    fit_of.push_back(fits[order[k]].get());
    add_seeds(meshes[order[k]], int(k) + 1, seeds);
    const int64_t n = counts.count(sorted.back()) ? counts.at(sorted.back()) : 0;
    out.regions.push_back({sorted.back(), n, double(n) * voxel_mm3});
  }
  const multi::RegionSupport support(vol, sorted);
  const multi::MaterialField field(sorted, fit_of, union_run ? &union_run->surface : nullptr, &support);
  obs.begin("complex");
  const std::vector<multi::ComplexParticle> particles =
      multi::sample_complex(field, seeds, multi::ComplexSampleOptions{}, &out.sample);
  out.complex = multi::material_delaunay(field, particles, &out.triangulation);
  out.figures = multi::measure_complex(out.complex.mesh);
  obs.end();
  out.seconds_complex = timer.lap();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace mpumesh::pipeline
