// The tests' calls (embree_side.inl) on the real libembree3.
#include <embree3/rtcore.h>

#define MBRT_EMBREE_SIDE real_side
#define MBRT_EMBREE_SIDE_NAME "Embree"
#define MBRT_EMBREE_SIDE_GETTER realEmbree
#include "embree_side.inl"
