// Chan-Vese "active contours without edges" on each slice of a stack, the CPU reference of
// shaders/chan_vese_means.comp and shaders/chan_vese_update.comp (data contract: shaders/shared/chan_vese_abi.h).
//
// The scheme is the semi-implicit one of Chan and Vese (2001, eq. 9 with h = 1), in Jacobi
// form: every neighbour is taken from the previous iterate, so the CPU (double) and the GPU
// (float) compute the same map. With δ = ε / (π (ε² + φ²)), m = Δt δ(φ) μ and
//   C1 = 1/√(η² + (φ[i+1,j]-φ[i,j])²     + ((φ[i,j+1]-φ[i,j-1])/2)²)
//   C2 = 1/√(η² + (φ[i,j]-φ[i-1,j])²     + ((φ[i-1,j+1]-φ[i-1,j-1])/2)²)
//   C3 = 1/√(η² + ((φ[i+1,j]-φ[i-1,j])/2)² + (φ[i,j+1]-φ[i,j])²)
//   C4 = 1/√(η² + ((φ[i+1,j-1]-φ[i-1,j-1])/2)² + (φ[i,j]-φ[i,j-1])²)
//   φ' = (φ + m (C1 φ[i+1,j] + C2 φ[i-1,j] + C3 φ[i,j+1] + C4 φ[i,j-1])
//           + Δt δ (−ν − λ1 (u − c1)² + λ2 (u − c2)²)) / (1 + m (C1 + C2 + C3 + C4))
// and Neumann borders (indices clamped to the slice). φ' is a convex combination of
// neighbours plus a bounded data term, which is why the step is stable at μ Δt = 650.
// c1 and c2 are the means of u over φ >= 0 and φ < 0 in the slice, from exact integer sums.
#pragma once

#include <cstdint>
#include <vector>

namespace mpumesh::seg {

struct ChanVeseParams {
  double lambda1 = 1.0;
  double lambda2 = 7.0;  // the paper's value for bone
  double mu = 0.1 * 255.0 * 255.0;
  double nu = 0.0;
  double dt = 0.01;
  double epsilon = 1.0;  // width of the regularised Dirac δ, pixels
  double eta = 1e-4;     // keeps the curvature coefficients finite where φ is flat
  int iterations = 100;
};

// Throws InputError naming the parameter when one is out of range.
void validate(const ChanVeseParams& p);

struct ChanVeseStack {
  int64_t nx = 0, ny = 0, nz = 0;
  std::vector<float> u;    // windowed image, integers 0..255
  std::vector<float> phi;  // level set, inside >= 0
  int64_t slice_pixels() const { return nx * ny; }
};

struct ChanVeseResult {
  std::vector<float> phi;             // after the last iteration
  std::vector<double> c1, c2;         // per slice, the means used by the last iteration
};

// Region means of one slice: c1 over phi >= 0, c2 over phi < 0 (the CV_EMPTY_* values
// when a region is empty). Sums are exact integers, so both backends agree bit for bit
// up to the final division.
struct SliceMeans {
  double c1, c2;
  int64_t inside;
};
template <class Real>
SliceMeans slice_means(const float* u, const Real* phi, int64_t pixels);

// One Jacobi step on one slice: phi_out from phi_in.
template <class Real>
void chan_vese_step(const float* u, const Real* phi_in, Real* phi_out, int64_t nx, int64_t ny, SliceMeans means,
                    const ChanVeseParams& p);

// All iterations on every slice (double precision, slices in parallel).
ChanVeseResult chan_vese_ref(const ChanVeseStack& stack, const ChanVeseParams& p);

}  // namespace mpumesh::seg
