// Label maps: a volume of whole-number labels (0 the background), as atlas and
// learning-based segmenters write them, meshed one label at a time.
// A label becomes an indicator volume for the threshold segmentation at 0.5:
//   1 on the label's voxels, 0 on the background, -1 on every other label.
// The boundary field is then +0.5 inside and -0.5 toward the background, so the contour
// lies halfway between voxel centres there (the label's voxels are its volume), and -1.5
// toward another label, so a face shared with another label is met a quarter voxel inside
// the label, and the caps between slices stop at the same crossing
// (pts::PointOptions::caps_to_field_crossing). Two touching labels' surfaces are then
// half a voxel apart over their shared face; where two independent fits of one curved
// interface still cross, the label meshed later yields (mesh/mesh_separation.h). A
// larger inset was measured to make the fits worse: on a 4 mm ball inside another label,
// a sixth of a voxel left a 1.1 mm bump, a quarter none.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "volume/volume.h"

namespace mpumesh::seg {

// "SOURCE (label L)": how messages name one label of a volume.
std::string label_name(const std::string& source, int64_t label);

// The indicator of `label` (see above), with the volume's geometry and the label's name
// as its source; `others` is the value on the other labels' voxels (-1 above; 0 counts
// them as background, so that the contour passes through the faces the label shares with
// them, as a multi-material complex wants: pipeline/complex_run.h). Throws InputError
// when a voxel is not a whole number (not a label map), or when no voxel holds the
// label, or too few.
Volume label_indicator(const Volume& labels, int64_t label, float others = -1.0f);

// The voxel count of every non-zero label. Throws InputError naming the volume when a
// voxel is not a whole number (not a label map) or there are more than kMaxLabels labels
// (most likely an intensity image).
inline constexpr size_t kMaxLabels = 1000;
std::map<int64_t, int64_t> label_voxel_counts(const Volume& labels);

// Why a label of `voxels` voxels is too small to mesh, or "" when it is not.
inline constexpr int64_t kMinLabelVoxels = 8;
std::string too_small_to_mesh(int64_t voxels);

// "all" (empty result) or a comma-separated list of whole numbers, each above 0.
std::vector<int64_t> parse_label_list(const std::string& text);

}  // namespace mpumesh::seg
