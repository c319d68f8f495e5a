// A label map meshed into one multi-material complex (`mpumesh run --labels`;
// docs/method.md "Several labels"): each label's run (its fit and its adaptive sample),
// where labels touch a run of their union (its fit is the background's function), the
// labelling of space from the fits within each region's voxel support
// (multi/material_field.h, multi/region_support.h), the junctions and interfaces sampled
// from the labels' samples (multi/complex_sampling.h) and one restricted Delaunay
// triangulation of them (multi/material_delaunay.h), measured (multi/complex_figures.h).
#pragma once

#include <cstdint>
#include <vector>

#include "multi/complex_figures.h"
#include "multi/complex_sampling.h"
#include "multi/material_delaunay.h"
#include "pipeline/label_runs.h"

namespace mpumesh::pipeline {

struct ComplexRegion {
  int64_t label = 0, voxels = 0;
  double voxel_volume_mm3 = 0;  // its voxels' volume
};

struct ComplexResult {
  LabelsResult labels;         // the labels' own runs: which were meshed, which skipped
  std::vector<ComplexRegion> regions;  // the labels meshed, ascending
  multi::MaterialComplex complex;
  multi::ComplexSampleStats sample;
  multi::ComplexDelaunayStats triangulation;
  multi::ComplexFigures figures;
  double seconds_labels = 0, seconds_union = 0, seconds_complex = 0, seconds = 0;
};

// The labels named (the others count as background), each label's run with `base`
// (label runs as run_labels makes them, without separation; `on_label` sees each).
// Throws InputError when fewer than one label could be meshed.
ComplexResult run_complex(const Volume& labels_volume, const std::vector<int64_t>& labels, bool skip_failures,
                          const RunOptions& base, const BackendOpener& open_backend, Observer* observer,
                          const std::function<void(LabelRun&)>& on_label);

}  // namespace mpumesh::pipeline
