// A label map meshed into one multi-material complex (`mpumesh run --labels`;
// docs/method.md "Several labels"): each label's run (its fit and its adaptive sample),
// where labels touch a run of their union (its fit is the background's function), the
// labelling of space from the fits within each region's voxel support
// (multi/material_field.h, multi/region_support.h), the junctions and interfaces sampled
// from the labels' samples (multi/complex_sampling.h), one restricted Delaunay
// triangulation of them (multi/material_delaunay.h), a label map's specks merged into a
// neighbour (multi/complex_specks.h), its triangles made better shaped
// (multi/complex_optimize.h), measured (multi/complex_figures.h).
// A surface mesh of several parts is remeshed the same way, a part for a label.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "multi/complex_figures.h"
#include "multi/complex_optimize.h"
#include "multi/complex_sampling.h"
#include "multi/complex_specks.h"
#include "multi/material_delaunay.h"
#include "multi/volume_match.h"
#include "pipeline/label_runs.h"

namespace mpumesh::pipeline {

struct ComplexRegion {
  int64_t label = 0, voxels = 0;  // voxels: 0 for a mesh's part
  // What its enclosed volume is measured against: its voxels' volume (a label map) or the
  // input part's enclosed volume (a mesh).
  double reference_volume_mm3 = 0;
};

struct ComplexResult {
  bool from_mesh = false;      // the parts of a surface mesh rather than a label map's labels
  LabelsResult labels;         // the labels' own runs: which were meshed, which skipped
  std::vector<ComplexRegion> regions;  // the labels meshed, ascending
  // The closed shells the parts' runs dropped (away from the data, thinner than the fit
  // resolves, or beyond a part's one shell).
  int64_t shells_removed = 0;
  multi::MaterialComplex complex;
  multi::ComplexSampleStats sample;
  multi::ComplexDelaunayStats triangulation;
  // A label map's pieces of a label under its specks' bound (RunOptions::speck_voxels),
  // each merged into a neighbour (multi/complex_specks.h).
  multi::SpeckStats specks;
  multi::ComplexOptimizeStats optimization;
  // A label map's labels moved to hold the volumes of their voxels (multi/volume_match.h).
  multi::VolumeMatchStats volume_match;
  multi::ComplexFigures figures;
  // RunOptions::volume_mesh: one volume mesh of the complex, a region per label
  // (multi/complex_tetrahedralize.h).
  std::optional<VolumeMeshResult> volume;
  double seconds_labels = 0, seconds_union = 0, seconds_complex = 0, seconds_volume = 0, seconds = 0;
};

// The labels named (the others count as background), each label's run with `base`
// (label runs as run_labels makes them, without separation; `on_label` sees each).
// Throws InputError when fewer than one label could be meshed.
ComplexResult run_complex(const Volume& labels_volume, const std::vector<int64_t>& labels, bool skip_failures,
                          const RunOptions& base, const BackendOpener& open_backend, Observer* observer,
                          const std::function<void(LabelRun&)>& on_label);

// The parts of a closed surface mesh (each shell with its cavities; mesh/component_filter.h
// split_parts) remeshed as one complex: the parts numbered from 1 by enclosed volume,
// largest first, each part's run with `base` (one shell kept; without a count or spacing,
// the default count shared among the parts by area); the parts in contact grouped, each
// group's union fitted, the labelling of space from them (multi/material_field.h: parts
// within their fits' tolerance share an interface, the others stay apart); the groups
// meshed as a complex, the parts in contact with none as their own runs meshed them. A
// part whose run fails on its own is skipped with the reason (ComplexResult::labels).
// `name` names the mesh in messages. Throws InputError when the mesh is not closed, has
// fewer than two parts, or no part could be meshed.
ComplexResult run_parts_complex(const TriangleMesh& mesh, const std::string& name, const RunOptions& base,
                                const BackendOpener& open_backend, Observer* observer);

}  // namespace mpumesh::pipeline
