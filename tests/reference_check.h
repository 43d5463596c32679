// Traces rays with a structure and judges every answer (closest hit and any
// hit) with the float64 reference.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "mbrt/accel.h"
#include "oracle.h"
#include "reference64.h"

namespace mbrt::test {

inline ref::RefReport judgeWithReference(const ref::Reference& reference, const Accel& accel,
                                         const std::vector<Ray>& rays) {
  std::vector<Hit> hits(rays.size());
  std::vector<uint8_t> occluded(rays.size());
  accel.intersect(rays, hits);
  accel.occluded(rays, occluded);
  return ref::judgeBatch(reference, rays, hits, occluded);
}

// Rays just before and just after every partial time-range end of the
// scene's top level (one float step away, and 1e-4 away), `perTime` each.
inline std::vector<Ray> rangeEndRays(const ProceduralScene& ps, size_t perTime, uint64_t seed) {
  std::vector<float> times;
  for (uint32_t id = 0; id < ps.scene->numGeometries(); ++id) {
    const TimeRange r = ps.scene->geometry(id).timeRange();
    for (float e : {r.lo, r.hi}) {
      if (e <= 0.0f || e >= 1.0f) continue;
      for (float t : {std::nextafter(e, 0.0f), e, std::nextafter(e, 1.0f), e - 1e-4f, e + 1e-4f}) times.push_back(t);
    }
  }
  std::vector<Ray> rays;
  for (size_t i = 0; i < times.size(); ++i)
    for (const Ray& r : oracleRays(ps, perTime, 0, seed + i, times[i])) rays.push_back(r);
  return rays;
}

// Where a peer (Embree) and brute differ, the reference decides. Counts
// the differing rays, those where the peer is wrong (listed, up to
// `maxListed`) and those where brute is wrong.
struct Settlement {
  size_t differing = 0, peerWrong = 0, bruteWrong = 0;
  std::vector<std::string> listed;
};

inline void settle(const ref::Reference& reference, const std::vector<Ray>& rays, const OracleAnswers& brute,
                   const std::vector<Hit>& peerHits, const std::vector<uint8_t>& peerOccluded, float tolerance,
                   Settlement& out, const std::string& label, size_t maxListed = 20) {
  for (size_t i = 0; i < rays.size(); ++i) {
    OracleReport one;
    recordAgreement(one, rays[i], brute.hits[i], peerHits[i], brute.occluded[i] != 0, peerOccluded[i] != 0,
                    tolerance);
    if (one.wrong + one.anyWrong == 0) continue;
    ++out.differing;
    ref::Verdict pc, pa, bc, ba;
    const bool po = peerOccluded[i] != 0, bo = brute.occluded[i] != 0;
    reference.judge(rays[i], &peerHits[i], &po, pc, pa);
    reference.judge(rays[i], &brute.hits[i], &bo, bc, ba);
    if (!pc.ok || !pa.ok) {
      ++out.peerWrong;
      if (out.listed.size() < maxListed) out.listed.push_back(label + ": " + (!pc.ok ? pc.why : pa.why));
    }
    if (!bc.ok || !ba.ok) ++out.bruteWrong;
  }
}

inline Settlement settleWithReference(const ref::Reference& reference, const Accel& brute, const Accel& peer,
                                      const std::vector<Ray>& rays, float tolerance, const std::string& label) {
  const OracleAnswers b = oracleAnswers(brute, rays);
  std::vector<Hit> hits(rays.size());
  std::vector<uint8_t> occ(rays.size());
  peer.intersect(rays, hits);
  peer.occluded(rays, occ);
  Settlement s;
  settle(reference, rays, b, hits, occ, tolerance, s, label);
  return s;
}

}  // namespace mbrt::test
