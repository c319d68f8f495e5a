// The particles of a multi-material complex (docs/method.md "Several labels"), junctions
// first, after Meyer, Kirby & Whitaker (2008): the curves where three regions meet are
// found and sampled before the interfaces, and held while the interfaces are sampled.
//   1. Seeds: the vertices of adaptive samplings that already follow each surface's
//      curvature (each label's own mesh), each with its spacing (its mean edge length
//      there). Each interface (a, b), a < b, is taken from one of them: label b's mesh
//      for (0, b), label a's for a label pair, so that no interface is sampled twice. A
//      seed goes onto its interface f_a = f_b by Newton steps.
//   2. Junctions: a seed whose third region is within one spacing of its two goes onto
//      the curve of the three (and onto the point of four, where a fourth region is as
//      near: a corner, held); the curve's points are thinned to 0.6 spacings, spread
//      along the curve by a one-dimensional repulsion, and the curve's gaps filled to
//      0.6 spacings.
//   3. Interfaces: a seed within 0.6 spacings of a junction point, or of a kept seed of
//      another surface's sampling, is dropped; the rest are relaxed by a short-range
//      repulsion in their interface's tangent plane, projected back each step, the
//      junction points held. Every step updates all particles at once, so the result does
//      not depend on the threads.
// The per-particle steps (multi/complex_step_ref.h) run on the backend given: the CPU
// reference, or shaders/complex_step.comp on a Vulkan device.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

#include "multi/complex_step_ref.h"
#include "multi/material_field.h"

namespace mpumesh {
class ComputeBackend;
}

namespace mpumesh::multi {

struct Seed {
  Eigen::Vector3d p;
  double spacing = 0;  // mm
  int source = 0;      // the region whose surface it was sampled on
};

struct ComplexSampleStats {
  int64_t seeds = 0, off_interface = 0;  // seeds taken, seeds that did not converge
  int64_t other_source = 0;              // seeds on an interface another sampling covers
  int64_t merged = 0;                    // dropped near a junction or another sampling
  int64_t interface_particles = 0, junction_particles = 0, corners = 0;
  int iterations = 0;
  double seconds = 0;
};

struct ComplexSampleOptions {
  int relax_iterations = 12;
  int junction_iterations = 20;
};

std::vector<ComplexParticle> sample_complex(const MaterialField& field, const std::vector<Seed>& seeds,
                                            const ComplexSampleOptions& options, ComputeBackend& backend,
                                            ComplexSampleStats* stats = nullptr);

}  // namespace mpumesh::multi
