// Rigid (affine) motion of a part of a moving triangle mesh: one affine key
// per vertex step that maps the rest pose onto that step (the
// least-squares fit of Günther et al. 2006, §3.1, decompose/affine_fit.h).
// Element-wise interpolation of the keys applied to a rest vertex equals the
// interpolation of the mapped vertices, so an instance of the rest pose with
// these keys moves as the part does between steps, up to the fit's residual.
//
// The simplest form of keys that fits is kept: a translation per step (the
// linear part exactly the identity), else one linear part for every step
// with a translation per step, else an affine map per step. The simpler
// forms cost a ray less on its way into the instance
// (scene/instance_space.h: three subtractions, or six dot products without
// a per-ray inverse).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "mbrt/scene.h"

namespace mbrt::detail {

enum class KeyForm : uint8_t { Translation, ConstantLinear, Affine };
const char* toString(KeyForm form);

struct PartFit {
  bool fits = false;             // every vertex at every step within the tolerance
  bool moves = false;            // some vertex moves by more than the tolerance
  KeyForm form = KeyForm::Affine;
  std::vector<Affine3f> keys;    // per step: rest pose -> step (when fits)
  double maxResidual = 0;        // largest vertex distance, in units of the diagonal
  double diagonal = 0;           // of the rest pose's bounds
};

// Fits the vertices `vertices` (indices into g's buffers) of a triangle
// geometry, its step 0 the rest pose (whose key is then the identity
// exactly). `tolerance` is relative to the rest bounds' diagonal. Keys
// whose interpolation between steps comes close to a singular matrix are
// refused (the inverse that takes rays into the instance would be unstable).
PartFit fitPart(const Geometry& g, std::span<const uint32_t> vertices, double tolerance);

// The same fit from a rest pose kept apart: rest[i] is vertex vertices[i]
// as it was when the part was extracted (auto's refit: the instance's tree
// over that pose stays, its keys are fitted again to g's steps now).
PartFit refitPart(std::span<const Vec3f> rest, const Geometry& g, std::span<const uint32_t> vertices,
                  double tolerance);

// The vertices used by the given triangles of g, sorted, each once.
std::vector<uint32_t> usedVertices(const Geometry& g, std::span<const uint32_t> triangles);

}  // namespace mbrt::detail
