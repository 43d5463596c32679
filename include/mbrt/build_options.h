// Which structure to build and how: the kinds and the build options.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mbrt {

enum class AccelKind {
  Brute,        // tests every primitive: the oracle
  BvhInterp,    // BVH with linear bounds over the whole shutter
  BvhSegments,  // one linear-bounds BVH per global time segment
  Frozen,       // static BVH of the scene frozen at BuildOptions::frozenTime
  Stbvh,        // Woop et al. 2017
  Msbvh,        // Grünschloß et al. 2011
  Mbkd,         // Yang et al. 2017
  FuzzyKd,      // Günther et al. 2006
  Embree,       // Intel Embree 3, when built in
  Auto,         // rigid motion extracted into instances, a kind chosen per object (docs/auto.md)
};

std::string_view toString(AccelKind kind);
std::optional<AccelKind> parseAccelKind(std::string_view name);
// The kinds this build of mbrt can construct, in a stable order.
std::vector<AccelKind> availableAccelKinds();

struct BuildOptions {
  AccelKind kind = AccelKind::Auto;  // as the command's default (docs/auto.md)
  int branching = 8;          // BVH node width: 2, 4 or 8
  int maxLeafSize = 8;        // primitives per BVH leaf at most
  int sahBins = 32;           // bins of the binned SAH
  float traversalCost = 1.0f;     // C_T of the SAH (intersection cost is 1)
  float frozenTime = 0.5f;    // time of the `frozen` kind
  size_t memoryBudget = 0;    // bytes the build may use; 0 = unlimited
  int maxInstanceDepth = 8;   // nesting of instances
  // `embree` only: Robust (RTC_SCENE_FLAG_ROBUST, watertight as mbrt; what the
  // oracle tests compare with), Default (Embree's default flags, what its
  // users run), Static (default flags, Embree's static BVH over the scene
  // frozen at frozenTime) or StaticRobust (that static BVH built with
  // RTC_SCENE_FLAG_ROBUST: the watertight kernel-to-kernel peer of `frozen`).
  // A field, not kinds: no test that walks every kind meets a non-watertight
  // structure, and no kind list changes.
  enum class EmbreeMode : uint8_t { Robust, Default, Static, StaticRobust } embreeMode = EmbreeMode::Robust;
  // `auto` only: a part becomes an instance when one affine key per step
  // reproduces every vertex within this fraction of the part's diagonal
  // (0: only exact fits), and the kind of every object below the top level
  // (none: chosen per object by cost; a near-rigid cluster keeps its own
  // tree, docs/auto.md), which also keeps the decomposition.
  float autoFitTolerance = 1e-5f;
  std::optional<AccelKind> autoLeafKind;
  // `auto` only: where the cost model's best candidates (kinds of an object,
  // or the decomposition against the whole scene as one object) lie within
  // its error, trace a sample of rays through each and keep the measured
  // best (docs/auto.md, "Measured confirmation"). The choice then depends
  // on the machine's timing; false keeps the model's choice, which depends
  // only on the scene and these options.
  bool autoConfirmByTrace = true;
  // `auto` only: the accel will follow new vertex data by Accel::refit (a
  // frame sequence; AccelUpdater sets it under its Refit and Auto policies).
  // Then `auto` builds only what refits: moving objects choose among the
  // kinds that refit in place (bvh-interp, msbvh), whose first refit would
  // otherwise rebuild any other, and deforming meshes are not decomposed
  // into near-rigid clusters, whose trees every refit makes again
  // (docs/auto.md, "Refit").
  bool autoForRefits = false;
};

// The one spelling of the Embree modes: "robust", "default", "static",
// "static-robust" (Python's embree_mode, the command's and the bench's).
std::string_view toString(BuildOptions::EmbreeMode mode);
std::optional<BuildOptions::EmbreeMode> parseEmbreeMode(std::string_view name);
// A row of Embree in the bench: "embree" (its default mode, what its users
// run), "embree-robust", "embree-static", "embree-static-robust"; and back.
std::string embreeRowName(BuildOptions::EmbreeMode mode);
std::optional<BuildOptions::EmbreeMode> parseEmbreeRow(std::string_view row);

}  // namespace mbrt
