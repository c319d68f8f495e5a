#include "kernels/complex_step_vk.h"

#include <algorithm>
#include <limits>

#include "complex_step.spv.h"
#include "kernels/mpu_eval_vk.h"
#include "mpu/mpu_surface.h"
#include "multi/material_field.h"
#include "multi/region_support.h"
#include "vk/command.h"

namespace mpumesh::vk {
namespace {

std::vector<Binding> bindings() {
  std::vector<Binding> b;
  for (uint32_t id = CX_BIND_LEAVES; id <= CX_BIND_OUT_STATE; ++id) b.push_back({id, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  return b;
}

abi::vec4 vec4_of(const Eigen::Vector3d& v, double w) { return {float(v.x()), float(v.y()), float(v.z()), float(w)}; }

// The fits in the table's order: the labels' (region r is fit r - 1), the parts' contact
// unions, the labels' union.
std::vector<const mpu::MpuSurface*> table_order(const multi::MaterialField& field) {
  std::vector<const mpu::MpuSurface*> all = field.fits();
  all.insert(all.end(), field.unions().fits.begin(), field.unions().fits.end());
  if (field.outside()) all.push_back(field.outside());
  return all;
}

// The centre of the fits' cubes' bounding box: the positions' origin.
Eigen::Vector3d centre_of(const std::vector<const mpu::MpuSurface*>& fits) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const mpu::MpuSurface* s : fits) {
    lo = lo.cwiseMin(s->box_min);
    hi = hi.cwiseMax(s->box_min + Eigen::Vector3d::Constant(s->box_size));
  }
  return fits.empty() ? Eigen::Vector3d::Zero() : Eigen::Vector3d(0.5 * (lo + hi));
}

// Every fit's leaves, offsets and leaf ids concatenated, and its row of the table.
void pack_fits(const std::vector<const mpu::MpuSurface*>& fits, const Eigen::Vector3d& origin,
               std::vector<abi::vec4>& leaves, std::vector<uint32_t>& offsets, std::vector<uint32_t>& ids,
               std::vector<abi::CxFit>& table) {
  for (const mpu::MpuSurface* s : fits) {
    abi::CxFit f{};
    f.grid_min = vec4_of(s->box_min - origin, 1.0 / s->cell_size());
    f.dims = {s->grid.dims[0], s->grid.dims[1], s->grid.dims[2], uint32_t(leaves.size() / MPU_LEAF_VEC4)};
    f.bases = {uint32_t(offsets.size()), uint32_t(ids.size()), 0, 0};
    // Where the fit holds (mpu/data_box.h: its points' box widened by 0.5% of its cube).
    const double margin = 0.005 * s->box_size;
    f.data_min = vec4_of(s->data_min - Eigen::Vector3d::Constant(margin) - origin, s->box_size);
    f.data_max = vec4_of(s->data_max + Eigen::Vector3d::Constant(margin) - origin, 0);
    table.push_back(f);
    const std::vector<abi::vec4> own = pack_leaves(*s, origin);
    leaves.insert(leaves.end(), own.begin(), own.end());
    offsets.insert(offsets.end(), s->grid.offsets.begin(), s->grid.offsets.end());
    ids.insert(ids.end(), s->grid.leaf_ids.begin(), s->grid.leaf_ids.end());
  }
}

// The regions' rows (support boxes and contact groups) and their support bits, with the
// map's layout in the push block.
void pack_regions(const multi::MaterialField& field, const Eigen::Vector3d& origin, std::vector<abi::CxRegion>& rows,
                  std::vector<uint32_t>& bits, abi::ComplexPush& push) {
  const multi::RegionSupport* sup = field.support();
  const auto& group = field.unions().group;
  rows.assign(size_t(field.regions()), abi::CxRegion{});
  for (int r = 0; r < field.regions(); ++r) {
    abi::CxRegion& row = rows[size_t(r)];
    if (r > 0 && !group.empty() && group[size_t(r - 1)] >= 0) row.hi.w = uint32_t(group[size_t(r - 1)] + 1);
    if (!sup) continue;
    const multi::RegionSupport::Box& b = sup->box(r);
    row.lo = {uint32_t(b.lo[0]), uint32_t(b.lo[1]), uint32_t(b.lo[2]), uint32_t(bits.size())};
    row.hi.x = uint32_t(b.hi[0]);
    row.hi.y = uint32_t(b.hi[1]);
    row.hi.z = uint32_t(b.hi[2]);
    // 64 voxels a word, lower half first: the same bits as 32-bit words.
    for (const uint64_t w : sup->bits(r)) {
      bits.push_back(uint32_t(w));
      bits.push_back(uint32_t(w >> 32));
    }
  }
  push.support = sup ? 1 : 0;
  if (!sup) return;
  for (int d = 0; d < 3; ++d) {
    for (int c = 0; c < 3; ++c) push.to_index[3 * d + c] = float(sup->to_index()(d, c) / sup->spacing()[d]);
    push.map_origin[d] = float(sup->origin()[d] - origin[d]);
    push.map_dims[d] = uint32_t(sup->dims()[size_t(d)]);
  }
}

}  // namespace

MaterialDeviceField::MaterialDeviceField(Context& ctx, const multi::MaterialField& field) {
  const std::vector<const mpu::MpuSurface*> all = table_order(field);
  origin = centre_of(all);
  std::vector<abi::vec4> packed;
  std::vector<uint32_t> offs, ids, bits;
  std::vector<abi::CxFit> table;
  pack_fits(all, origin, packed, offs, ids, table);
  std::vector<abi::CxRegion> rows;
  pack_regions(field, origin, rows, bits, push);
  push.regions = uint32_t(field.regions());
  push.unions = uint32_t(field.unions().fits.size());
  push.outside = field.outside() ? uint32_t(all.size() - 1) : CX_NONE;
  push.contact = float(field.contact());
  push.depth = float(field.depth());
  leaves = upload_vector(ctx, packed);
  offsets = upload_vector(ctx, offs);
  leaf_ids = upload_vector(ctx, ids);
  fits = upload_vector(ctx, table);
  regions = upload_vector(ctx, rows);
  support = upload_vector(ctx, bits);
}

ComplexStepKernel::ComplexStepKernel(Context& ctx)
    : ctx_(ctx), step_(ctx, kSpv_complex_step, bindings(), sizeof(abi::ComplexPush), default_workgroup_size(ctx)) {}

void ComplexStepKernel::run(const MaterialDeviceField& field, multi::ComplexBatch& batch,
                            std::map<std::string, double>& kernel_ms) {
  const size_t n = batch.in.size();
  batch.out = batch.in;
  batch.ok.assign(n, 0);
  if (n == 0) return;
  std::vector<abi::vec4> pos(n);
  std::vector<abi::ivec4> regions(n);
  std::vector<uint32_t> kind(n);
  for (size_t i = 0; i < n; ++i) {
    const multi::ComplexParticle& q = batch.in[i];
    pos[i] = vec4_of(q.p - field.origin, q.spacing);
    regions[i] = {q.regions[0], q.regions[1], q.regions[2], q.regions[3]};
    kind[i] = uint32_t(q.kind);
  }
  const auto b_pos = upload_vector(ctx_, pos), b_regions = upload_vector(ctx_, regions),
             b_kind = upload_vector(ctx_, kind), b_first = upload_vector(ctx_, batch.first),
             b_neighbours = upload_vector(ctx_, batch.neighbours);
  Buffer b_out(ctx_, n * sizeof(abi::vec4), kStorage), b_out_regions(ctx_, n * sizeof(abi::ivec4), kStorage),
      b_state(ctx_, n * sizeof(uint32_t), kStorage);
  abi::ComplexPush push = field.push;
  const Grid grid = grid_for(ctx_, n, step_.workgroup_size());
  push.count = uint32_t(n);
  push.row = grid.row;
  push.step = uint32_t(batch.step);
  Recorder rec(ctx_);
  const Buffer* bufs[] = {field.leaves.get(),  field.offsets.get(), field.leaf_ids.get(), field.fits.get(),
                          field.regions.get(), field.support.get(), b_pos.get(),          b_regions.get(),
                          b_kind.get(),        b_first.get(),       b_neighbours.get(),   &b_out,
                          &b_out_regions,      &b_state};
  rec.dispatch(step_, bufs, &push, grid, "complex_step");
  rec.submit_and_wait(kernel_ms);
  const auto out = b_out.read<abi::vec4>(n);
  const auto out_regions = b_out_regions.read<abi::ivec4>(n);
  const auto state = b_state.read<uint32_t>(n);
  for (size_t i = 0; i < n; ++i) {
    if (!(state[i] & 1u)) continue;  // as it was, in double
    multi::ComplexParticle& q = batch.out[i];
    q.p = Eigen::Vector3d(out[i].x, out[i].y, out[i].z) + field.origin;
    q.regions = {out_regions[i].x, out_regions[i].y, out_regions[i].z, out_regions[i].w};
    q.kind = multi::ParticleKind(state[i] >> 1);
    batch.ok[i] = 1;
  }
}

}  // namespace mpumesh::vk
