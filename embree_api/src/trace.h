// Tracing one ray of the caller's memory: a single RTCRay(Hit), or lane
// `lane` of a packet of N rays in Embree's SOA layout (N = 1 for single
// rays and AOS streams). Packets and streams loop over their lanes through
// the same path (packets.cpp, streams.cpp).
//
// What is written is what Embree 3.13 writes: on a hit tfar, Ng (object
// space, unnormalised: (v1 - v0) x (v2 - v0)), u/v (for quads over the
// quad: u along v0 -> v1, v along v0 -> v3), primID, geomID and instID[0];
// nothing on a miss; tfar = -inf when an occlusion ray is blocked.
#pragma once

#include "api.h"
#include "scene.h"

namespace mbrt::embree_api {

// The committed state of `scene`, or fails (not committed: Embree's
// RTC_ERROR_INVALID_OPERATION "scene got not committed").
const Committed& committedOf(RTCScene scene);

void intersectLane(const Committed& c, RTCIntersectContext* context, RTCRayN* ray, RTCHitN* hit, unsigned N,
                   unsigned lane);
void occludedLane(const Committed& c, RTCIntersectContext* context, RTCRayN* ray, unsigned N, unsigned lane);

}  // namespace mbrt::embree_api
