/* LD_PRELOAD interposer for Open3D 0.16's RaycastingScene.
 *
 * Open3D 0.16 fills every ray with mask = 0, because upstream Open3D bundles
 * an Embree built without ray masks. Debian's libembree3 is built with ray
 * masks (RTC_DEVICE_PROPERTY_RAY_MASK_SUPPORTED = 1), so unchanged Open3D
 * misses every geometry (default geometry mask 0xFFFFFFFF, and
 * 0 & 0xFFFFFFFF == 0). This library sets every ray's mask to 0xFFFFFFFF
 * and forwards the call to the libembree3 that Open3D loaded: the real one
 * or the mbrt shim, whichever LD_LIBRARY_PATH selects. Open3D's binaries
 * stay unchanged; only the rays it passes are patched. The forwarded symbol
 * is looked up on the first call, because libembree3 is loaded (by Python
 * importing open3d) after this library's constructors ran.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>

#include <embree3/rtcore.h>

typedef void (*Intersect1MFn)(RTCScene, struct RTCIntersectContext*,
                              struct RTCRayHit*, unsigned int, size_t);
typedef void (*Occluded1MFn)(RTCScene, struct RTCIntersectContext*,
                             struct RTCRay*, unsigned int, size_t);

/* The libembree3 that Open3D loaded: Python opens extension modules with
 * RTLD_LOCAL, so RTLD_NEXT does not see it; RTLD_NOLOAD returns the copy
 * already loaded (from LD_LIBRARY_PATH's directory when that is set). */
static void* next_symbol(const char* name) {
  void* fn = dlsym(RTLD_NEXT, name);
  if (fn == NULL) {
    void* embree = dlopen("libembree3.so.3", RTLD_NOW | RTLD_NOLOAD);
    if (embree != NULL) fn = dlsym(embree, name);
  }
  if (fn == NULL) {
    fprintf(stderr, "mask_all: %s not found in the loaded libembree3\n", name);
    abort();
  }
  return fn;
}

/* next_symbol(name), looked up once and kept in *slot (thread-safe). */
static void* cached_next(void** slot, const char* name) {
  void* fn = __atomic_load_n(slot, __ATOMIC_ACQUIRE);
  if (fn == NULL) {
    fn = next_symbol(name);
    __atomic_store_n(slot, fn, __ATOMIC_RELEASE);
  }
  return fn;
}

void rtcIntersect1M(RTCScene scene, struct RTCIntersectContext* context,
                    struct RTCRayHit* rayhits, unsigned int count,
                    size_t byte_stride) {
  static void* next = NULL;
  for (unsigned int i = 0; i < count; ++i) {
    struct RTCRayHit* rh =
        (struct RTCRayHit*)((char*)rayhits + (size_t)i * byte_stride);
    rh->ray.mask = 0xFFFFFFFFu;
  }
  ((Intersect1MFn)cached_next(&next, "rtcIntersect1M"))(scene, context, rayhits,
                                                        count, byte_stride);
}

void rtcOccluded1M(RTCScene scene, struct RTCIntersectContext* context,
                   struct RTCRay* rays, unsigned int count,
                   size_t byte_stride) {
  static void* next = NULL;
  for (unsigned int i = 0; i < count; ++i) {
    struct RTCRay* r = (struct RTCRay*)((char*)rays + (size_t)i * byte_stride);
    r->mask = 0xFFFFFFFFu;
  }
  ((Occluded1MFn)cached_next(&next, "rtcOccluded1M"))(scene, context, rays,
                                                      count, byte_stride);
}
