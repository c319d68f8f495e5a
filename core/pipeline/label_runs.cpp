#include "pipeline/label_runs.h"

#include <fmt/format.h>

#include <algorithm>

#include "common/error.h"
#include "segment/label_map.h"

namespace mpumesh::pipeline {

std::vector<int64_t> labels_to_mesh(const std::string& input, const std::vector<int64_t>& named,
                                    const std::map<int64_t, int64_t>& counts) {
  if (counts.empty()) throw InputError(input + ": the label map holds no label (every voxel is 0)");
  if (named.empty()) {
    std::vector<int64_t> all;
    for (const auto& [l, n] : counts) all.push_back(l);
    return all;
  }
  std::string present;
  for (const auto& [l, n] : counts) present += (present.empty() ? "" : ", ") + std::to_string(l);
  for (const int64_t l : named) {
    const auto it = counts.find(l);
    if (it == counts.end())
      throw InputError(fmt::format("{}: no voxel holds label {} (the labels present: {})", input, l, present));
    const std::string small = seg::too_small_to_mesh(it->second);
    if (!small.empty()) throw InputError(seg::label_name(input, l) + ": " + small);
  }
  return named;
}

namespace {

// A label's mesh (vertices and triangles only), for the labels after it to yield to.
struct LabelShape {
  int64_t label;
  TriangleMesh mesh;
};

// A label meshed after others that it touches moves its vertices out of theirs
// (mesh/mesh_separation.h), to a tenth of a voxel from them, and its quality is measured
// again; nothing when no earlier label is near. The triangle pairs by which its final mesh
// still crosses each of them go to `crossings` (and to the observer, where there are any).
std::optional<LabelSeparation> yield_to_earlier_labels(RunResult& r, int64_t label,
                                                       const std::vector<LabelShape>& earlier, double voxel,
                                                       const RunOptions& options, Observer& obs,
                                                       std::vector<LabelCrossing>& crossings) {
  std::vector<const TriangleMesh*> near;
  LabelSeparation sep;
  for (const LabelShape& e : earlier)
    if (bounding_boxes_overlap(r.mesh, e.mesh)) {
      near.push_back(&e.mesh);
      sep.against.push_back(e.label);
    }
  if (near.empty()) return std::nullopt;
  sep.stats = separate_from(r.mesh, near, 0.1 * voxel);
  if (sep.stats.moved_vertices > 0 && r.quality && options.quality)
    r.quality = measure_quality(r.mesh, *options.quality);
  for (size_t k = 0; k < near.size(); ++k) {
    const int64_t other = sep.against[k], n = sep.stats.crossings_with[k];
    crossings.push_back({std::min(other, label), std::max(other, label), n});
    if (n > 0) obs.note(fmt::format("note: the meshes of labels {} and {} cross ({} triangle pairs)", other, label, n));
  }
  return sep;
}

}  // namespace

LabelsResult run_labels(const Volume& vol, const std::vector<int64_t>& labels, bool skip_failures,
                        const RunOptions& base, const BackendOpener& open_backend, Observer* observer,
                        const std::function<void(LabelRun&)>& on_label, bool separate) {
  Observer quiet;
  Observer& obs = observer ? *observer : quiet;
  LabelsResult out;
  out.voxel_counts = seg::label_voxel_counts(vol);
  const std::map<int64_t, int64_t>& counts = out.voxel_counts;
  std::vector<LabelShape> shapes;
  auto skip = [&](int64_t l, const std::string& why) {
    const auto it = counts.find(l);
    out.skipped.push_back({l, it == counts.end() ? 0 : it->second, why});
    obs.note("note: " + seg::label_name(vol.source, l) + ": skipped: " + why);
  };
  for (size_t k = 0; k < labels.size(); ++k) {
    obs.progress("labels", double(k) / double(labels.size()));
    const int64_t l = labels[k];
    const auto it = counts.find(l);
    const std::string small = seg::too_small_to_mesh(it == counts.end() ? 0 : it->second);
    if (!small.empty()) {
      skip(l, small);
      continue;
    }
    RunOptions options = base;
    options.label = l;
    LabelRun run;
    run.label = l;
    try {
      run.result = run_pipeline(vol, options, open_backend, &obs);
    } catch (const std::exception& e) {  // InputError or NumericalError: this label's own
      if (!skip_failures || !(dynamic_cast<const InputError*>(&e) || dynamic_cast<const NumericalError*>(&e))) throw;
      skip(l, e.what());
      continue;
    }
    if (separate) {
      run.separation =
          yield_to_earlier_labels(run.result, l, shapes, vol.in_plane_spacing(), base, obs, out.crossings);
      shapes.push_back({l, {}});
      shapes.back().mesh.vertices = run.result.mesh.vertices;
      shapes.back().mesh.triangles = run.result.mesh.triangles;
    }
    out.meshed.push_back(l);
    on_label(run);
  }
  if (out.meshed.empty()) {
    std::string why;
    for (const SkippedLabel& s : out.skipped)
      why += fmt::format("{}label {}: {}", why.empty() ? "" : "; ", s.label, s.reason);
    throw InputError(vol.source + ": no label could be meshed (" + why + ")");
  }
  std::sort(out.crossings.begin(), out.crossings.end(), [](const LabelCrossing& x, const LabelCrossing& y) {
    return std::pair(x.a, x.b) < std::pair(y.a, y.b);
  });
  obs.progress("labels", 1);
  return out;
}

}  // namespace mpumesh::pipeline
