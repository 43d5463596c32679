// The tests' calls (embree_side.inl) on mbrt's Embree API, renamed
// (src/renames.h) so that it links beside the real libembree3.
#include "api.h"

#define MBRT_EMBREE_SIDE mbrt_side
#define MBRT_EMBREE_SIDE_NAME "mbrt"
#define MBRT_EMBREE_SIDE_GETTER mbrtEmbree
#include "embree_side.inl"
