// Per-vertex normals and curvature for a mesh (TriangleMesh::normals, ::curvature): from
// the MPU surface it was made from, or estimated from the mesh alone for any other mesh.
// Signs follow the MPU evaluation (core/mpu/mpu_eval_ref.h): normals point out, and a
// convex part has negative k1, k2 and H (a sphere of radius r: k = -1/r, K = 1/r^2).
#pragma once

#include "compute/compute_backend.h"
#include "geometry/triangle_mesh.h"
#include "mpu/mpu_surface.h"

namespace mpumesh {

// Evaluates the surface at every vertex (on the backend given): normal = ∇f/|∇f|, and
// k1, k2, K, H there.
void attach_surface_attributes(TriangleMesh& mesh, const mpu::MpuSurface& surface, ComputeBackend& backend);

// For a mesh without a surface: area-weighted normals (made to point out of the enclosed
// volume), K from the angle deficit and H from the cotangent Laplacian, both over the
// mixed Voronoi area (Meyer, Desbrun, Schröder and Barr 2003), k1, k2 = H ± sqrt(H² − K).
void estimate_mesh_curvature(TriangleMesh& mesh);

// Each vertex's Gaussian curvature at the mesh's own scale: its K (mesh.curvature, which
// must be there) averaged over the vertices within its spacing (the mean length of its
// edges) whose normals agree (particles/sizing_field.h). A mesh with edges s long cannot
// follow a bend narrower than s: this is the curvature its spacing can follow, and it
// shows a CT's anatomy where the K at each vertex shows the noise of thin plates' rims.
std::vector<double> gauss_at_mesh_scale(const TriangleMesh& mesh);

// The curvature at a scale: each vertex's k1 and k2 (mesh.curvature, which must be there
// with mesh.normals) replaced by their means over the vertices within 3 sigma whose
// normals lie within 60° of its own (so that the two faces of a plate do not mix) and
// whose curvature is finite, weighted by the vertices' areas and a Gaussian of the
// distance, exp(-d² / 2 sigma²); K = k1 k2 and H = (k1 + k2) / 2 of the means. A label
// map's fit follows its grid's steps at the scale of its smallest balls
// (mpu/fit_tolerance.h): the curvature its mesh carries is the fit's at that scale, where
// the steps' bumps average out and the shape's bends remain.
void smooth_curvature(TriangleMesh& mesh, double sigma);

}  // namespace mpumesh
