// Mesh_3 with CGAL's parallel mode (Parallel_tag, TBB: as many threads as TBB's arena,
// which mpumesh's own stages use too).
#include "cgal_mesh3_run.h"

namespace mpumesh::bench {

Mesh3Result cgal_mesh3_parallel(const Volume& v, const Mesh3Params& p) { return mesh3::run<CGAL::Parallel_tag>(v, p); }

}  // namespace mpumesh::bench
