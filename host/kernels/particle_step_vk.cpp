#include "kernels/particle_step_vk.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "particle_step_grid_count.spv.h"
#include "particle_step_grid_scatter.spv.h"
#include "particle_step_project.spv.h"
#include "particle_step_repulsion.spv.h"
#include "particle_step_thickness.spv.h"
#include "shared/particle_step_abi.h"
#include "vk/command.h"

namespace mpumesh::vk {
namespace {

std::vector<Binding> bindings(std::initializer_list<uint32_t> ids) {
  std::vector<Binding> b;
  for (uint32_t id : ids) b.push_back({id, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  return b;
}

}  // namespace

ParticleKernel::ParticleKernel(Context& ctx)
    : ctx_(ctx),
      count_(ctx, kSpv_particle_step_grid_count, bindings({PT_BIND_POS, PT_BIND_CELL, PT_BIND_RANK, PT_BIND_START}),
             sizeof(abi::ParticlePush), default_workgroup_size(ctx)),
      scatter_(ctx, kSpv_particle_step_grid_scatter, bindings({PT_BIND_CELL, PT_BIND_RANK, PT_BIND_START, PT_BIND_ORDER}),
               sizeof(abi::ParticlePush), default_workgroup_size(ctx)),
      repulsion_(ctx, kSpv_particle_step_repulsion,
                 bindings({PT_BIND_POS, PT_BIND_POS_NEW, PT_BIND_NORMAL, PT_BIND_STATS, PT_BIND_CELL, PT_BIND_START,
                           PT_BIND_ORDER}),
                 sizeof(abi::ParticlePush), default_workgroup_size(ctx)),
      project_(ctx, kSpv_particle_step_project,
               bindings({MPU_BIND_LEAVES, MPU_BIND_OFFSETS, MPU_BIND_LEAF_IDS, PT_BIND_POS, PT_BIND_POS_NEW,
                         PT_BIND_NORMAL, PT_BIND_CURV}),
               sizeof(abi::ParticlePush), default_workgroup_size(ctx)),
      thickness_(ctx, kSpv_particle_step_thickness,
                 bindings({MPU_BIND_LEAVES, MPU_BIND_OFFSETS, MPU_BIND_LEAF_IDS, PT_BIND_POS, PT_BIND_NORMAL,
                           PT_BIND_STATS}),
                 sizeof(abi::ParticlePush), default_workgroup_size(ctx)),
      scan_(ctx) {}

namespace {

// The surface's part of the particle push block.
abi::ParticlePush surface_push(const MpuDeviceSurface& s, size_t n) {
  abi::ParticlePush push{};
  push.box_min_x = s.push.box_min_x;
  push.box_min_y = s.push.box_min_y;
  push.box_min_z = s.push.box_min_z;
  push.inv_cell = s.push.inv_cell;
  push.nx = s.push.nx;
  push.ny = s.push.ny;
  push.nz = s.push.nz;
  push.far_value = s.push.far_value;
  push.count = uint32_t(n);
  return push;
}

}  // namespace

void ParticleKernel::project(const MpuDeviceSurface& s, particles::ParticleState& st, const particles::StepParams& p,
                             bool with_curvature, std::map<std::string, double>& kernel_ms) {
  const size_t n = st.size();
  if (n == 0) return;
  const VkDeviceSize v4 = n * sizeof(abi::vec4);
  std::vector<abi::vec4> in(n);
  for (size_t i = 0; i < n; ++i) in[i] = s.local(st.x[i], st.sigma[i]);
  // Host-visible input and outputs: one submission.
  constexpr auto host = Buffer::Kind::kStaging;
  Buffer b_in(ctx_, v4, kStorage, host), b_pos(ctx_, v4, kStorage, host), b_nrm(ctx_, v4, kStorage, host),
      b_curv(ctx_, v4, kStorage, host);
  b_in.upload(in.data(), v4);
  abi::ParticlePush push = surface_push(s, n);
  push.newton_steps = uint32_t(std::max(p.newton_steps, 1));
  push.curvature = with_curvature ? 1 : 0;
  const Grid grid = grid_for(ctx_, n, project_.workgroup_size());
  push.row = grid.row;
  Recorder rec(ctx_);
  const Buffer* bufs[] = {s.leaves.get(), s.offsets.get(), s.leaf_ids.get(), &b_pos, &b_in, &b_nrm, &b_curv};
  rec.dispatch(project_, bufs, &push, grid, "particle_step_project");
  rec.submit_and_wait(kernel_ms);
  const auto pos = b_pos.read<abi::vec4>(n), nrm = b_nrm.read<abi::vec4>(n), curv = b_curv.read<abi::vec4>(n);
  st.normal.resize(n);
  st.distance.resize(n);
  st.curv.resize(n);
  for (size_t i = 0; i < n; ++i) {
    st.x[i] = Eigen::Vector3d(pos[i].x, pos[i].y, pos[i].z) + s.origin;
    st.normal[i] = Eigen::Vector3d(nrm[i].x, nrm[i].y, nrm[i].z);
    st.distance[i] = nrm[i].w;
    st.curv[i] = with_curvature ? mpu::Curvature{curv[i].x, curv[i].y, curv[i].z, curv[i].w} : mpu::Curvature{};
  }
}

std::vector<double> ParticleKernel::thickness(const MpuDeviceSurface& s, const std::vector<Eigen::Vector3d>& x,
                                              const std::vector<Eigen::Vector3d>& n,
                                              const std::vector<double>& max_dist,
                                              std::map<std::string, double>& kernel_ms) {
  const size_t count = x.size();
  std::vector<double> t(count, INFINITY);
  if (count == 0) return t;
  const VkDeviceSize v4 = count * sizeof(abi::vec4);
  std::vector<abi::vec4> in(count), dir(count);
  for (size_t i = 0; i < count; ++i) {
    // A reach that is not positive and finite (a lost particle) is sent as 0: none.
    const double reach = max_dist[i] > 0 && std::isfinite(max_dist[i]) ? max_dist[i] : 0.0;
    in[i] = s.local(x[i], reach);
    dir[i] = {float(n[i].x()), float(n[i].y()), float(n[i].z()), 0.f};
  }
  constexpr auto host = Buffer::Kind::kStaging;  // one submission (see project)
  Buffer b_pos(ctx_, v4, kStorage, host), b_nrm(ctx_, v4, kStorage, host), b_out(ctx_, v4, kStorage, host);
  b_pos.upload(in.data(), v4);
  b_nrm.upload(dir.data(), v4);
  abi::ParticlePush push = surface_push(s, count);
  const Grid grid = grid_for(ctx_, count, thickness_.workgroup_size());
  push.row = grid.row;
  Recorder rec(ctx_);
  const Buffer* bufs[] = {s.leaves.get(), s.offsets.get(), s.leaf_ids.get(), &b_pos, &b_nrm, &b_out};
  rec.dispatch(thickness_, bufs, &push, grid, "particle_step_thickness");
  rec.submit_and_wait(kernel_ms);
  const auto out = b_out.read<abi::vec4>(count);
  for (size_t i = 0; i < count; ++i) t[i] = out[i].x;  // +inf stays +inf
  return t;
}

namespace {

// The particles' positions (relative to the surface's origin, σ in w) and normals (the
// distance to f = 0 in w), as the shaders read them.
void pack_state(const MpuDeviceSurface& s, const particles::ParticleState& st, std::vector<abi::vec4>& pos,
                std::vector<abi::vec4>& nrm) {
  const size_t n = st.size();
  pos.resize(n);
  nrm.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d x = st.x[i] - s.origin;
    pos[i] = {float(x.x()), float(x.y()), float(x.z()), float(st.sigma[i])};
    nrm[i] = {float(st.normal[i].x()), float(st.normal[i].y()), float(st.normal[i].z()), float(st.distance[i])};
  }
}

// The push constants of a batch: the step's parameters, and the neighbour grid for the
// whole batch: cells of the largest interaction range, over the particles' box grown by
// the farthest they can move (clamped cells beyond it still find their neighbours in the
// 27 around). Returns the grid's cell count.
uint32_t batch_push(const MpuDeviceSurface& s, const particles::ParticleState& st, const particles::StepParams& p,
                    int iterations, abi::ParticlePush& push) {
  const size_t n = st.size();
  const double range = p.cutoff * std::min(p.sigma_cap, 1e6);
  double smax = 0;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d x = st.x[i] - s.origin;
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
    smax = std::max(smax, st.sigma[i]);
  }
  const double cell = std::max({range, p.cutoff * smax, (hi - lo).maxCoeff() / 1023.0, 1e-6});
  const double margin = iterations * p.max_move * std::max(smax, std::min(p.sigma_cap, 1e6));
  lo.array() -= margin;
  hi.array() += margin;
  push = surface_push(s, n);
  push.grid_x = float(lo.x());
  push.grid_y = float(lo.y());
  push.grid_z = float(lo.z());
  push.grid_inv_cell = float(1.0 / cell);
  uint32_t dims[3];
  for (int d = 0; d < 3; ++d) dims[d] = uint32_t(std::min(std::floor((hi[d] - lo[d]) / cell) + 1, 1024.0));
  push.gx = dims[0];
  push.gy = dims[1];
  push.gz = dims[2];
  push.dt = float(p.dt);
  push.mu = float(p.mu);
  push.desired_energy = float(p.desired_energy);
  push.rho = float(p.rho);
  push.beta = float(p.beta);
  push.phi = float(p.phi);
  push.cutoff = float(p.cutoff);
  push.max_move = float(p.max_move);
  push.sigma_change = float(p.sigma_change);
  push.sigma_cap = float(std::min(p.sigma_cap, 1e30));
  push.newton_steps = uint32_t(p.newton_steps);
  return dims[0] * dims[1] * dims[2];
}

// The state read back (positions, normals, curvature, then energy and speed), into st.
void unpack_state(const MpuDeviceSurface& s, const abi::vec4* back, particles::ParticleState& st) {
  const size_t n = st.size();
  const abi::vec4 *pos = back, *nrm = back + n, *curv = back + 2 * n, *stats = back + 3 * n;
  for (size_t i = 0; i < n; ++i) {
    st.x[i] = Eigen::Vector3d(pos[i].x, pos[i].y, pos[i].z) + s.origin;
    st.sigma[i] = pos[i].w;
    st.normal[i] = Eigen::Vector3d(nrm[i].x, nrm[i].y, nrm[i].z);
    st.distance[i] = nrm[i].w;
    st.curv[i] = {curv[i].x, curv[i].y, curv[i].z, curv[i].w};
    st.energy[i] = stats[i].x;
    st.speed[i] = stats[i].y;
  }
}

}  // namespace

void ParticleKernel::run(const MpuDeviceSurface& s, particles::ParticleState& st, const particles::StepParams& p,
                         int iterations, std::map<std::string, double>& kernel_ms) {
  const size_t n = st.size();
  if (n == 0 || iterations <= 0) return;
  std::vector<abi::vec4> pos, nrm;
  pack_state(s, st, pos, nrm);
  abi::ParticlePush push;
  const uint32_t cells = batch_push(s, st, p, iterations, push);
  const VkDeviceSize v4 = n * sizeof(abi::vec4), u1 = n * sizeof(uint32_t);
  Buffer b_pos(ctx_, v4, kStorage), b_new(ctx_, v4, kStorage), b_nrm(ctx_, v4, kStorage), b_curv(ctx_, v4, kStorage),
      b_stats(ctx_, v4, kStorage), b_cell(ctx_, u1, kStorage), b_rank(ctx_, u1, kStorage),
      b_start(ctx_, (cells + 1) * sizeof(uint32_t), kStorage), b_order(ctx_, u1, kStorage);
  // One submission per batch: the state goes up through one staging buffer at the start
  // of the command buffer and comes back through another at its end (a submission per
  // kernel, each waited for, costs a large share of a batch's time on a GPU).
  Buffer up(ctx_, 2 * v4, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, Buffer::Kind::kStaging);
  Buffer down(ctx_, 4 * v4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, Buffer::Kind::kStaging);
  std::memcpy(up.mapped(), pos.data(), v4);
  std::memcpy(static_cast<char*>(up.mapped()) + v4, nrm.data(), v4);
  const Grid grid = grid_for(ctx_, n, count_.workgroup_size());
  push.row = grid.row;
  Recorder rec(ctx_);
  rec.copy(up, b_pos, v4, 0, 0);
  rec.copy(up, b_nrm, v4, v4, 0);
  rec.barrier();
  std::vector<std::unique_ptr<Buffer>> scratch;
  const Buffer* count_bufs[] = {&b_pos, &b_cell, &b_rank, &b_start};
  const Buffer* scatter_bufs[] = {&b_cell, &b_rank, &b_start, &b_order};
  const Buffer* rep_bufs[] = {&b_pos, &b_new, &b_nrm, &b_stats, &b_cell, &b_start, &b_order};
  const Buffer* proj_bufs[] = {s.leaves.get(), s.offsets.get(), s.leaf_ids.get(), &b_pos, &b_new, &b_nrm, &b_curv};
  for (int it = 0; it < iterations; ++it) {
    rec.fill(b_start, 0);
    rec.barrier();
    rec.dispatch(count_, count_bufs, &push, grid, "particle_step_grid");
    rec.barrier();
    scan_.record(rec, b_start, cells + 1, scratch);
    rec.dispatch(scatter_, scatter_bufs, &push, grid, "particle_step_grid");
    rec.barrier();
    rec.dispatch(repulsion_, rep_bufs, &push, grid, "particle_step_repulsion");
    rec.barrier();
    push.curvature = it + 1 == iterations ? 1u : 0u;  // the curvature of the batch's end
    rec.dispatch(project_, proj_bufs, &push, grid, "particle_step_project");
    rec.barrier();
  }
  rec.copy(b_pos, down, v4, 0, 0);
  rec.copy(b_nrm, down, v4, 0, v4);
  rec.copy(b_curv, down, v4, 0, 2 * v4);
  rec.copy(b_stats, down, v4, 0, 3 * v4);
  rec.submit_and_wait(kernel_ms);
  unpack_state(s, static_cast<const abi::vec4*>(down.mapped()), st);
}

}  // namespace mpumesh::vk
