#include "segment/segmentation.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/option_names.h"
#include "segment/distance_transform.h"

namespace mpumesh::seg {

const char* method_name(Method m) { return m == Method::kThreshold ? "threshold" : "chan-vese"; }

std::vector<float> window_image(const Volume& vol, Window w) {
  if (!(w.lo < w.hi)) throw InputError(option_ref("window") + ": LO must be below HI");
  std::vector<float> u(vol.voxels.size());
  const double scale = 255.0 / (w.hi - w.lo);
  tbb::parallel_for(size_t(0), u.size(), [&](size_t p) {
    const double v = vol.voxels[p];
    u[p] = std::isnan(v) ? 0.0f : float(std::round(std::clamp((v - w.lo) * scale, 0.0, 255.0)));
  });
  return u;
}

std::vector<float> signed_distance_init(const std::vector<uint8_t>& mask, std::array<int64_t, 3> dims) {
  const int64_t nx = dims[0], ny = dims[1], n = nx * ny;
  std::vector<float> phi(mask.size());
  tbb::parallel_for(int64_t(0), dims[2], [&](int64_t k) {
    const uint8_t* m = mask.data() + n * k;
    float* out = phi.data() + n * k;
    const int64_t in = std::count(m, m + n, uint8_t(1));
    if (in == 0 || in == n) {
      std::fill(out, out + n, float(in ? nx + ny : -(nx + ny)));
      return;
    }
    const auto to_out = squared_distance_2d(m, nx, ny, 0), to_in = squared_distance_2d(m, nx, ny, 1);
    for (int64_t p = 0; p < n; ++p)
      out[p] = m[p] ? std::sqrt(to_out[size_t(p)]) - 0.5f : 0.5f - std::sqrt(to_in[size_t(p)]);
  });
  return phi;
}

namespace {

// After Chan-Vese, the field whose sign is the final mask and whose zero crossings are the
// sub-pixel boundary. Chan-Vese decides the regions (no specks, no noise holes); the
// threshold places their boundary. A pixel takes Chan-Vese's label where its four in-plane
// neighbours share that label (away from Chan-Vese's boundary) and the threshold's label
// where they do not (in the one-pixel band along it). The value is the threshold field
// min(v - lo, hi - v), linear in position across an edge (partial volume), so contours
// fall where the image crosses the threshold, as the marching-cubes surface does; φ is not
// linear across the edge and would place them up to half a pixel off. Where the label
// overrules the threshold (a filled noise hole, a removed speck) the value is a nominal
// ±0.5.
mc::McField boundary_field(const mc::McField& thr, const std::vector<float>& phi, std::array<int64_t, 3> d) {
  mc::McField h;
  h.dims = thr.dims;
  h.values.resize(thr.values.size());
  const int64_t px = thr.dims[0], py = thr.dims[1], pz = thr.dims[2];
  auto cv = [&](int64_t i, int64_t j, int64_t k) {  // unpadded indices, clamped in-plane
    i = std::clamp<int64_t>(i, 0, d[0] - 1);
    j = std::clamp<int64_t>(j, 0, d[1] - 1);
    return phi[size_t(i + d[0] * (j + d[1] * k))] >= 0.0f;
  };
  tbb::parallel_for(int64_t(0), pz, [&](int64_t k) {
    for (int64_t j = 0; j < py; ++j)
      for (int64_t i = 0; i < px; ++i) {
        const int64_t p = i + px * (j + py * k);
        const float g = thr.values[size_t(p)];
        if (i == 0 || j == 0 || k == 0 || i == px - 1 || j == py - 1 || k == pz - 1) {
          h.values[size_t(p)] = g;  // padding: already negative
          continue;
        }
        const int64_t ui = i - 1, uj = j - 1, uk = k - 1;
        const bool c = cv(ui, uj, uk);
        const bool interior = cv(ui - 1, uj, uk) == c && cv(ui + 1, uj, uk) == c && cv(ui, uj - 1, uk) == c &&
                              cv(ui, uj + 1, uk) == c;
        const bool inside = interior ? c : g >= 0.0f;
        h.values[size_t(p)] = (g >= 0.0f) == inside ? g : (inside ? 0.5f : -0.5f);
      }
  });
  return h;
}

std::vector<uint8_t> inner_mask(const mc::McField& f) {
  const int64_t nx = f.dims[0] - 2, ny = f.dims[1] - 2, nz = f.dims[2] - 2;
  std::vector<uint8_t> m(size_t(nx * ny * nz));
  tbb::parallel_for(int64_t(0), nz, [&](int64_t k) {
    for (int64_t j = 0; j < ny; ++j) {
      const float* row = &f.values[size_t(1 + f.dims[0] * ((j + 1) + f.dims[1] * (k + 1)))];
      uint8_t* out = &m[size_t(nx * (j + ny * k))];
      for (int64_t i = 0; i < nx; ++i) out[i] = row[i] >= 0.0f ? 1 : 0;
    }
  });
  return m;
}

}  // namespace

Segmentation segment(const Volume& vol, const SegmentOptions& opt, ComputeBackend& backend) {
  require_3d(vol);
  Segmentation s;
  s.method = opt.method;
  mc::McField thr = mc::make_threshold_field(vol, opt.threshold);
  std::vector<uint8_t> mask = inner_mask(thr);
  if (std::all_of(mask.begin(), mask.end(), [](uint8_t m) { return m != 0; }))
    throw InputError(vol.source + ": every voxel lies in the threshold range " + std::to_string(opt.threshold.lo) +
                     (std::isinf(opt.threshold.hi) ? std::string() : ":" + std::to_string(opt.threshold.hi)) +
                     ": there is no surface inside the volume");
  s.threshold_components = mask_components(mask, vol.dims);
  if (s.threshold_components.count == 0)
    throw InputError(vol.source + ": no voxel lies in the threshold range " + std::to_string(opt.threshold.lo) +
                     (std::isinf(opt.threshold.hi) ? std::string() : ":" + std::to_string(opt.threshold.hi)));
  if (opt.method == Method::kThreshold) {
    s.field = std::move(thr);
    s.components = s.threshold_components;
    return s;
  }
  validate(opt.cv);
  ChanVeseResult r = backend.chan_vese(chan_vese_stack(vol, opt.window, mask), opt.cv);
  s.field = boundary_field(thr, r.phi, vol.dims);
  s.c1 = std::move(r.c1);
  s.c2 = std::move(r.c2);
  mask = inner_mask(s.field);
  s.components = mask_components(mask, vol.dims);
  if (s.components.count == 0)
    throw InputError(vol.source + ": Chan-Vese left no voxel inside (try another " + option_ref("window") + " or " + option_ref("lambda2") + ")");
  return s;
}

std::vector<uint8_t> threshold_mask(const Volume& vol, mc::ThresholdRange range) {
  return inner_mask(mc::make_threshold_field(vol, range));
}

ChanVeseStack chan_vese_stack(const Volume& vol, Window w, const std::vector<uint8_t>& mask) {
  ChanVeseStack stack;
  stack.nx = vol.dims[0];
  stack.ny = vol.dims[1];
  stack.nz = vol.dims[2];
  stack.u = window_image(vol, w);
  stack.phi = signed_distance_init(mask, vol.dims);
  return stack;
}

Volume mask_volume(const Segmentation& s, const Volume& like) {
  Volume m;
  m.dims = like.dims;
  m.spacing = like.spacing;
  m.origin = like.origin;
  m.direction = like.direction;
  m.modality = like.modality;
  const auto mask = inner_mask(s.field);
  m.voxels.assign(mask.begin(), mask.end());
  return m;
}

Window parse_window(const std::string& text) {
  const auto colon = text.find(':');
  Window w;
  try {
    if (colon == std::string::npos) throw std::invalid_argument("no colon");
    size_t a = 0, b = 0;
    const std::string lo = text.substr(0, colon), hi = text.substr(colon + 1);
    w.lo = std::stod(lo, &a);
    w.hi = std::stod(hi, &b);
    if (a != lo.size() || b != hi.size() || !std::isfinite(w.lo) || !std::isfinite(w.hi))
      throw std::invalid_argument("junk");
  } catch (const std::exception&) {
    throw InputError(option_ref("window") + ": '" + text + "' is not LO:HI (numbers)");
  }
  if (!(w.lo < w.hi)) throw InputError(option_ref("window") + ": LO must be below HI in '" + text + "'");
  return w;
}

SegmentationSummary summarize(const Segmentation& s) {
  SegmentationSummary m;
  for (float v : s.field.values) m.inside_voxels += v >= 0.0f ? 1 : 0;
  m.threshold_components = s.threshold_components.count;
  m.components = s.components.count;
  m.largest_component_voxels = s.components.sizes.empty() ? 0 : s.components.sizes.front();
  return m;
}

}  // namespace mpumesh::seg
