// MBRT_EMBREE_DUMP=FILE: every scene commit writes the scene as mbrt traces
// it (its mbrt geometries with Embree's ids and primitive maps, instanced
// scenes included) to FILE, replacing the previous one, so that a
// program's rays can be judged afterwards by the float64 reference
// (embree_api/clients/tutorials.sh). Filter functions are not written.
// The format is read by embree_api/clients/scene_dump_read.h.
#pragma once

#include "snapshot.h"

namespace mbrt::embree_api {

// Writes `snapshot` when MBRT_EMBREE_DUMP is set; false when writing failed.
bool dumpIfAsked(const Snapshot& snapshot);

}  // namespace mbrt::embree_api
