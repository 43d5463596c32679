/* Tests of the C API (mbrt/mbrt.h): batched and struct-of-arrays calls,
 * threads tracing one accel, statistics and the memory budget. Cases run by
 * test_capi.c's main. */
#include <pthread.h>
#include <stdlib.h>

#include "capi_test.h"

/* The batched calls give the answers of the single-ray ones. */
void testBatched(void) {
  enum { kRays = 50000 };
  static MBRTRay rays[kRays];
  static MBRTHit hits[kRays];
  static uint8_t occluded[kRays];
  MBRTDevice device = mbrtNewDevice();
  RandomScene rs = makeRandomScene(device);
  MBRTAccel accel = mbrtNewAccel(rs.top, "stbvh", NULL);
  size_t i, wrong = 0, hitCount = 0;
  randomRays(rays, kRays, -1.0f);
  memset(occluded, 7, sizeof(occluded));
  CHECK(mbrtIntersectM(accel, rays, hits, kRays) == 1);
  CHECK(mbrtOccludedM(accel, rays, occluded, kRays) == 1);
  for (i = 0; i < kRays; ++i) {
    MBRTHit one;
    int found = mbrtIntersect1(accel, &rays[i], &one);
    hitCount += (size_t)found;
    if (memcmp(&one, &hits[i], sizeof(one)) != 0 || occluded[i] != (uint8_t)found) ++wrong;
  }
  CHECK(wrong == 0);
  CHECK(hitCount > kRays / 10 && hitCount < kRays);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  mbrtReleaseAccel(accel);
  mbrtReleaseScene(rs.top);
  mbrtReleaseScene(rs.child);
  mbrtReleaseDevice(device);
}

/* Struct-of-arrays batches give the array-of-structs answers; missing
 * required arrays are errors. */
void testSoA(void) {
  enum { kRays = 20000 };
  static MBRTRay rays[kRays];
  static MBRTHit hits[kRays];
  static uint8_t occluded[kRays], occludedSoA[kRays];
  static float c[9][kRays], ht[kRays], hu[kRays], hv[kRays], ng[3][kRays];
  static uint32_t masks[kRays], geom[kRays], prim[kRays], inst[kRays];
  MBRTDevice device = mbrtNewDevice();
  RandomScene rs = makeRandomScene(device);
  MBRTAccel accel = mbrtNewAccel(rs.top, "stbvh", NULL);
  MBRTRaySoA soa;
  MBRTHitSoA out = {ht, hu, hv, ng[0], ng[1], ng[2], geom, prim, inst};
  MBRTHitSoA partial = {ht, NULL, NULL, NULL, NULL, NULL, geom, prim, NULL};
  size_t i, wrong = 0;
  randomRays(rays, kRays, -1.0f);
  for (i = 0; i < kRays; ++i) {
    int k;
    for (k = 0; k < 3; ++k) c[k][i] = rays[i].org[k], c[3 + k][i] = rays[i].dir[k];
    c[6][i] = rays[i].tnear, c[7][i] = rays[i].tfar, c[8][i] = rays[i].time;
    masks[i] = rays[i].mask;
  }
  soa.orgX = c[0], soa.orgY = c[1], soa.orgZ = c[2], soa.dirX = c[3], soa.dirY = c[4], soa.dirZ = c[5];
  soa.tnear = c[6], soa.tfar = c[7], soa.time = c[8], soa.mask = masks;
  CHECK(mbrtIntersectM(accel, rays, hits, kRays) == 1);
  CHECK(mbrtOccludedM(accel, rays, occluded, kRays) == 1);
  CHECK(mbrtIntersectSoA(accel, &soa, &out, kRays) == 1);
  CHECK(mbrtOccludedSoA(accel, &soa, occludedSoA, kRays) == 1);
  for (i = 0; i < kRays; ++i) {
    const MBRTHit* h = &hits[i];
    if (memcmp(&h->t, &ht[i], 4) || memcmp(&h->u, &hu[i], 4) || memcmp(&h->v, &hv[i], 4) ||
        memcmp(&h->ng[0], &ng[0][i], 4) || memcmp(&h->ng[1], &ng[1][i], 4) || memcmp(&h->ng[2], &ng[2][i], 4) ||
        h->geomID != geom[i] || h->primID != prim[i] || h->instID != inst[i] || occluded[i] != occludedSoA[i])
      ++wrong;
  }
  CHECK(wrong == 0);
  /* Optional fields: NULL ray fields are the defaults, NULL hit fields are skipped. */
  soa.tnear = NULL, soa.tfar = NULL, soa.mask = NULL;
  CHECK(mbrtIntersectSoA(accel, &soa, &partial, kRays) == 1);
  for (i = 0, wrong = 0; i < kRays; ++i)
    if (rays[i].tnear == 0.0f && rays[i].mask == 0xFFFFFFFFu && isinf(rays[i].tfar) &&
        (geom[i] != hits[i].geomID || prim[i] != hits[i].primID))
      ++wrong;
  CHECK(wrong == 0);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  soa.dirY = NULL;
  CHECK(mbrtIntersectSoA(accel, &soa, &out, kRays) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "must not be NULL");
  CHECK(mbrtOccludedSoA(accel, NULL, occludedSoA, kRays) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "rays is NULL");
  soa.dirY = c[4];
  partial.primID = NULL;
  CHECK(mbrtIntersectSoA(accel, &soa, &partial, kRays) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "primID must not be NULL");
  CHECK(mbrtIntersectSoA(NULL, &soa, &out, kRays) == 0);
  mbrtReleaseAccel(accel);
  mbrtReleaseScene(rs.top);
  mbrtReleaseScene(rs.child);
  mbrtReleaseDevice(device);
}

/* Many threads trace the same accel at once and get the single-threaded
 * answers. */
enum { kThreadRays = 20000, kThreads = 8 };
static MBRTRay gThreadRays[kThreadRays];
static MBRTHit gThreadRef[kThreadRays];
typedef struct ThreadJob {
  MBRTAccel accel;
  int index;
  size_t wrong;
} ThreadJob;

static void* traceThread(void* arg) {
  ThreadJob* job = (ThreadJob*)arg;
  size_t i, n;
  for (n = 0; n < kThreadRays; ++n) {
    /* Each thread starts elsewhere so that threads trace different rays at
     * the same moment. */
    MBRTHit hit;
    i = (n + (size_t)job->index * (kThreadRays / kThreads)) % kThreadRays;
    mbrtIntersect1(job->accel, &gThreadRays[i], &hit);
    if (memcmp(&hit, &gThreadRef[i], sizeof(hit)) != 0) ++job->wrong;
    if (mbrtOccluded1(job->accel, &gThreadRays[i]) != (gThreadRef[i].geomID != MBRT_INVALID_ID)) ++job->wrong;
  }
  return NULL;
}

void testThreads(void) {
  MBRTDevice device = mbrtNewDevice();
  RandomScene rs = makeRandomScene(device);
  MBRTAccel accel = mbrtNewAccel(rs.top, "stbvh", NULL);
  pthread_t threads[kThreads];
  ThreadJob jobs[kThreads];
  size_t i;
  int t;
  CHECK(accel != NULL);
  randomRays(gThreadRays, kThreadRays, -1.0f);
  for (i = 0; i < kThreadRays; ++i) mbrtIntersect1(accel, &gThreadRays[i], &gThreadRef[i]);
  for (t = 0; t < kThreads; ++t) {
    jobs[t].accel = accel, jobs[t].index = t, jobs[t].wrong = 0;
    CHECK(pthread_create(&threads[t], NULL, traceThread, &jobs[t]) == 0);
  }
  for (t = 0; t < kThreads; ++t) {
    pthread_join(threads[t], NULL);
    CHECK(jobs[t].wrong == 0);
  }
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  mbrtReleaseAccel(accel);
  mbrtReleaseScene(rs.top);
  mbrtReleaseScene(rs.child);
  mbrtReleaseDevice(device);
}

void testStats(void) {
  MBRTDevice device = mbrtNewDevice();
  RandomScene rs = makeRandomScene(device);
  MBRTAccel accel = mbrtNewAccel(rs.top, "stbvh", NULL);
  MBRTAccelStats stats;
  CHECK(mbrtGetAccelStats(accel, &stats) == 1);
  CHECK(!strcmp(stats.kind, "stbvh"));
  /* Top level: the soup, the segments and two instances; the child scene's
   * triangles once per instanced scene level. */
  CHECK(stats.primitives >= kSoupTriangles + kSegments + 2);
  CHECK(stats.references >= kSoupTriangles + kSegments + 2);
  CHECK(stats.leafNodes > 0 && stats.bytes > 0 && stats.sahCost > 0.0);
  CHECK(stats.invalidRays == 0);
  mbrtReleaseAccel(accel);
  mbrtReleaseScene(rs.top);
  mbrtReleaseScene(rs.child);
  mbrtReleaseDevice(device);
}

void testMemoryBudget(void) {
  MBRTDevice device = mbrtNewDevice();
  RandomScene rs = makeRandomScene(device);
  MBRTBuildOptions options;
  MBRTAccel accel;
  mbrtDefaultBuildOptions(&options);
  CHECK(options.branching == 8 && options.memoryBudget == 0);
  options.memoryBudget = 1024;
  CHECK(mbrtNewAccel(rs.top, "stbvh", &options) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_OUT_OF_MEMORY, "memory budget");
  options.memoryBudget = 0;
  accel = mbrtNewAccel(rs.top, "stbvh", &options);
  CHECK(accel != NULL);
  mbrtReleaseAccel(accel);
  mbrtReleaseScene(rs.top);
  mbrtReleaseScene(rs.child);
  mbrtReleaseDevice(device);
}
