// The per-particle steps of the complex's sampling (multi/complex_sampling.h), each
// computed for every particle of a batch from the state before the step: the
// double-precision CPU reference of shaders/complex_step.comp, which the Vulkan backend
// runs (ComputeBackend::complex_steps).
//   kOntoInterface     a seed onto the interface of its two most inside regions
//   kJunctionCandidate an interface particle whose third region is within a spacing onto
//                      the curve of the three (or the point of four: a corner)
//   kRelaxJunction     a junction particle pushed along its curve by its neighbours and
//                      projected back; corners held
//   kRelaxInterface    an interface particle pushed in its tangent plane by its
//                      neighbours and projected back onto its (possibly new) interface;
//                      junction particles and corners held
// The relaxations read each particle's neighbours (ComplexBatch::first, neighbours),
// found before the step within its reach (complex_reach).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

#include "multi/material_field.h"

namespace mpumesh::multi {

enum class ParticleKind : uint8_t { kInterface = 2, kJunction = 3, kCorner = 4 };

struct ComplexParticle {
  Eigen::Vector3d p;
  double spacing = 0;
  ParticleKind kind = ParticleKind::kInterface;
  // The regions it lies between, ascending; unused entries -1.
  std::array<int, 4> regions{-1, -1, -1, -1};
};

enum class ComplexStep : uint32_t { kOntoInterface = 0, kJunctionCandidate = 1, kRelaxJunction = 2, kRelaxInterface = 3 };

// A seed goes at most this many spacings onto its interface or junction.
inline constexpr double kComplexReach = 2.0;
// The relaxations' repulsion reaches this many spacings; a step moves at most this
// fraction of one.
inline constexpr double kRelaxReach = 1.3;
inline constexpr double kRelaxStepCap = 0.25;

// The radius, in the particle's spacings, within which a relaxation step reads its
// neighbours: the junctions' reach, or for an interface particle the reach of a pair
// whose other spacing is twice its own (the step drops pairs beyond their mean reach).
inline double complex_reach(ComplexStep step) {
  return step == ComplexStep::kRelaxJunction ? kRelaxReach : 1.5 * kRelaxReach;
}

struct ComplexBatch {
  ComplexStep step = ComplexStep::kOntoInterface;
  std::vector<ComplexParticle> in;
  // The relaxations' neighbours of particle i: neighbours[first[i] .. first[i + 1]),
  // indices into `in` (i itself may be among them).
  std::vector<uint32_t> first, neighbours;
  // Written by the step: where each particle went, and whether it got there (false: `out`
  // holds the particle as it was). A particle the step holds is copied with ok false.
  std::vector<ComplexParticle> out;
  std::vector<uint8_t> ok;
};

// The neighbours of every particle of `batch.in` within complex_reach(batch.step) of its
// spacings (a k-d tree search; the order the tree gives).
void find_neighbours(ComplexBatch& batch);

// The step for particle i of `batch` (the reference, in double precision).
bool complex_step(const MaterialField& field, const ComplexBatch& batch, size_t i, ComplexParticle& out);

// The step for every particle (in parallel; each particle's result depends on the batch's
// input alone).
void complex_steps_ref(const MaterialField& field, ComplexBatch& batch);

}  // namespace mpumesh::multi
