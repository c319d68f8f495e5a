#include "segment/distance_transform.h"

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

}  // namespace

void squared_distance_2d(const uint8_t* mask, int64_t nx, int64_t ny, uint8_t target, double wx, double wy,
                         std::vector<float>& out) {
  // Scratch reused per thread: fresh multi-100-kB buffers per slice cost more in page
  // faults than the transform itself.
  thread_local std::vector<double> f, d, z;
  thread_local std::vector<int64_t> v;
  f.resize(size_t(nx * ny));
  out.resize(size_t(nx * ny));
  bool any = false;
  for (int64_t p = 0; p < nx * ny; ++p) {
    f[size_t(p)] = mask[p] == target ? 0.0 : kInf;
    any |= mask[p] == target;
  }
  if (!any) {
    std::fill(out.begin(), out.end(), float(kInf));
    return;
  }
  for (int64_t j = 0; j < ny; ++j) transform_1d(f.data() + nx * j, nx, 1, wx, d, v, z);
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
