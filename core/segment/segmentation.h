// Stage 2: the volume to a segmentation. Two methods: a threshold on the voxel values (HU
// for CT), and Chan-Vese on every slice of the windowed image, initialised from that
// threshold. Both give a field on the volume's grid padded by one voxel on every side
// (mc::McField layout), >= 0 inside, whose zero level is the boundary the contours follow.
#pragma once

#include <string>
#include <vector>

#include "compute/compute_backend.h"
#include "mc/mc_field.h"
#include "segment/chan_vese_ref.h"
#include "segment/components.h"
#include "volume/volume.h"

namespace mpumesh::seg {

enum class Method { kThreshold, kChanVese };

// Intensities mapped linearly to 0..255 (clamped, rounded) for Chan-Vese.
struct Window {
  double lo = 100.0, hi = 1500.0;  // bone: soft tissue and air map to 0
};

struct SegmentOptions {
  Method method = Method::kChanVese;
  mc::ThresholdRange threshold{226.0};  // the threshold (and Chan-Vese's start)
  Window window;
  ChanVeseParams cv;
};

struct Segmentation {
  Method method = Method::kThreshold;
  // Padded by one voxel; its sign is the mask and its zero level the sub-pixel boundary.
  // Threshold: min(v - lo, hi - v). Chan-Vese: the sign of φ, the magnitude from the
  // threshold field (see boundary_field in segmentation.cpp).
  // Padding voxels are negative, so every structure closes.
  mc::McField field;
  std::vector<double> c1, c2;     // Chan-Vese: the region means of the last iteration, per slice
  ComponentStats threshold_components;  // of the threshold mask
  ComponentStats components;            // of the final mask
  bool inside(int64_t pi, int64_t pj, int64_t pk) const {  // padded indices
    return field.values[size_t(pi + field.dims[0] * (pj + field.dims[1] * pk))] >= 0.0f;
  }
};

Segmentation segment(const Volume& vol, const SegmentOptions& opt, ComputeBackend& backend);

// The final mask on the volume's own grid (0/1) and geometry, for writing.
Volume mask_volume(const Segmentation& s, const Volume& like);

// The threshold mask on the volume's grid (0/1, x fastest).
std::vector<uint8_t> threshold_mask(const Volume& vol, mc::ThresholdRange range);

// What Chan-Vese starts from: the windowed image and the signed distance to `mask`.
ChanVeseStack chan_vese_stack(const Volume& vol, Window w, const std::vector<uint8_t>& mask);

// The image windowed to 0..255 integers (stored as float), as Chan-Vese sees it.
std::vector<float> window_image(const Volume& vol, Window w);

// The Chan-Vese start: per slice, the signed distance in pixels to the boundary of the
// mask (+ inside, - outside, ±0.5 next to it); a slice with no inside (or no outside)
// pixel gets -(nx + ny) (or +(nx + ny)) everywhere.
std::vector<float> signed_distance_init(const std::vector<uint8_t>& mask, std::array<int64_t, 3> dims);

// What the reports say of a segmentation.
struct SegmentationSummary {
  int64_t inside_voxels = 0;  // of the padded field (the padding is outside)
  int64_t threshold_components = 0, components = 0, largest_component_voxels = 0;
};
SegmentationSummary summarize(const Segmentation& s);

// "LO:HI" (numbers, LO < HI).
Window parse_window(const std::string& text);
const char* method_name(Method m);

}  // namespace mpumesh::seg
