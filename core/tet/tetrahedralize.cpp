#include "tet/tetrahedralize.h"

#include <fmt/format.h>

#include <cmath>
#include <unordered_map>

#include "common/error.h"
#include "common/option_names.h"
#include "mesh/topology.h"
#include "tet/sliver_cavities.h"
#include "tet/tetgen_steps.h"

namespace mpumesh {
namespace {

using namespace tetgen_steps;

// Step 4: the regions, without the cavities; the boundary triangles, outward.
TetMesh to_mesh(const tetgenio& out, const SurfaceFaces& input, TetStats& st) {
  TetMesh m;
  const std::vector<std::array<uint32_t, 4>> tets = positive_tets(out, m.nodes);
  const size_t nt = tets.size();
  const Components c = solid_components(tets, input);
  // Whether a component's surface faces look out of it (as the surface's triangles do from
  // the solid) or into it (a cavity).
  std::unordered_map<uint32_t, int64_t> vote;  // component -> faces out minus faces in
  for (const Components::Face& f : c.faces)
    vote[c.component[f.tet]] += faces_out_of(m.nodes, tets[f.tet], f.face, *input.at(f.key)) ? 1 : -1;
  // Regions numbered in order of their first tetrahedron; cavities dropped.
  std::unordered_map<uint32_t, int32_t> number;
  std::vector<int32_t> region(nt, 0);
  for (uint32_t t = 0; t < nt; ++t) {
    const uint32_t r = c.component[t];
    if (vote[r] <= 0) continue;
    const auto [it, fresh] = number.try_emplace(r, int32_t(number.size()) + 1);
    region[t] = it->second;
  }
  for (const auto& [r, v] : vote) st.cavities_removed += v <= 0;
  for (uint32_t t = 0; t < nt; ++t)
    if (region[t] > 0) m.tets.push_back(tets[t]), m.region.push_back(region[t]);
  m.regions = int32_t(number.size());
  for (const Components::Face& f : c.faces) {
    const int32_t r = region[f.tet];
    if (r == 0) continue;
    const auto& v = tets[f.tet];
    m.boundary.push_back({v[size_t(kTetFace[f.face][0])], v[size_t(kTetFace[f.face][1])], v[size_t(kTetFace[f.face][2])]});
    m.boundary_region.push_back(r);
  }
  return m;
}

}  // namespace

InputError volume_mesh_error(const std::string& input, const InputError& e) {
  const std::string what = e.what();
  const std::string prefix = "tetmesh: ";
  return InputError(input + ": volume mesh: " + (what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what));
}

void validate(const TetOptions& o) {
  auto need = [&](bool ok, const char* name, const char* what) {
    if (!ok) throw InputError(option_ref(name) + " must be " + what);
  };
  need(std::isfinite(o.size) && o.size >= 0, "volume_size", "zero (automatic) or a positive length (mm)");
  need(std::isfinite(o.grading) && o.grading > 0 && o.grading <= 10, "volume_grading", "in (0, 10] (mm per mm)");
}

TetMesh tetrahedralize(const TriangleMesh& input, const TetOptions& opt, TetStats* stats_out,
                       const ProgressFn& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  require_closed_manifold(input, "tetmesh", "the surface", "a volume mesh fills a closed surface");
  if (!analyze_topology(input).oriented)
    throw InputError("tetmesh: the surface is not consistently oriented; a volume mesh needs its inside known");
  TetStats st;
  st.surface_points = int64_t(input.vertices.size());
  for (const auto& t : input.triangles)
    st.surface_volume += input.vertices[t[0]].dot(input.vertices[t[1]].cross(input.vertices[t[2]])) / 6;
  if (!(st.surface_volume > 0))
    throw InputError(fmt::format("tetmesh: the surface encloses {:.3g} mm3 (its triangles face inward): nothing to fill",
                                 st.surface_volume));
  const std::vector<double> spacing = mean_edge_lengths(input);
  st.size = interior_size(spacing, opt.size);
  const std::unique_ptr<tetgenio> out = quality_tetrahedra(input, spacing, opt, st.size, FlatSide::kSurfaceOutward, st,
                                                                progress);
  TetMesh m = to_mesh(*out, surface_faces(input), st);
  st.perturbed = perturb_slivers(m, uint32_t(input.vertices.size()));
  st.sliver_cavities = refill_sliver_cavities(m, kSliverBelowDeg);
  finish(m, input.vertices.size(), t0, st);
  if (stats_out) *stats_out = st;
  tell(progress, 1);
  return m;
}

}  // namespace mpumesh
