// `auto`'s hits named in the original scene, the object of a primitive, and
// its statistics (docs/auto.md, "Hits name the original scene").
#include <algorithm>
#include <map>

#include "auto/auto_structure.h"
#include "scene/primitive_intersect.h"

namespace mbrt::detail {
namespace {

// Hits on an extracted rigid part whose |cos| between the ray and the
// normal is below this are tested again in world space (remapHit).
constexpr float kRetestCosine = 0.1f;

// "rigid, kind frozen" from an object's line, for counts of many objects.
std::string kindOfLine(const std::string& line) {
  const std::string what = line.find(": rigid,") != std::string::npos            ? "rigid"
                           : line.find(": near-rigid cluster,") != std::string::npos ? "near-rigid"
                                                                                      : "other";
  const size_t k = line.find("; kind ");
  if (k == std::string::npos) return what;
  const size_t end = line.find(':', k + 7);
  return what + " " + line.substr(k + 7, end == std::string::npos ? std::string::npos : end - k - 7);
}

bool holds(const std::vector<uint32_t>& prims, uint32_t primID) {
  return prims.empty() || std::binary_search(prims.begin(), prims.end(), primID);
}

}  // namespace

// An extracted part's hit is tested again on the original triangle with the
// world-space ray when it grazes, so that t, u, v and Ng are the mesh's own
// (in the rest frame, the float transform of a grazing ray moves t by ~1e-7
// / cos θ). Steeper hits keep the instance's t, u, v (within ~1e-6 of the
// world test's), saving the fetch of the original mesh's vertices at two
// steps (docs/auto.md, "Hits name the original scene"). Where the world test
// misses (the ray passes within the fit's residual of an edge), the
// instance's hit stands, its normal as the mesh's: cof(M) n = det(M) M^-T n.
void AutoStructure::remapHit(RayQuery& ray, float tfar, Hit& hit) const {
  if (hit.instID >= objects_.size()) return;
  const AutoObject& o = *objects_[hit.instID];
  switch (o.type) {
    case ObjectType::Rigid: {
      const uint32_t primID = o.prims.empty() ? hit.primID : o.prims[hit.primID];
      const float dn = dot(hit.Ng, ray.dir);
      if (dn * dn < kRetestCosine * kRetestCosine * dot(hit.Ng, hit.Ng) * dot(ray.dir, ray.dir)) {
        RayQuery world = ray;
        world.tfar = tfar;
        Hit exact;
        if (leaf_detail::candidate(ctx_.geometry(o.geomID), {o.geomID, primID}, world, exact)) {
          hit = exact;
          ray.tfar = exact.t;
          break;
        }
      }
      // The instance's normal M^-T n, turned into the mesh's cof(M) n (a
      // translation's determinant is 1).
      if (o.fit.form != KeyForm::Translation)
        hit.Ng = hit.Ng * topScene_->geometry(hit.instID).transformAt(ray.time).determinant();
      hit.geomID = o.geomID;
      hit.primID = primID;
      hit.instID = kInvalidId;
      break;
    }
    case ObjectType::Cluster:  // world-space triangles: the hit is the mesh's own
      hit.geomID = o.geomID;
      hit.primID = o.prims[hit.primID];
      hit.instID = kInvalidId;
      break;
    case ObjectType::World: {
      const WorldSource& w = o.sources[hit.geomID];
      hit.geomID = w.geomID;
      if (!w.prims.empty()) hit.primID = w.prims[hit.primID];
      hit.instID = kInvalidId;
      break;
    }
    case ObjectType::UserInstance:
      hit.instID = o.geomID;
      break;
  }
}

// The object a primitive was placed in (without extraction, 0).
uint32_t AutoStructure::clusterOf(PrimRef p) const {
  if (!decomposed_) return 0;
  for (uint32_t i = 0; i < objects_.size(); ++i) {
    const AutoObject& o = *objects_[i];
    if (o.type == ObjectType::World) {
      for (const WorldSource& w : o.sources)
        if (w.geomID == p.geomID && holds(w.prims, p.primID)) return i;
    } else if (o.geomID == p.geomID && (o.type == ObjectType::UserInstance || holds(o.prims, p.primID))) {
      return i;
    }
  }
  return kInvalidId;
}

void AutoStructure::fillStats(AccelStats& s) const {
  if (decomposed_) {
    top_->fillStats(s);
    topContext_->addChildStats(s);
  } else {
    trace_->fillStats(s);
    whole_.context->addChildStats(s);
  }
  // Scenes of many objects: the first ones in full, the rest counted.
  constexpr size_t kListed = 16;
  if (decomposed_) {
    std::map<std::string, size_t> kinds;
    for (size_t i = 0; i < objects_.size(); ++i) {
      if (i < kListed) s.objects += objects_[i]->line + "\n";
      else ++kinds[kindOfLine(objects_[i]->line)];
    }
    std::string counts;
    for (const auto& [kind, n] : kinds) counts += (counts.empty() ? "" : ", ") + std::to_string(n) + " " + kind;
    if (objects_.size() > kListed)
      s.objects += "... and " + std::to_string(objects_.size() - kListed) + " more objects (" + counts + ")\n";
    s.objects += topLine_ + "\n";
  }
  if (!choiceLine_.empty()) s.objects += choiceLine_ + "\n";
}

}  // namespace mbrt::detail
