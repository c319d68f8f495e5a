// Every label of a label map, meshed one after another from one reading of the volume
// (`mpumesh run --labels`): which labels (all present, or those named), a run of the
// pipeline per label, each later label's mesh moved out of the earlier labels' where they
// cross (mesh/mesh_separation.h), and the triangle pairs by which any two still cross.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "mesh/mesh_separation.h"
#include "pipeline/run_pipeline.h"
#include "volume/volume.h"

namespace mpumesh::pipeline {

// Which labels: all present (`named` empty), or those named, each present and large
// enough. Throws InputError naming `input` otherwise, or when the map holds no label.
std::vector<int64_t> labels_to_mesh(const std::string& input, const std::vector<int64_t>& named,
                                    const std::map<int64_t, int64_t>& voxel_counts);

// A label meshed after others whose meshes it may cross.
struct LabelSeparation {
  std::vector<int64_t> against;  // the earlier labels near it (bounding boxes overlap)
  SeparationStats stats;
};

struct LabelRun {
  int64_t label = 0;
  RunResult result;  // its quality measured again when separation moved vertices
  std::optional<LabelSeparation> separation;
};

struct SkippedLabel {
  int64_t label = 0, voxels = 0;
  std::string reason;
};

// The triangle pairs by which the meshes of labels a < b cross.
struct LabelCrossing {
  int64_t a = 0, b = 0, triangle_pairs = 0;
};

struct LabelsResult {
  std::map<int64_t, int64_t> voxel_counts;  // every label of the map (seg::label_voxel_counts)
  std::vector<int64_t> meshed;  // in the order run
  std::vector<SkippedLabel> skipped;
  std::vector<LabelCrossing> crossings;  // sorted by (a, b)
};

// Meshes `labels` of the label map `labels_volume` with `base` (its label set to each in
// turn). With `skip_failures` (all labels asked for), a label too small to mesh, or whose
// run fails with bad input or a numerical failure, is skipped with the reason; otherwise
// the error is thrown. `on_label` receives each label's run when it is done (for its
// outputs), in order; the caller keeps what it needs. Without `separate`, the meshes are
// left as their runs made them (the complex, pipeline/complex_run.h, needs only their
// fits and samples). Throws InputError when no label could be meshed.
LabelsResult run_labels(const Volume& labels_volume, const std::vector<int64_t>& labels, bool skip_failures,
                        const RunOptions& base, const BackendOpener& open_backend, Observer* observer,
                        const std::function<void(LabelRun&)>& on_label, bool separate = true);

}  // namespace mpumesh::pipeline
