#include "kernels/marching_cubes_vk.h"

#include <stdexcept>

#include "mc/mc_table.h"
#include "marching_cubes_classify.spv.h"
#include "marching_cubes_generate.spv.h"
#include "shared/marching_cubes_abi.h"

namespace mpumesh::vk {
namespace {

const std::vector<Binding> kClassifyBindings = {
    {MC_BIND_FIELD, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, {MC_BIND_INFO, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {MC_BIND_VOFF, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},  {MC_BIND_TOFF, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {MC_BIND_TABLE, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}};
const std::vector<Binding> kGenerateBindings = {
    {MC_BIND_FIELD, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, {MC_BIND_INFO, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {MC_BIND_VOFF, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},  {MC_BIND_TOFF, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {MC_BIND_VERTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, {MC_BIND_TRIS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
    {MC_BIND_TABLE, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}};

// The case table packed for the shader: edges as nibbles, 8 per word, w = count.
std::vector<abi::uvec4> packed_table() {
  static_assert(3 * mc::kMaxTrianglesPerCube <= 24, "three words of nibbles hold the edges");
  std::vector<abi::uvec4> out(MC_TABLE_CASES);
  const auto& table = mc::case_table();
  for (size_t c = 0; c < out.size(); ++c) {
    uint32_t w[3] = {0, 0, 0};
    for (int s = 0; s < 3 * table[c].triangle_count; ++s)
      w[s / 8] |= uint32_t(table[c].edges[size_t(s)]) << (4 * (s % 8));
    out[c] = {w[0], w[1], w[2], uint32_t(table[c].triangle_count)};
  }
  return out;
}

}  // namespace

McKernel::McKernel(Context& ctx)
    : ctx_(ctx),
      classify_(ctx, kSpv_marching_cubes_classify, kClassifyBindings, sizeof(abi::McPush), default_workgroup_size(ctx)),
      generate_(ctx, kSpv_marching_cubes_generate, kGenerateBindings, sizeof(abi::McPush), default_workgroup_size(ctx)),
      scan_(ctx) {
  auto table = packed_table();
  table_ = std::make_unique<Buffer>(ctx, table.size() * sizeof(abi::uvec4), kUniform);
  table_->upload(table.data(), table.size() * sizeof(abi::uvec4));
}

mc::McMesh McKernel::run(const mc::McField& field, std::map<std::string, double>& kernel_ms) {
  const uint64_t n = uint64_t(field.point_count());
  if (n > UINT32_MAX / 4) throw std::length_error("volume too large for the GPU marching cubes (2^30 voxels)");
  Buffer f(ctx_, n * sizeof(float), kStorage), info(ctx_, n * 4, kStorage), voff(ctx_, n * 4, kStorage),
      toff(ctx_, n * 4, kStorage);
  f.upload(field.values.data(), n * sizeof(float));
  const Grid grid = grid_for(ctx_, n, classify_.workgroup_size());
  abi::McPush push{uint32_t(field.dims[0]), uint32_t(field.dims[1]), uint32_t(field.dims[2]), uint32_t(n),
                   grid.row, float(mc::kMinEdgeFraction), 0, 0};
  std::vector<std::unique_ptr<Buffer>> scratch;
  {
    Recorder rec(ctx_);
    const Buffer* bufs[] = {&f, &info, &voff, &toff, table_.get()};
    rec.dispatch(classify_, bufs, &push, grid, "marching_cubes_classify");
    rec.barrier();
    scan_.record(rec, voff, uint32_t(n), scratch);
    scan_.record(rec, toff, uint32_t(n), scratch);
    rec.submit_and_wait(kernel_ms);
  }
  scratch.clear();
  // The last grid point owns no edge and no cube, so its exclusive offsets are the totals.
  const uint32_t nv = voff.read<uint32_t>(1, n - 1)[0];
  const uint32_t nt = toff.read<uint32_t>(1, n - 1)[0];
  Buffer verts(ctx_, uint64_t(nv) * sizeof(abi::vec4), kStorage), tris(ctx_, uint64_t(nt) * 12, kStorage);
  {
    Recorder rec(ctx_);
    const Buffer* bufs[] = {&f, &info, &voff, &toff, &verts, &tris, table_.get()};
    rec.dispatch(generate_, bufs, &push, grid, "marching_cubes_generate");
    rec.submit_and_wait(kernel_ms);
  }
  mc::McMesh mesh;
  const auto v = verts.read<abi::vec4>(nv);
  mesh.grid_vertices.resize(nv);
  for (size_t i = 0; i < nv; ++i) mesh.grid_vertices[i] = {double(v[i].x), double(v[i].y), double(v[i].z)};
  mesh.triangles.resize(nt);
  if (nt) tris.download(mesh.triangles.data(), uint64_t(nt) * 12);
  return mesh;
}

}  // namespace mpumesh::vk
