#include "segment/distance_transform.h"

#include <algorithm>
#include <cstddef>
#include <limits>

namespace mpumesh::seg {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// 1D squared distance transform of f (stride apart) with sample spacing w, in place.
void transform_1d(double* f, int64_t n, int64_t stride, double w, std::vector<double>& d, std::vector<int64_t>& v,
                  std::vector<double>& z) {
  d.resize(size_t(n));
  v.resize(size_t(n));
  z.resize(size_t(n + 1));
  int64_t k = -1;
  for (int64_t q = 0; q < n; ++q) {
    const double fq = f[q * stride];
    if (fq == kInf) continue;
    const double xq = w * double(q);
    while (k >= 0) {
      const double xv = w * double(v[size_t(k)]), fv = f[v[size_t(k)] * stride];
      const double s = ((fq + xq * xq) - (fv + xv * xv)) / (2.0 * (xq - xv));
      if (s > z[size_t(k)]) {
        ++k;
        v[size_t(k)] = q;
        z[size_t(k)] = s;
        z[size_t(k + 1)] = kInf;
        break;
      }
      --k;
    }
    if (k < 0) {
      k = 0;
      v[0] = q;
      z[0] = -kInf;
      z[1] = kInf;
    }
  }
  if (k < 0) return;  // no finite sample: everything stays infinite
  int64_t j = 0;
  for (int64_t q = 0; q < n; ++q) {
    const double xq = w * double(q);
    while (z[size_t(j + 1)] < xq) ++j;
    const double xv = w * double(v[size_t(j)]);
    d[size_t(q)] = (xq - xv) * (xq - xv) + f[v[size_t(j)] * stride];
  }
  for (int64_t q = 0; q < n; ++q) f[q * stride] = d[size_t(q)];
}

// The rows' pass on the binary image: along each row, the squared distance to the nearest
// target pixel (+infinity in a row without one). The lower envelope of the 1D transform
// gives that too for 0 / infinity samples, but through a division per site; the nearest
// sites either side, found in two scans, give it without one (on the sample CT the cap
// points' transforms take about 0.17 s of CPU, and the points stage 0.015 s less wall
// time this way). The value is the same expression of the same site; where two are
// equally near, the smaller of the two roundings.
void binary_rows(const uint8_t* mask, int64_t nx, int64_t ny, uint8_t target, double w, double* f) {
  for (int64_t j = 0; j < ny; ++j) {
    const uint8_t* m = mask + nx * j;
    double* row = f + nx * j;
    int64_t last = -1;
    for (int64_t q = 0; q < nx; ++q) {
      if (m[q] == target) last = q;
      row[q] = last < 0 ? kInf : (w * double(q) - w * double(last)) * (w * double(q) - w * double(last));
    }
    last = -1;
    for (int64_t q = nx; q-- > 0;) {
      if (m[q] == target) last = q;
      if (last < 0) continue;
      const double d = (w * double(q) - w * double(last)) * (w * double(q) - w * double(last));
      if (d < row[q]) row[q] = d;
    }
  }
}

}  // namespace

void squared_distance_2d(const uint8_t* mask, int64_t nx, int64_t ny, uint8_t target, double wx, double wy,
                         std::vector<float>& out) {
  // Scratch reused per thread: fresh multi-100-kB buffers per slice cost more in page
  // faults than the transform itself.
  thread_local std::vector<double> f, d, z;
  thread_local std::vector<int64_t> v;
  f.resize(size_t(nx * ny));
  out.resize(size_t(nx * ny));
  if (std::find(mask, mask + nx * ny, target) == mask + nx * ny) {
    std::fill(out.begin(), out.end(), float(kInf));
    return;
  }
  binary_rows(mask, nx, ny, target, wx, f.data());
  for (int64_t i = 0; i < nx; ++i) transform_1d(f.data() + i, ny, nx, wy, d, v, z);
  for (size_t p = 0; p < out.size(); ++p) out[p] = float(f[p]);
}

std::vector<float> squared_distance_2d(const uint8_t* mask, int64_t nx, int64_t ny, uint8_t target, double wx,
                                       double wy) {
  std::vector<float> out;
  squared_distance_2d(mask, nx, ny, target, wx, wy, out);
  return out;
}

}  // namespace mpumesh::seg
