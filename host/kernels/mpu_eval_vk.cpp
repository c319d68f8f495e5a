#include "kernels/mpu_eval_vk.h"

#include <algorithm>

#include "mpu_eval.spv.h"
#include "vk/command.h"

namespace mpumesh::vk {
namespace {

const std::vector<Binding> kBindings = {
    {MPU_BIND_LEAVES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, {MPU_BIND_OFFSETS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {MPU_BIND_LEAF_IDS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, {MPU_BIND_POINTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {MPU_BIND_FG, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},     {MPU_BIND_CURV, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};

// Points per dispatch: bounds the device memory of the point and result buffers (48 B
// per point).
constexpr size_t kChunk = size_t(1) << 22;

// points[first, first + n) relative to the surface's origin, in float.
std::vector<abi::vec4> relative(const MpuDeviceSurface& s, const std::vector<Eigen::Vector3d>& points, size_t first,
                                size_t n) {
  std::vector<abi::vec4> in(n);
  for (size_t i = 0; i < n; ++i) in[i] = s.local(points[first + i]);
  return in;
}

}  // namespace

std::vector<abi::vec4> pack_leaves(const mpu::MpuSurface& s, const Eigen::Vector3d& origin) {
  std::vector<abi::vec4> packed(s.leaves.size() * MPU_LEAF_VEC4);
  for (size_t i = 0; i < s.leaves.size(); ++i) {
    const mpu::Leaf& l = s.leaves[i];
    abi::vec4* p = &packed[i * MPU_LEAF_VEC4];
    const Eigen::Vector3d c = l.centre - origin;
    p[0] = {float(c.x()), float(c.y()), float(c.z()), float(l.radius)};
    // The frame rows' fourth components: 1/R, then coefficients 19 and 20 (u²w, uvw);
    // coefficient 21 (v²w) follows the first 19 in the fifth coefficient vec4.
    const float fourth[3] = {float(1.0 / l.radius), float(l.coeffs[19]), float(l.coeffs[20])};
    for (int r = 0; r < 3; ++r) p[1 + r] = {float(l.frame(r, 0)), float(l.frame(r, 1)), float(l.frame(r, 2)), fourth[r]};
    float coeffs[20] = {};
    for (int k = 0; k < 19; ++k) coeffs[k] = float(l.coeffs[size_t(k)]);
    coeffs[19] = float(l.coeffs[21]);
    for (int v = 0; v < 5; ++v) p[4 + v] = {coeffs[4 * v], coeffs[4 * v + 1], coeffs[4 * v + 2], coeffs[4 * v + 3]};
  }
  return packed;
}

MpuDeviceSurface::MpuDeviceSurface(Context& ctx, const mpu::MpuSurface& s) {
  origin = s.box_min + Eigen::Vector3d::Constant(0.5 * s.box_size);
  leaves = upload_vector(ctx, pack_leaves(s, origin));
  offsets = upload_vector(ctx, s.grid.offsets);
  leaf_ids = upload_vector(ctx, s.grid.leaf_ids);
  const Eigen::Vector3d lo = s.box_min - origin;
  push.box_min_x = float(lo.x());
  push.box_min_y = float(lo.y());
  push.box_min_z = float(lo.z());
  push.inv_cell = float(1.0 / s.cell_size());
  push.nx = s.grid.dims[0];
  push.ny = s.grid.dims[1];
  push.nz = s.grid.dims[2];
  push.far_value = float(s.box_size);
}

MpuEvalKernel::MpuEvalKernel(Context& ctx)
    : ctx_(ctx), eval_(ctx, kSpv_mpu_eval, kBindings, sizeof(abi::MpuPush), default_workgroup_size(ctx)) {}

std::vector<mpu::EvalRow> MpuEvalKernel::run(const MpuDeviceSurface& s, const std::vector<Eigen::Vector3d>& points,
                                             std::map<std::string, double>& kernel_ms) {
  std::vector<mpu::EvalRow> rows(points.size());
  for (size_t first = 0; first < points.size(); first += kChunk) {
    const size_t n = std::min(kChunk, points.size() - first);
    const std::vector<abi::vec4> in = relative(s, points, first, n);
    Buffer pts(ctx_, n * sizeof(abi::vec4), kStorage), fg(ctx_, n * sizeof(abi::vec4), kStorage),
        curv(ctx_, n * sizeof(abi::vec4), kStorage);
    pts.upload(in.data(), n * sizeof(abi::vec4));
    abi::MpuPush push = s.push;
    const Grid grid = grid_for(ctx_, n, eval_.workgroup_size());
    push.count = uint32_t(n);
    push.row = grid.row;
    Recorder rec(ctx_);
    const Buffer* bufs[] = {s.leaves.get(), s.offsets.get(), s.leaf_ids.get(), &pts, &fg, &curv};
    rec.dispatch(eval_, bufs, &push, grid, "mpu_eval");
    rec.submit_and_wait(kernel_ms);
    const auto a = fg.read<abi::vec4>(n), c = curv.read<abi::vec4>(n);
    for (size_t i = 0; i < n; ++i) {
      mpu::EvalRow& r = rows[first + i];
      for (int d = 0; d < 3; ++d) r.x[d] = points[first + i][d];
      r.f = a[i].x;
      r.g[0] = a[i].y;
      r.g[1] = a[i].z;
      r.g[2] = a[i].w;
      r.k1 = c[i].x;
      r.k2 = c[i].y;
      r.gauss = c[i].z;
      r.mean = c[i].w;
    }
  }
  return rows;
}

std::vector<double> MpuEvalKernel::run_f(const MpuDeviceSurface& s, const std::vector<Eigen::Vector3d>& points,
                                         std::map<std::string, double>& kernel_ms) {
  std::vector<double> f(points.size());
  for (size_t first = 0; first < points.size(); first += kChunk) {
    const size_t n = std::min(kChunk, points.size() - first);
    const std::vector<abi::vec4> in = relative(s, points, first, n);
    // Host-visible input and output: one submission a call (the triangulation makes one a
    // repair round).
    Buffer pts(ctx_, n * sizeof(abi::vec4), kStorage, Buffer::Kind::kStaging),
        fg(ctx_, n * sizeof(abi::vec4), kStorage, Buffer::Kind::kStaging), unused(ctx_, sizeof(abi::vec4), kStorage);
    pts.upload(in.data(), n * sizeof(abi::vec4));
    abi::MpuPush push = s.push;
    const Grid grid = grid_for(ctx_, n, eval_.workgroup_size());
    push.count = uint32_t(n);
    push.row = grid.row;
    push.value_only = 1;
    Recorder rec(ctx_);
    const Buffer* bufs[] = {s.leaves.get(), s.offsets.get(), s.leaf_ids.get(), &pts, &fg, &unused};
    rec.dispatch(eval_, bufs, &push, grid, "mpu_eval_f");
    rec.submit_and_wait(kernel_ms);
    const auto a = fg.read<abi::vec4>(n);
    for (size_t i = 0; i < n; ++i) f[first + i] = a[i].x;
  }
  return f;
}

}  // namespace mpumesh::vk
