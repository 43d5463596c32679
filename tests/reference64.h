// A float64 reference tracer that shares no code with the library's hot
// path. It reads only the public scene model (raw step buffers, indices,
// radii, instance keys, time ranges, masks, filters) and does its own time
// lookup, vertex and instance-key interpolation (its own slerp), its own
// ray/triangle test (Plücker edge functions in double) and ray/round-segment
// test (root finding on the exact signed distance of the hull of two
// spheres), with nested instances.
//
// It does not answer with one hit but with every candidate a correct float
// tracer may report: definite hits, and "ambiguous" ones, where the ray
// passes within kEdgeUlps float ulps of an edge or silhouette (ulps of the
// computation's scale |org| + t|dir| + |vertex|, carried through instance
// transforms), or where the hit lies within the t bound of tnear or tfar.
// judgeClosest / judgeAny then say whether a library answer is right: every
// difference outside those bands is a failure.
//
// The t bound: a float tracer is backward stable, its answer is exact for
// vertices and ray moved by a few ulps of the scale S. Moving a surface by
// e along its normal moves the hit by e / cos(theta) along the ray (theta:
// angle between ray and normal), so a hit's t may differ from the exact one
// by  kTUlps * 2^-24 * S / (|dir| * cos(theta)),  i.e. 64 ulps of the
// scale, about 4e-6 relative at normal incidence.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "mbrt/scene.h"

namespace mbrt::ref {

constexpr double kUlp = 1.0 / 16777216.0;  // 2^-24, float unit roundoff
constexpr double kEdgeUlps = 32;           // ambiguity band around edges and silhouettes
constexpr double kTUlps = 64;              // t bound (see above)

struct V3 {
  double x = 0, y = 0, z = 0;
};

// One primitive the ray may hit: where, how precisely, and whether a correct
// float tracer may also miss it (ambiguous).
struct Candidate {
  double t = 0;
  double tBound = 0;  // allowed |t_float - t|
  uint32_t geomID = kInvalidId, primID = kInvalidId, instID = kInvalidId;
  bool ambiguous = false;
};

struct Verdict {
  bool ok = true;
  bool ambiguous = false;  // the answer was settled by an ambiguous candidate
  std::string why;         // on failure: what the reference expected
};

class Reference {
 public:
  explicit Reference(const Scene& scene);
  ~Reference();

  // Every candidate for `ray` (empty for an invalid ray). With cull, only
  // primitives whose double box the ray's line meets are tested (exact for
  // definite hits; the judges retry without it before failing).
  void candidates(const Ray& ray, std::vector<Candidate>& out, bool cull = true) const;

  Verdict judgeClosest(const Ray& ray, const Hit& hit) const;
  Verdict judgeAny(const Ray& ray, bool occluded) const;
  // Both at once (one candidate search); a null answer is not judged.
  void judge(const Ray& ray, const Hit* hit, const bool* occluded, Verdict& closest, Verdict& any) const;

  struct Node;

 private:
  const Node* root_ = nullptr;
  std::unordered_map<const Scene*, std::unique_ptr<Node>> nodes_;
  const Node* nodeFor(const Scene& scene);
};

// Counts of a batch of judgements.
struct RefReport {
  size_t rays = 0, hits = 0, ambiguous = 0, wrong = 0, anyWrong = 0;
  std::string firstFailure;
};

// Judges `hits` / `occluded` (the library's answers for `rays`) in parallel.
RefReport judgeBatch(const Reference& ref, const std::vector<Ray>& rays, const std::vector<Hit>& hits,
                     const std::vector<uint8_t>& occluded);

std::string describe(const Ray& ray);

}  // namespace mbrt::ref
