/* Tests of the C API (mbrt/mbrt.h), in C99 without a test framework.
 *
 *   mbrt_c_tests CASE     runs one case (CTest capi.CASE); exit 0 when it passes
 *
 * Each failed check prints file:line and what was expected; a case fails
 * when any check failed. Here: the scenes and tracing cases and the case
 * table; wrong calls in test_capi_errors.c, batches, threads and statistics
 * in test_capi_batches.c, auto and animations in test_capi_auto.c, the
 * shared checks and helpers in capi_test.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "capi_test.h"

/* ---- cases ---------------------------------------------------------------- */
static void testVersion(void) {
  int major = -1, minor = -1, patch = -1;
  CHECK(mbrtGetVersion(&major, &minor, &patch) == MBRT_VERSION);
  CHECK(major == MBRT_VERSION_MAJOR && minor == MBRT_VERSION_MINOR && patch == MBRT_VERSION_PATCH);
  CHECK(MBRT_VERSION == MBRT_VERSION_MAJOR * 10000 + MBRT_VERSION_MINOR * 100 + MBRT_VERSION_PATCH);
  CHECK(mbrtGetVersion(NULL, NULL, NULL) == MBRT_VERSION);
}

static void testFrozenScene(void) {
  MBRTDevice device = mbrtNewDevice();
  MBRTScene top = mbrtNewScene(device), child = mbrtNewScene(device);
  const float identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  MBRTAccel accel;
  MBRTRay ray = makeRay(2, 0, -5, 0, 0, 1, 1);
  MBRTHit hit;
  CHECK(addMovingTriangle(child, 0, 1) == 0);
  CHECK(mbrtNewInstance(top, child, identity, 1, 0, 1) == 0);
  CHECK(mbrtNewInstance(child, top, identity, 1, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "cycle");
  accel = mbrtNewAccel(top, "stbvh", NULL);
  CHECK(accel != NULL);
  CHECK(mbrtIntersect1(accel, &ray, &hit) == 1 && hit.instID == 0 && hit.geomID == 0);
  CHECK(addMovingTriangle(top, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "live accel");
  CHECK(addMovingTriangle(child, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "live accel");
  mbrtSetGeometryMask(child, 0, 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "live accel");
  /* The child's handle may go while the instance keeps the scene. */
  mbrtReleaseScene(child);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  CHECK(mbrtIntersect1(accel, &ray, &hit) == 1 && hit.instID == 0);
  mbrtReleaseAccel(accel);
  CHECK(addMovingTriangle(top, 0, 1) == 1);
  mbrtReleaseScene(top);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  mbrtReleaseDevice(device);
  CHECK_ERROR(NULL, MBRT_ERROR_NONE, "");
}

/* Per-geometry time ranges and masks. */
static void testTimeRangeAndMask(void) {
  MBRTDevice device = mbrtNewDevice();
  MBRTScene scene = mbrtNewScene(device);
  MBRTAccel accel;
  MBRTRay ray = makeRay(2, 0, -5, 0, 0, 1, 0.9f);
  MBRTHit hit;
  /* Moves from x=0 at time 0.5 to x=2 at time 1; absent before 0.5. */
  CHECK(addMovingTriangle(scene, 0.5f, 1.0f) == 0);
  mbrtSetGeometryMask(scene, 0, 0x4u);
  accel = mbrtNewAccel(scene, "stbvh", NULL);
  CHECK(accel != NULL);
  ray.time = 1.0f;
  CHECK(mbrtIntersect1(accel, &ray, &hit) == 1);
  ray.time = 0.75f; /* centred at x = 1 then: x = 2 is outside at y = 0 */
  CHECK(mbrtIntersect1(accel, &ray, &hit) == 0);
  ray.org[0] = 1.0f;
  CHECK(mbrtIntersect1(accel, &ray, &hit) == 1);
  ray.time = 0.25f, ray.org[0] = 0.0f; /* where a full-range triangle would be at 0.25... */
  CHECK(mbrtIntersect1(accel, &ray, &hit) == 0);
  ray.time = 0.5f;
  CHECK(mbrtIntersect1(accel, &ray, &hit) == 1);
  ray.mask = 0x3u;
  CHECK(mbrtIntersect1(accel, &ray, &hit) == 0);
  CHECK(mbrtOccluded1(accel, &ray) == 0);
  ray.mask = 0x4u;
  CHECK(mbrtOccluded1(accel, &ray) == 1);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  mbrtReleaseAccel(accel);
  mbrtReleaseScene(scene);
  mbrtReleaseDevice(device);
}

/* SRT keys: translation-only keys trace like the same matrix keys, and a
 * rotating key turns the instance. */
static void testSrtInstances(void) {
  MBRTDevice device = mbrtNewDevice();
  MBRTScene child = mbrtNewScene(device), bySrt = mbrtNewScene(device), byMatrix = mbrtNewScene(device);
  MBRTScene rotating = mbrtNewScene(device);
  MBRTVertexBuffer step = {kTri0, 12, 3};
  const float matrices[24] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, /* */ 1, 0, 0, 2, 0, 1, 0, 0, 0, 0, 1, 0};
  MBRTSRTKey keys[2] = {{{1, 1, 1}, {1, 0, 0, 0}, {0, 0, 0}}, {{1, 1, 1}, {1, 0, 0, 0}, {2, 0, 0}}};
  /* 90 degrees about z at time 1: (x, y) -> (-y, x). */
  MBRTSRTKey turn[2] = {{{1, 1, 1}, {1, 0, 0, 0}, {0, 0, 0}}, {{1, 1, 1}, {0.70710678f, 0, 0, 0.70710678f}, {0, 0, 0}}};
  MBRTSRTKey zeroRotation = {{1, 1, 1}, {0, 0, 0, 0}, {0, 0, 0}};
  MBRTAccel a, b, r;
  MBRTRay ray = makeRay(0.9f, 0, -5, 0, 0, 1, 1.0f);
  MBRTHit ha, hb;
  size_t i, wrong = 0, hits = 0;
  CHECK(mbrtNewTriangleMesh(child, kTriIndices, 1, &step, 1, 0, 1) == 0);
  CHECK(mbrtNewInstanceSRT(bySrt, child, keys, 2, 0, 1) == 0);
  CHECK(mbrtNewInstance(byMatrix, child, matrices, 2, 0, 1) == 0);
  CHECK(mbrtNewInstanceSRT(rotating, child, turn, 2, 0, 1) == 0);
  a = mbrtNewAccel(bySrt, "stbvh", NULL);
  b = mbrtNewAccel(byMatrix, "stbvh", NULL);
  r = mbrtNewAccel(rotating, "bvh-interp", NULL);
  CHECK(a && b && r);
  for (i = 0; i < 10000; ++i) {
    MBRTRay q = makeRay(between(-2, 4), between(-2, 2), -3, between(-0.2f, 0.2f), between(-0.2f, 0.2f), 1, uniform());
    int fa = mbrtIntersect1(a, &q, &ha), fb = mbrtIntersect1(b, &q, &hb);
    hits += (size_t)fa;
    if (fa != fb || (fa && (fabsf(ha.t - hb.t) > 1e-5f || ha.instID != hb.instID))) ++wrong;
  }
  CHECK(wrong == 0);
  printf("srt and matrix keys agree on 10000 rays, %zu hits\n", hits);
  CHECK(hits > 400); /* about 8% of the rays meet the triangle */
  /* (0.9, 0) is inside the turned triangle only. */
  CHECK(mbrtIntersect1(r, &ray, &ha) == 1 && ha.instID == 0 && fabsf(ha.t - 5.0f) < 1e-5f);
  ray.time = 0.0f;
  CHECK(mbrtIntersect1(r, &ray, &ha) == 0);
  mbrtReleaseAccel(a);
  mbrtReleaseAccel(b);
  mbrtReleaseAccel(r);
  /* A zero quaternion is refused at the build. */
  mbrtReleaseScene(rotating);
  rotating = mbrtNewScene(device);
  CHECK(mbrtNewInstanceSRT(rotating, child, &zeroRotation, 1, 0, 1) == 0);
  CHECK(mbrtNewAccel(rotating, "stbvh", NULL) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "mbrtNewAccel");
  CHECK(mbrtNewInstanceSRT(rotating, child, NULL, 1, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "keys is NULL");
  mbrtReleaseScene(rotating);
  mbrtReleaseScene(bySrt);
  mbrtReleaseScene(byMatrix);
  mbrtReleaseScene(child);
  mbrtReleaseDevice(device);
}

typedef struct FilterState {
  int calls;
  uint32_t reject; /* primID rejected; MBRT_INVALID_ID: reject every hit */
} FilterState;

static int rejectPrim(void* user, const MBRTRay* ray, const MBRTHit* candidate) {
  FilterState* state = (FilterState*)user;
  ++state->calls;
  (void)ray;
  return state->reject != MBRT_INVALID_ID && candidate->primID != state->reject;
}

/* Filters reject candidates: the ray goes on to the next surface. */
static void testFilters(void) {
  MBRTDevice device = mbrtNewDevice();
  MBRTScene scene = mbrtNewScene(device), top = mbrtNewScene(device);
  /* Two triangles over the origin, at z = 0 (prim 0) and z = 1 (prim 1). */
  const float verts[] = {-1, -1, 0, 1, -1, 0, 0, 1, 0, -1, -1, 1, 1, -1, 1, 0, 1, 1};
  const uint32_t indices[] = {0, 1, 2, 3, 4, 5};
  const float identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  MBRTVertexBuffer step = {verts, 12, 6};
  MBRTRay ray = makeRay(0, 0, -5, 0, 0, 1, 0);
  MBRTHit hit;
  FilterState state = {0, 0};
  const char* kinds[] = {"brute", "stbvh", "bvh-interp"};
  size_t k;
  CHECK(mbrtNewTriangleMesh(scene, indices, 2, &step, 1, 0, 1) == 0);
  mbrtSetGeometryFilter(scene, 0, rejectPrim, &state);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  for (k = 0; k < sizeof(kinds) / sizeof(kinds[0]); ++k) {
    MBRTAccel accel = mbrtNewAccel(scene, kinds[k], NULL);
    CHECK(accel != NULL);
    state.calls = 0, state.reject = 0;
    CHECK(mbrtIntersect1(accel, &ray, &hit) == 1 && hit.primID == 1 && fabsf(hit.t - 6.0f) < 1e-5f);
    CHECK(state.calls >= 2);
    CHECK(mbrtOccluded1(accel, &ray) == 1);
    state.reject = MBRT_INVALID_ID;
    CHECK(mbrtIntersect1(accel, &ray, &hit) == 0);
    CHECK(mbrtOccluded1(accel, &ray) == 0);
    /* A frozen scene's filter does not change. */
    mbrtSetGeometryFilter(scene, 0, NULL, NULL);
    CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "live accel");
    mbrtReleaseAccel(accel);
  }
  mbrtSetGeometryFilter(scene, 0, NULL, NULL);
  {
    MBRTAccel accel = mbrtNewAccel(scene, "stbvh", NULL);
    state.calls = 0;
    CHECK(mbrtIntersect1(accel, &ray, &hit) == 1 && hit.primID == 0 && fabsf(hit.t - 5.0f) < 1e-5f);
    CHECK(state.calls == 0);
    mbrtReleaseAccel(accel);
  }
  CHECK(mbrtNewInstance(top, scene, identity, 1, 0, 1) == 0);
  mbrtSetGeometryFilter(top, 0, rejectPrim, &state);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "instance");
  mbrtSetGeometryFilter(scene, 3, rejectPrim, &state);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "out of range");
  mbrtReleaseScene(top);
  mbrtReleaseScene(scene);
  mbrtReleaseDevice(device);
}

/* Every kind agrees with brute on random rays through the random scene. */
static void testAgreement(void) {
  enum { kRays = 20000 };
  static MBRTRay rays[kRays];
  static MBRTHit ref[kRays];
  MBRTDevice device = mbrtNewDevice();
  RandomScene rs = makeRandomScene(device);
  MBRTAccel brute = mbrtNewAccel(rs.top, "brute", NULL);
  uint32_t k, n = mbrtGetKindCount();
  size_t segmentHits = 0, instanceHits = 0; /* over all kinds' rays */
  CHECK(brute != NULL);
  for (k = 0; k < n && brute; ++k) {
    const char* kind = mbrtGetKindName(k);
    int isFrozen = !strcmp(kind, "frozen"), isEmbree = !strcmp(kind, "embree");
    MBRTBuildOptions options;
    MBRTAccel accel;
    size_t i, wrong = 0, hits = 0;
    if (!strcmp(kind, "brute")) continue;
    mbrtDefaultBuildOptions(&options);
    options.frozenTime = 0.5f;
    /* frozen is right at its build time only. */
    randomRays(rays, kRays, isFrozen ? options.frozenTime : -1.0f);
    for (i = 0; i < kRays; ++i) {
      mbrtIntersect1(brute, &rays[i], &ref[i]);
      segmentHits += ref[i].geomID == 1 && ref[i].instID == MBRT_INVALID_ID;
      instanceHits += ref[i].instID != MBRT_INVALID_ID;
    }
    accel = mbrtNewAccel(rs.top, kind, &options);
    if (!accel) {
      const char* message;
      mbrtGetError(device, &message);
      fprintf(stderr, "build of %s failed: %s\n", kind, message);
      ++gFailures;
      continue;
    }
    for (i = 0; i < kRays; ++i) {
      MBRTHit hit;
      int found = mbrtIntersect1(accel, &rays[i], &hit);
      hits += (size_t)found;
      if (found != (ref[i].geomID != MBRT_INVALID_ID) || !sameHit(&ref[i], &hit, isEmbree ? 2e-4f : 1e-5f) ||
          mbrtOccluded1(accel, &rays[i]) != found) {
        if (wrong < 3)
          fprintf(stderr, "%s ray %zu: t %g ids %u/%u/%u, brute t %g ids %u/%u/%u\n", kind, i, hit.t,
                  (unsigned)hit.geomID, (unsigned)hit.primID, (unsigned)hit.instID, ref[i].t,
                  (unsigned)ref[i].geomID, (unsigned)ref[i].primID, (unsigned)ref[i].instID);
        ++wrong;
      }
    }
    printf("%-12s %zu rays, %zu hits, %zu differ from brute\n", kind, (size_t)kRays, hits, wrong);
    /* The scene is hit often enough for the comparison to mean something. */
    CHECK(hits > kRays / 10);
    /* Embree has its own triangle and curve arithmetic: a few edge-on rays
     * may differ. Every other kind shares mbrt's primitive tests. */
    if (isEmbree)
      CHECK(wrong * 1000 <= kRays);
    else
      CHECK(wrong == 0);
    mbrtReleaseAccel(accel);
  }
  /* The rays reach every kind of geometry: segments and instances too. */
  printf("brute: %zu segment hits, %zu instance hits\n", segmentHits, instanceHits);
  CHECK(segmentHits > 100 && instanceHits > 100);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  mbrtReleaseAccel(brute);
  mbrtReleaseScene(rs.top);
  mbrtReleaseScene(rs.child);
  mbrtReleaseDevice(device);
}

typedef struct Case {
  const char* name;
  void (*run)(void);
} Case;

static const Case kCases[] = {
    {"version", testVersion},         {"null_handles", testNullHandles},
    {"wrong_handles", testWrongHandles}, {"bad_arguments", testBadArguments},
    {"bad_kind", testBadKind},        {"error_callback", testErrorCallback},
    {"release_in_use", testReleaseInUse}, {"frozen_scene", testFrozenScene},
    {"time_range_and_mask", testTimeRangeAndMask}, {"srt_instances", testSrtInstances},
    {"filters", testFilters},         {"agreement", testAgreement},
    {"batched", testBatched},         {"soa", testSoA},
    {"threads", testThreads},
    {"stats", testStats},             {"memory_budget", testMemoryBudget},
    {"auto_options", testAutoOptions},
    {"animation", testAnimation},     {"animation_layouts", testAnimationLayouts},
    {"animation_errors", testAnimationErrors},
};

int main(int argc, char** argv) {
  size_t i;
  if (argc != 2) {
    fprintf(stderr, "usage: %s CASE\ncases:", argv[0]);
    for (i = 0; i < sizeof(kCases) / sizeof(kCases[0]); ++i) fprintf(stderr, " %s", kCases[i].name);
    fprintf(stderr, "\n");
    return 2;
  }
  for (i = 0; i < sizeof(kCases) / sizeof(kCases[0]); ++i) {
    if (!strcmp(argv[1], kCases[i].name)) {
      kCases[i].run();
      if (gFailures) fprintf(stderr, "%s: %d check(s) failed\n", argv[1], gFailures);
      return gFailures ? 1 : 0;
    }
  }
  fprintf(stderr, "unknown case %s\n", argv[1]);
  return 2;
}
