// Components of a triangulation that lie on sheets of the fit away from the data, for the
// restricted Delaunay triangulation to drop (mesh/restricted_delaunay.h).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace mpumesh {

// Per triangle: whether its component (triangles joined through shared vertices) holds a
// vertex v with sampled(v), and fewer than half of its vertices with off(v) (when given).
// restricted_delaunay keeps only those. A component that no particle or lost-sheet point
// holds was made by repair points alone, on a sheet of f that no particle reached. The
// particles start at the data points and stay on f = 0, so every sheet the data support
// holds some; such a component lies on a spurious sheet of the fit (on the sample CT: 4
// repair points 18-22 mm from any bone, in the air by the volume's cut face, where f < 0;
// a tetrahedron with 10 mm edges). off(v): a repair point farther than a reach from every
// particle; a component mostly of those lies on such a sheet too, joined to the data by
// the one particle whose Voronoi cell reaches it (on the CT: 12 repair points 14-27 mm
// from any bone and one particle by the cut face). *unsampled: how many components are
// dropped.
std::vector<char> sampled_components(const std::vector<std::array<uint32_t, 3>>& triangles, size_t vertices,
                                     const std::function<bool(uint32_t)>& sampled, int64_t* unsampled = nullptr,
                                     const std::function<bool(uint32_t)>& off = nullptr);

}  // namespace mpumesh
