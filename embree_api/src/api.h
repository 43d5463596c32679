// Embree 3.13's API as this library implements it: Debian's own headers
// (/usr/include/embree3/: the real structs and signatures, so the ABI is
// Embree's), with every rtc* function exported (RTC_EXPORT_API) or, in the
// build the comparison tests link beside the real libembree3, renamed.
#pragma once

#ifdef MBRT_EMBREE_RENAME
#include "renames.h"
#endif
#define RTC_EXPORT_API
#include <embree3/rtcore.h>
