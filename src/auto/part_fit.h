// Rigid (affine) motion of a part of a moving triangle mesh: one affine key
// per vertex step that maps the rest pose (step 0) onto that step (the
// least-squares fit of Günther et al. 2006, §3.1, decompose/affine_fit.h).
// Element-wise interpolation of the keys applied to a rest vertex equals the
// interpolation of the mapped vertices, so an instance of the rest pose with
// these keys moves as the part does between steps, up to the fit's residual.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "mbrt/scene.h"

namespace mbrt::detail {

struct PartFit {
  bool fits = false;             // every vertex at every step within the tolerance
  bool moves = false;            // some vertex moves by more than the tolerance
  std::vector<Affine3f> keys;    // per step: rest pose -> step (when fits)
  double maxResidual = 0;        // largest vertex distance, in units of the diagonal
  double diagonal = 0;           // of the rest pose's bounds
};

// Fits the vertices `vertices` (indices into g's buffers) of a triangle
// geometry. `tolerance` is relative to the rest bounds' diagonal. Keys
// whose interpolation between steps comes close to a singular matrix are
// refused (the inverse that takes rays into the instance would be unstable).
PartFit fitPart(const Geometry& g, std::span<const uint32_t> vertices, double tolerance);

// The vertices used by the given triangles of g, sorted, each once.
std::vector<uint32_t> usedVertices(const Geometry& g, std::span<const uint32_t> triangles);

}  // namespace mbrt::detail
