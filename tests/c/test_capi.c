/* Tests of the C API (mbrt/mbrt.h), in C99 without a test framework.
 *
 *   mbrt_c_tests CASE     runs one case (CTest capi.CASE); exit 0 when it passes
 *
 * Each failed check prints file:line and what was expected; a case fails
 * when any check failed. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mbrt/mbrt.h"

static int gFailures = 0;

#define CHECK(cond)                                                     \
  do {                                                                  \
    if (!(cond)) {                                                      \
      fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
      ++gFailures;                                                      \
    }                                                                   \
  } while (0)

/* Reads and clears the error of `device` (NULL: the thread's no-device
 * slot); checks its code, and that its message contains `part`. */
#define CHECK_ERROR(device, expected, part) checkError((device), (expected), (part), __FILE__, __LINE__)
static void checkError(MBRTDevice device, MBRTError expected, const char* part, const char* file, int line) {
  const char* message = NULL;
  MBRTError code = mbrtGetError(device, &message);
  if (code != expected || message == NULL || (part && !strstr(message, part))) {
    fprintf(stderr, "%s:%d: expected error %d containing \"%s\", got %d: \"%s\"\n", file, line, (int)expected,
            part ? part : "", (int)code, message ? message : "(null)");
    ++gFailures;
  }
}

/* ---- deterministic random numbers (xorshift) ------------------------------ */
static uint64_t gRng = 88172645463325252ull;
static float uniform(void) {
  gRng ^= gRng << 13;
  gRng ^= gRng >> 7;
  gRng ^= gRng << 17;
  return (float)((gRng >> 40) * (1.0 / 16777216.0));
}
static float between(float lo, float hi) { return lo + (hi - lo) * uniform(); }

/* ---- scenes --------------------------------------------------------------- */
static const float kTri0[] = {-1, -1, 0, 1, -1, 0, 0, 1, 0};
static const float kTri1[] = {1, -1, 0, 3, -1, 0, 2, 1, 0};
static const uint32_t kTriIndices[] = {0, 1, 2};

/* One triangle moving by +2 in x over [time0, time1]. */
static uint32_t addMovingTriangle(MBRTScene scene, float time0, float time1) {
  MBRTVertexBuffer steps[2] = {{kTri0, 12, 3}, {kTri1, 12, 3}};
  return mbrtNewTriangleMesh(scene, kTriIndices, 1, steps, 2, time0, time1);
}

static MBRTRay makeRay(float ox, float oy, float oz, float dx, float dy, float dz, float time) {
  MBRTRay r;
  r.org[0] = ox, r.org[1] = oy, r.org[2] = oz;
  r.dir[0] = dx, r.dir[1] = dy, r.dir[2] = dz;
  r.tnear = 0.0f;
  r.tfar = INFINITY;
  r.time = time;
  r.mask = 0xFFFFFFFFu;
  return r;
}

/* A random moving scene: a triangle soup with 3 steps (strided vertices),
 * round segments with 2 steps, and two instances (moving matrix keys) of a
 * child scene with a static mesh. Geometries 0..3 of the top scene. */
enum { kSoupTriangles = 300, kSegments = 60, kChildTriangles = 80 };
typedef struct RandomScene {
  MBRTScene top, child;
} RandomScene;

static RandomScene makeRandomScene(MBRTDevice device) {
  RandomScene rs;
  enum { kStride = 5 }; /* floats per vertex: xyz and two padding floats */
  static float soup[3][3 * kSoupTriangles * kStride];
  static uint32_t soupIndices[3 * kSoupTriangles];
  static float segVerts[2][2 * kSegments * 3];
  static uint32_t segIndices[2 * kSegments];
  static float radii[2 * kSegments];
  static float childVerts[3 * kChildTriangles * 3];
  static uint32_t childIndices[3 * kChildTriangles];
  MBRTVertexBuffer steps[3];
  int i, k;
  for (i = 0; i < kSoupTriangles; ++i) {
    float c[3] = {between(-4, 4), between(-4, 4), between(-4, 4)};
    float m[3] = {between(-0.5f, 0.5f), between(-0.5f, 0.5f), between(-0.5f, 0.5f)};
    int v;
    for (v = 0; v < 3; ++v) {
      float p[3] = {c[0] + between(-0.6f, 0.6f), c[1] + between(-0.6f, 0.6f), c[2] + between(-0.6f, 0.6f)};
      for (k = 0; k < 3; ++k) {
        float* dst = &soup[k][(3 * i + v) * kStride];
        dst[0] = p[0] + m[0] * (float)k, dst[1] = p[1] + m[1] * (float)k, dst[2] = p[2] + m[2] * (float)k;
        dst[3] = dst[4] = 12345.0f; /* padding: never read as a coordinate */
      }
      soupIndices[3 * i + v] = (uint32_t)(3 * i + v);
    }
  }
  for (i = 0; i < kSegments; ++i) {
    float a[3] = {between(-4, 4), between(-4, 4), between(-4, 4)};
    for (k = 0; k < 3; ++k) {
      float b = a[k] + between(-0.8f, 0.8f), move = between(-0.4f, 0.4f);
      segVerts[0][6 * i + k] = a[k], segVerts[0][6 * i + 3 + k] = b;
      segVerts[1][6 * i + k] = a[k] + move, segVerts[1][6 * i + 3 + k] = b + move;
    }
    segIndices[2 * i] = (uint32_t)(2 * i), segIndices[2 * i + 1] = (uint32_t)(2 * i + 1);
    radii[2 * i] = between(0.02f, 0.1f), radii[2 * i + 1] = between(0.02f, 0.1f);
  }
  for (i = 0; i < 3 * kChildTriangles; ++i) {
    for (k = 0; k < 3; ++k) childVerts[3 * i + k] = between(-1, 1);
    childIndices[i] = (uint32_t)i;
  }
  rs.top = mbrtNewScene(device);
  rs.child = mbrtNewScene(device);
  for (k = 0; k < 3; ++k) steps[k].data = soup[k], steps[k].stride = kStride * sizeof(float), steps[k].count = 3 * kSoupTriangles;
  CHECK(mbrtNewTriangleMesh(rs.top, soupIndices, kSoupTriangles, steps, 3, 0.0f, 1.0f) == 0);
  for (k = 0; k < 2; ++k) steps[k].data = segVerts[k], steps[k].stride = 12, steps[k].count = 2 * kSegments;
  CHECK(mbrtNewSegments(rs.top, segIndices, kSegments, steps, 2, radii, 0.0f, 1.0f) == 1);
  steps[0].data = childVerts, steps[0].stride = 12, steps[0].count = 3 * kChildTriangles;
  CHECK(mbrtNewTriangleMesh(rs.child, childIndices, kChildTriangles, steps, 1, 0.0f, 1.0f) == 0);
  {
    /* Row-major 3x4 keys: a translation that moves, and a scaled one. */
    const float moving[24] = {1, 0, 0, 5, 0, 1, 0, 0, 0, 0, 1, 0, /* */ 1, 0, 0, 5, 0, 1, 0, 1.5f, 0, 0, 1, 0};
    const float scaled[12] = {0, -2, 0, -5, 2, 0, 0, 1, 0, 0, 2, 1};
    CHECK(mbrtNewInstance(rs.top, rs.child, moving, 2, 0.0f, 1.0f) == 2);
    CHECK(mbrtNewInstance(rs.top, rs.child, scaled, 1, 0.0f, 1.0f) == 3);
  }
  mbrtSetGeometryMask(rs.top, 1, 0x2u);
  CHECK(mbrtGetGeometryCount(rs.top) == 4);
  return rs;
}

/* Rays from a box around the scene towards points inside it, at random
 * times (or all at `fixedTime` when it is >= 0), some with a partial mask. */
static void randomRays(MBRTRay* rays, size_t n, float fixedTime) {
  size_t i;
  for (i = 0; i < n; ++i) {
    float o[3], d[3];
    int k;
    for (k = 0; k < 3; ++k) o[k] = between(-9, 9), d[k] = between(-5, 5) - o[k];
    rays[i] = makeRay(o[0], o[1], o[2], d[0], d[1], d[2], fixedTime >= 0 ? fixedTime : uniform());
    if (i % 7 == 0) rays[i].mask = 0x1u; /* misses the segments (mask 0x2) */
    if (i % 11 == 0) rays[i].tfar = between(0.2f, 1.0f);
  }
}

/* Same answer: both miss, or both hit at t within `tol` (relative) and the
 * same primitive unless another one lies at the same t (a tie). */
static int sameHit(const MBRTHit* a, const MBRTHit* b, float tol) {
  float scale;
  if ((a->geomID == MBRT_INVALID_ID) != (b->geomID == MBRT_INVALID_ID)) return 0;
  if (a->geomID == MBRT_INVALID_ID) return 1;
  scale = fabsf(a->t) > 1.0f ? fabsf(a->t) : 1.0f;
  if (fabsf(a->t - b->t) > tol * scale) return 0;
  if (a->geomID == b->geomID && a->primID == b->primID && a->instID == b->instID) return 1;
  return fabsf(a->t - b->t) <= 1e-4f * scale; /* a tie */
}

/* ---- cases ---------------------------------------------------------------- */
static void testVersion(void) {
  int major = -1, minor = -1, patch = -1;
  CHECK(mbrtGetVersion(&major, &minor, &patch) == MBRT_VERSION);
  CHECK(major == MBRT_VERSION_MAJOR && minor == MBRT_VERSION_MINOR && patch == MBRT_VERSION_PATCH);
  CHECK(MBRT_VERSION == MBRT_VERSION_MAJOR * 10000 + MBRT_VERSION_MINOR * 100 + MBRT_VERSION_PATCH);
  CHECK(mbrtGetVersion(NULL, NULL, NULL) == MBRT_VERSION);
}

static void testNullHandles(void) {
  MBRTRay ray = makeRay(0, 0, -1, 0, 0, 1, 0);
  MBRTHit hit;
  MBRTAccelStats stats;
  uint8_t occ = 7;
  const float key[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  MBRTVertexBuffer step = {kTri0, 12, 3};
  /* No error yet. */
  CHECK_ERROR(NULL, MBRT_ERROR_NONE, "");
  CHECK(mbrtNewScene(NULL) == NULL);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "device handle");
  /* mbrtGetError cleared it. */
  CHECK_ERROR(NULL, MBRT_ERROR_NONE, "");
  mbrtReleaseDevice(NULL);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "device handle");
  mbrtSetErrorCallback(NULL, NULL, NULL);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "device handle");
  mbrtReleaseScene(NULL);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "scene handle");
  CHECK(mbrtNewTriangleMesh(NULL, kTriIndices, 1, &step, 1, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "scene handle");
  CHECK(mbrtNewSegments(NULL, kTriIndices, 1, &step, 1, key, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "scene handle");
  CHECK(mbrtNewInstance(NULL, NULL, key, 1, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "scene handle");
  mbrtSetGeometryMask(NULL, 0, 1);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "scene handle");
  CHECK(mbrtGetGeometryCount(NULL) == 0);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "scene handle");
  CHECK(mbrtNewAccel(NULL, "stbvh", NULL) == NULL);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "scene handle");
  mbrtReleaseAccel(NULL);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "accel handle");
  CHECK(mbrtGetAccelStats(NULL, &stats) == 0);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "accel handle");
  hit.geomID = 5;
  CHECK(mbrtIntersect1(NULL, &ray, &hit) == 0);
  CHECK(hit.geomID == MBRT_INVALID_ID);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "accel handle");
  CHECK(mbrtOccluded1(NULL, &ray) == 0);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "accel handle");
  CHECK(mbrtIntersectM(NULL, &ray, &hit, 1) == 0);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "accel handle");
  CHECK(mbrtOccludedM(NULL, &ray, &occ, 1) == 0);
  CHECK(occ == 7);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "accel handle");
  mbrtDefaultBuildOptions(NULL);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "options is NULL");
}

/* Handles of one type passed as another are refused by their tag. */
static void testWrongHandles(void) {
  MBRTDevice device = mbrtNewDevice();
  MBRTScene scene = mbrtNewScene(device);
  MBRTAccel accel;
  MBRTRay ray = makeRay(2, 0, -5, 0, 0, 1, 1);
  MBRTHit hit;
  CHECK(addMovingTriangle(scene, 0, 1) == 0);
  accel = mbrtNewAccel(scene, "bvh-interp", NULL);
  CHECK(accel != NULL);
  CHECK(mbrtNewScene((MBRTDevice)scene) == NULL);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "device handle");
  CHECK(mbrtNewAccel((MBRTScene)device, "stbvh", NULL) == NULL);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "scene handle");
  CHECK(mbrtNewAccel((MBRTScene)accel, "stbvh", NULL) == NULL);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "scene handle");
  CHECK(mbrtIntersect1((MBRTAccel)scene, &ray, &hit) == 0);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "accel handle");
  mbrtReleaseScene((MBRTScene)accel);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "scene handle");
  CHECK(mbrtGetError((MBRTDevice)scene, NULL) == MBRT_ERROR_INVALID_ARGUMENT);
  /* The real handles still work and none of the above touched the device. */
  CHECK(mbrtIntersect1(accel, &ray, &hit) == 1);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  mbrtReleaseAccel(accel);
  mbrtReleaseScene(scene);
  mbrtReleaseDevice(device);
  CHECK_ERROR(NULL, MBRT_ERROR_NONE, "");
}

static void testBadArguments(void) {
  MBRTDevice device = mbrtNewDevice();
  MBRTScene scene = mbrtNewScene(device);
  MBRTVertexBuffer steps[2] = {{kTri0, 12, 3}, {kTri1, 12, 3}};
  const uint32_t outOfRange[] = {0, 1, 3};
  const float nanVerts[] = {0, 0, 0, 1, 0, 0, NAN, 1, 0};
  MBRTVertexBuffer nanStep = {nanVerts, 12, 3};
  MBRTRay ray = makeRay(0, 0, -1, 0, 0, 1, 0);
  MBRTHit hit;
  MBRTAccel accel;
  MBRTBuildOptions options;

  CHECK(mbrtNewTriangleMesh(scene, NULL, 1, steps, 2, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "indices is NULL");
  CHECK(mbrtNewTriangleMesh(scene, kTriIndices, 1, NULL, 2, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "steps is NULL");
  CHECK(mbrtNewTriangleMesh(scene, kTriIndices, 1, steps, 0, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "numSteps");
  steps[1].stride = 8;
  CHECK(mbrtNewTriangleMesh(scene, kTriIndices, 1, steps, 2, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "stride");
  steps[1].stride = 12, steps[1].count = 2;
  CHECK(mbrtNewTriangleMesh(scene, kTriIndices, 1, steps, 2, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "vertices");
  steps[1].count = 3;
  CHECK(mbrtNewTriangleMesh(scene, kTriIndices, 1, steps, 2, 0.5f, 0.25f) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "time range");
  CHECK(mbrtNewTriangleMesh(scene, kTriIndices, 1, steps, 2, 0, 1.5f) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "time range");
  CHECK(mbrtNewSegments(scene, kTriIndices, 1, steps, 2, NULL, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "radii");
  CHECK(mbrtNewInstance(scene, scene, (const float*)kTri0, 1, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "itself");
  CHECK(mbrtGetGeometryCount(scene) == 0);
  mbrtSetGeometryMask(scene, 0, 1);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "out of range");

  /* Errors found when the scene is validated at the build. */
  CHECK(mbrtNewAccel(scene, "stbvh", NULL) == NULL); /* empty scene */
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "mbrtNewAccel");
  CHECK(mbrtNewTriangleMesh(scene, outOfRange, 1, steps, 2, 0, 1) == 0);
  CHECK(mbrtNewAccel(scene, "stbvh", NULL) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "mbrtNewAccel");
  mbrtReleaseScene(scene);
  scene = mbrtNewScene(device);
  CHECK(mbrtNewTriangleMesh(scene, kTriIndices, 1, &nanStep, 1, 0, 1) == 0);
  CHECK(mbrtNewAccel(scene, "bvh-interp", NULL) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "mbrtNewAccel");
  mbrtReleaseScene(scene);

  /* Bad build options. */
  scene = mbrtNewScene(device);
  CHECK(addMovingTriangle(scene, 0, 1) == 0);
  mbrtDefaultBuildOptions(&options);
  options.branching = 3;
  CHECK(mbrtNewAccel(scene, "stbvh", &options) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "mbrtNewAccel");

  /* NULL rays and hits. */
  accel = mbrtNewAccel(scene, "stbvh", NULL);
  CHECK(accel != NULL);
  CHECK(mbrtIntersect1(accel, NULL, &hit) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "ray is NULL");
  CHECK(mbrtIntersect1(accel, &ray, NULL) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "hit is NULL");
  CHECK(mbrtOccluded1(accel, NULL) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "ray is NULL");
  CHECK(mbrtIntersectM(accel, NULL, &hit, 1) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "NULL");
  CHECK(mbrtOccludedM(accel, &ray, NULL, 1) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "NULL");
  CHECK(mbrtGetAccelStats(accel, NULL) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "stats is NULL");
  /* An empty batch is no error. */
  CHECK(mbrtIntersectM(accel, NULL, NULL, 0) == 1);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  /* An invalid ray misses without an error and is counted. */
  ray.dir[2] = NAN;
  CHECK(mbrtIntersect1(accel, &ray, &hit) == 0);
  CHECK(hit.geomID == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  {
    MBRTAccelStats stats;
    CHECK(mbrtGetAccelStats(accel, &stats) == 1);
    CHECK(stats.invalidRays == 1);
  }
  mbrtReleaseAccel(accel);
  mbrtReleaseScene(scene);
  mbrtReleaseDevice(device);
  CHECK_ERROR(NULL, MBRT_ERROR_NONE, "");
}

static void testBadKind(void) {
  MBRTDevice device = mbrtNewDevice();
  MBRTScene scene = mbrtNewScene(device);
  uint32_t i, n = mbrtGetKindCount();
  int sawStbvh = 0, sawBrute = 0;
  CHECK(addMovingTriangle(scene, 0, 1) == 0);
  CHECK(mbrtNewAccel(scene, "no-such-kind", NULL) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "unknown kind \"no-such-kind\"");
  CHECK(mbrtNewAccel(scene, "", NULL) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "unknown kind");
  CHECK(mbrtNewAccel(scene, "STBVH ", NULL) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "stbvh");
  CHECK(mbrtNewAccel(scene, NULL, NULL) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "kind is NULL");
  CHECK(n >= 8);
  for (i = 0; i < n; ++i) {
    const char* name = mbrtGetKindName(i);
    CHECK(name != NULL);
    if (name && !strcmp(name, "stbvh")) sawStbvh = 1;
    if (name && !strcmp(name, "brute")) sawBrute = 1;
  }
  CHECK(sawStbvh && sawBrute);
  CHECK(mbrtGetKindName(n) == NULL);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "out of range");
  mbrtReleaseScene(scene);
  mbrtReleaseDevice(device);
}

typedef struct CallbackLog {
  int calls;
  MBRTError lastCode;
  char lastMessage[256];
} CallbackLog;

static void logError(void* user, MBRTError code, const char* message) {
  CallbackLog* log = (CallbackLog*)user;
  ++log->calls;
  log->lastCode = code;
  strncpy(log->lastMessage, message, sizeof(log->lastMessage) - 1);
  log->lastMessage[sizeof(log->lastMessage) - 1] = '\0';
}

static void testErrorCallback(void) {
  MBRTDevice device = mbrtNewDevice();
  MBRTScene scene = mbrtNewScene(device);
  CallbackLog log;
  memset(&log, 0, sizeof(log));
  mbrtSetErrorCallback(device, logError, &log);
  CHECK(mbrtNewAccel(scene, "no-such-kind", NULL) == NULL);
  CHECK(log.calls == 1);
  CHECK(log.lastCode == MBRT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(log.lastMessage, "no-such-kind") != NULL);
  /* The error is recorded as well. */
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "no-such-kind");
  /* A successful call does not call it. */
  CHECK(addMovingTriangle(scene, 0, 1) == 0);
  CHECK(log.calls == 1);
  mbrtSetErrorCallback(device, NULL, NULL);
  mbrtSetGeometryMask(scene, 9, 1);
  CHECK(log.calls == 1);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "geometry id 9");
  mbrtReleaseScene(scene);
  mbrtReleaseDevice(device);
}

static void testReleaseInUse(void) {
  MBRTDevice device = mbrtNewDevice();
  MBRTScene scene = mbrtNewScene(device);
  MBRTAccel a, b;
  MBRTRay ray = makeRay(2, 0, -5, 0, 0, 1, 1);
  MBRTHit hit;
  CHECK(addMovingTriangle(scene, 0, 1) == 0);
  a = mbrtNewAccel(scene, "stbvh", NULL);
  b = mbrtNewAccel(scene, "brute", NULL);
  CHECK(a && b);
  mbrtReleaseScene(scene);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "2 live accel");
  mbrtReleaseDevice(device);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "1 live scene");
  /* Nothing was released: the accels still trace the scene. */
  CHECK(mbrtIntersect1(a, &ray, &hit) == 1 && fabsf(hit.t - 5.0f) < 1e-5f);
  mbrtReleaseAccel(a);
  mbrtReleaseScene(scene);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "1 live accel");
  CHECK(mbrtIntersect1(b, &ray, &hit) == 1 && fabsf(hit.t - 5.0f) < 1e-5f);
  mbrtReleaseAccel(b);
  mbrtReleaseScene(scene);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  mbrtReleaseDevice(device);
  CHECK_ERROR(NULL, MBRT_ERROR_NONE, "");
}

/* A scene traced by a live accel, directly or through an instance, does not
 * change; instance cycles are refused. */
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

/* The batched calls give the answers of the single-ray ones. */
static void testBatched(void) {
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
static void testSoA(void) {
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

static void testThreads(void) {
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

static void testStats(void) {
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

static void testMemoryBudget(void) {
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

/* A mesh of kAutoTriangles random triangles moving by (2, 1, 0) per step over
 * 3 steps (exact in float: a rigid motion `auto` extracts), one vertex of
 * step 2 moved by `wobble` more (with a tolerance below wobble / diagonal
 * the mesh deforms and is not extracted). */
enum { kAutoTriangles = 40 };
static MBRTScene makeRigidScene(MBRTDevice device, float wobble) {
  static float verts[3][9 * kAutoTriangles];
  static uint32_t indices[3 * kAutoTriangles];
  MBRTScene scene = mbrtNewScene(device);
  MBRTVertexBuffer steps[3];
  int i, k;
  for (i = 0; i < 3 * kAutoTriangles; ++i) {
    float p[3] = {between(-2, 2), between(-2, 2), between(-2, 2)};
    for (k = 0; k < 3; ++k) {
      verts[k][3 * i] = p[0] + 2.0f * (float)k;
      verts[k][3 * i + 1] = p[1] + 1.0f * (float)k;
      verts[k][3 * i + 2] = p[2];
    }
    indices[i] = (uint32_t)i;
  }
  verts[2][0] += wobble;
  for (k = 0; k < 3; ++k) steps[k].data = verts[k], steps[k].stride = 12, steps[k].count = 3 * kAutoTriangles;
  CHECK(mbrtNewTriangleMesh(scene, indices, kAutoTriangles, steps, 3, 0.0f, 1.0f) == 0);
  return scene;
}

/* Hits of `accel` that differ from brute's on random rays. */
static size_t disagreements(MBRTScene scene, MBRTAccel accel) {
  enum { kRays = 4000 };
  static MBRTRay rays[kRays];
  MBRTAccel brute = mbrtNewAccel(scene, "brute", NULL);
  size_t i, wrong = 0, hits = 0;
  randomRays(rays, kRays, -1.0f);
  for (i = 0; i < kRays; ++i) {
    MBRTHit ref, hit;
    int found = mbrtIntersect1(accel, &rays[i], &hit);
    mbrtIntersect1(brute, &rays[i], &ref);
    hits += (size_t)found;
    wrong += !sameHit(&ref, &hit, 1e-5f) || mbrtOccluded1(accel, &rays[i]) != found;
  }
  CHECK(hits > kRays / 50); /* the comparison means something */
  mbrtReleaseAccel(brute);
  return wrong;
}

/* The options of `auto`: defaults, the leaf kind and the tolerance take
 * effect (seen in the statistics), bad values are refused. */
static void testAutoOptions(void) {
  MBRTDevice device = mbrtNewDevice();
  MBRTScene rigid = makeRigidScene(device, 0.0f), wobbly = makeRigidScene(device, 1e-2f);
  MBRTBuildOptions options;
  MBRTAccelStats byCost, byBrute, strict, loose;
  MBRTAccel accel;
  mbrtDefaultBuildOptions(&options);
  CHECK(options.autoLeafKind == NULL && options.autoFitTolerance == 1e-5f);
  /* The rigid mesh becomes an instance of a static tree: forcing brute for
   * it leaves no tree below the top level: fewer nodes, less memory. */
  accel = mbrtNewAccel(rigid, "auto", &options);
  CHECK(accel != NULL && mbrtGetAccelStats(accel, &byCost) == 1);
  CHECK(disagreements(rigid, accel) == 0);
  mbrtReleaseAccel(accel);
  options.autoLeafKind = "brute";
  accel = mbrtNewAccel(rigid, "auto", &options);
  CHECK(accel != NULL && mbrtGetAccelStats(accel, &byBrute) == 1);
  CHECK(disagreements(rigid, accel) == 0);
  mbrtReleaseAccel(accel);
  printf("auto leaf kind by cost: %zu nodes, %zu bytes; brute: %zu nodes, %zu bytes\n",
         byCost.innerNodes + byCost.leafNodes, byCost.bytes, byBrute.innerNodes + byBrute.leafNodes, byBrute.bytes);
  CHECK(byBrute.innerNodes + byBrute.leafNodes < byCost.innerNodes + byCost.leafNodes);
  CHECK(byBrute.bytes < byCost.bytes);
  /* The wobbly mesh: extracted (an instance reference on top) only when the
   * tolerance admits the wobble (with the leaf kind forced, so that `auto`
   * keeps its decomposition rather than the cheaper flat tree of so small
   * a scene). */
  options.autoLeafKind = "bvh-interp";
  options.autoFitTolerance = 0.0f;
  accel = mbrtNewAccel(wobbly, "auto", &options);
  CHECK(accel != NULL && mbrtGetAccelStats(accel, &strict) == 1);
  CHECK(disagreements(wobbly, accel) == 0);
  mbrtReleaseAccel(accel);
  options.autoFitTolerance = 0.5f;
  accel = mbrtNewAccel(wobbly, "auto", &options);
  CHECK(accel != NULL && mbrtGetAccelStats(accel, &loose) == 1);
  mbrtReleaseAccel(accel);
  printf("auto tolerance 0: %zu references; 0.5: %zu references\n", strict.references, loose.references);
  CHECK(loose.references != strict.references);
  /* Bad values. */
  options.autoFitTolerance = -1.0f;
  CHECK(mbrtNewAccel(rigid, "auto", &options) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "tolerance");
  options.autoFitTolerance = 1e-5f;
  options.autoLeafKind = "no-such-kind";
  CHECK(mbrtNewAccel(rigid, "auto", &options) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "no-such-kind");
  options.autoLeafKind = "auto";
  CHECK(mbrtNewAccel(rigid, "auto", &options) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "cannot be auto");
  mbrtReleaseScene(rigid);
  mbrtReleaseScene(wobbly);
  mbrtReleaseDevice(device);
}

/* ---- animations ------------------------------------------------------------ */
/* Rays from around the box [lo, hi] (grown by half) through points inside it. */
static void raysToward(MBRTRay* rays, size_t n, const float lo[3], const float hi[3]) {
  size_t i;
  for (i = 0; i < n; ++i) {
    float o[3], d[3];
    int k;
    for (k = 0; k < 3; ++k) {
      const float size = hi[k] - lo[k];
      o[k] = between(lo[k] - 3 * size, hi[k] + 3 * size);
      d[k] = between(lo[k], hi[k]) - o[k];
    }
    rays[i] = makeRay(o[0], o[1], o[2], d[0], d[1], d[2], uniform());
  }
}

/* The accel gives brute's answers on rays toward the box; some rays hit. */
static void checkAgainstBrute(MBRTAccel accel, MBRTAccel brute, const float lo[3], const float hi[3]) {
  enum { kRays = 2000 };
  static MBRTRay rays[kRays];
  size_t i, hits = 0, wrong = 0;
  raysToward(rays, kRays, lo, hi);
  for (i = 0; i < kRays; ++i) {
    MBRTHit a, b;
    const int found = mbrtIntersect1(accel, &rays[i], &a);
    mbrtIntersect1(brute, &rays[i], &b);
    hits += (size_t)found;
    wrong += !sameHit(&b, &a, 1e-5f) || mbrtOccluded1(accel, &rays[i]) != found;
  }
  CHECK(hits > kRays / 20);
  CHECK(wrong == 0);
}

/* A built-in scene frame by frame: the scene's vertices replaced in place,
 * a refitting accel and a rebuilt one following it, both right. */
static void testAnimation(void) {
  static const float lo[3] = {-0.4f, 0.0f, -0.4f}, hi[3] = {0.4f, 2.0f, 0.9f}; /* skinned at size 0.02 */
  MBRTDevice device = mbrtNewDevice();
  MBRTAnimationOptions options;
  MBRTAnimation animation;
  MBRTScene scene;
  MBRTAccel accel, brute;
  MBRTAccelUpdate update;
  double start = -1, end = -1;
  int64_t first = -1, count = -1, f;
  mbrtDefaultAnimationOptions(&options);
  CHECK(options.keysPerSecond == 24.0 && options.size == 1.0 && options.steps == 0 && options.clip == NULL);
  options.size = 0.02;
  animation = mbrtNewAnimation(device, "skinned", &options);
  CHECK(animation != NULL);
  CHECK(mbrtGetAnimationTimeline(animation, &start, &end) == 1 && start == 0.0 && end == 1.0);
  CHECK(mbrtGetAnimationFrames(animation, 24.0, 180.0, &first, &count) == 1 && first == 0 && count == 24);
  scene = mbrtGetAnimationScene(animation);
  CHECK(scene != NULL && mbrtGetGeometryCount(scene) == 0);
  CHECK(mbrtNewAccel(scene, "bvh-interp", NULL) == NULL); /* no frame yet: an empty scene */
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "");
  CHECK(mbrtSetAnimationFrame(animation, 0, 24.0, 180.0) == 2);
  CHECK(mbrtGetAnimationScene(animation) == scene && mbrtGetGeometryCount(scene) > 0);
  accel = mbrtNewAccel(scene, "bvh-interp", NULL);
  brute = mbrtNewAccel(scene, "brute", NULL);
  CHECK(accel && brute);
  for (f = 4; f < 24 && accel && brute; f += 9) {
    MBRTRay ray = makeRay(0, 1, -5, 0, 0, 1, 0.5f);
    MBRTHit hit;
    CHECK(mbrtSetAnimationFrame(animation, f, 24.0, 180.0) == 1); /* the layout stays */
    CHECK(mbrtIntersect1(accel, &ray, &hit) == 0);               /* stale until updated */
    CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "mbrtUpdateAccel");
    CHECK(mbrtUpdateAccel(accel, MBRT_UPDATE_REFIT, 1.5, &update) == 1);
    CHECK(!strcmp(update.what, "refit") && update.refitted == 1 && update.sahCost == 0.0);
    CHECK(mbrtUpdateAccel(brute, MBRT_UPDATE_REFIT, 1.5, &update) == 1);
    CHECK(!strcmp(update.what, "rebuild (kind cannot refit)") && update.refitted == 0);
    checkAgainstBrute(accel, brute, lo, hi);
  }
  CHECK(mbrtSetAnimationShutter(animation, 0.5, 0.52) == 1); /* as long as a frame: the same steps */
  CHECK(mbrtUpdateAccel(accel, MBRT_UPDATE_AUTO, 1e6, &update) == 1 && update.sahCost > 0.0);
  CHECK(mbrtUpdateAccel(brute, MBRT_UPDATE_REBUILD, 1.5, NULL) == 1);
  checkAgainstBrute(accel, brute, lo, hi);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  mbrtReleaseAnimation(animation); /* refused: accels live */
  CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "live accel");
  mbrtReleaseAccel(accel);
  mbrtReleaseAccel(brute);
  mbrtReleaseDevice(device); /* refused: the animation lives */
  CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "live scene");
  mbrtReleaseAnimation(animation);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  mbrtReleaseDevice(device);
}

/* A scene with instances changes its layout every frame: the accel is
 * built anew, and an OBJ sequence's keys are seconds of its timeline. */
static void testAnimationLayouts(void) {
  static const float lo[3] = {-7, -0.2f, -7}, hi[3] = {7, 2.4f, 7}; /* demo at size 0.05 */
  MBRTDevice device = mbrtNewDevice();
  MBRTAnimationOptions options;
  MBRTAnimation demo, keys;
  MBRTAccel accel, brute;
  MBRTAccelUpdate update;
  double end = 0;
  int64_t count = 0;
  mbrtDefaultAnimationOptions(&options);
  options.size = 0.05;
  demo = mbrtNewAnimation(device, "demo", &options);
  CHECK(mbrtSetAnimationFrame(demo, 0, 24.0, 180.0) == 2);
  accel = mbrtNewAccel(mbrtGetAnimationScene(demo), "msbvh", NULL);
  brute = mbrtNewAccel(mbrtGetAnimationScene(demo), "brute", NULL);
  CHECK(mbrtSetAnimationFrame(demo, 12, 24.0, 180.0) == 2);
  CHECK(mbrtUpdateAccel(accel, MBRT_UPDATE_AUTO, 1.5, &update) == 1);
  CHECK(!strcmp(update.what, "rebuild (new layout)") && update.sahCost > 0.0);
  CHECK(mbrtUpdateAccel(brute, MBRT_UPDATE_REFIT, 1.5, &update) == 1);
  CHECK(!strcmp(update.what, "rebuild (new layout)"));
  checkAgainstBrute(accel, brute, lo, hi);
  mbrtReleaseAccel(accel);
  mbrtReleaseAccel(brute);
  mbrtReleaseAnimation(demo);

  mbrtDefaultAnimationOptions(&options);
  options.keysPerSecond = 4.0;
  keys = mbrtNewAnimation(device, MBRT_TEST_DATA "/keys", &options);
  CHECK(mbrtGetAnimationTimeline(keys, NULL, &end) == 1 && end == 0.25);
  CHECK(mbrtGetAnimationFrames(keys, 4.0, 180.0, NULL, &count) == 1 && count == 1);
  CHECK(mbrtSetAnimationShutter(keys, 0.0, 0.25) == 2 && mbrtGetGeometryCount(mbrtGetAnimationScene(keys)) == 1);
  mbrtReleaseAnimation(keys);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
  mbrtReleaseDevice(device);
}

/* Bad input and misuse: a clear error, nothing changed. */
static void testAnimationErrors(void) {
  MBRTDevice device = mbrtNewDevice();
  MBRTAnimationOptions options;
  MBRTAnimation animation;
  MBRTScene scene, other;
  MBRTAccel accel;
  MBRTVertexBuffer step = {kTri0, 12, 3};
  static const float identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  CHECK(mbrtNewAnimation(NULL, "skinned", NULL) == NULL);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "device");
  CHECK(mbrtNewAnimation(device, NULL, NULL) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "input is NULL");
  CHECK(mbrtNewAnimation(device, MBRT_TEST_DATA "/cube_scene.json", NULL) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "JSON scene file");
  CHECK(mbrtNewAnimation(device, MBRT_TEST_DATA "/no_such_file.glb", NULL) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "no_such_file.glb");
  CHECK(mbrtNewAnimation(device, "no_such_scene", NULL) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "no_such_scene");
  mbrtDefaultAnimationOptions(&options);
  options.motion = "rotate:90";
  CHECK(mbrtNewAnimation(device, "skinned", &options) == NULL); /* a motion moves a static mesh only */
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "procedural motion");
  options.motion = NULL;
  options.keysPerSecond = 0.0;
  CHECK(mbrtNewAnimation(device, MBRT_TEST_DATA "/keys", &options) == NULL);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "keys per second");
  CHECK(mbrtGetAnimationTimeline(NULL, NULL, NULL) == 0);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "animation handle");
  CHECK(mbrtSetAnimationFrame((MBRTAnimation)device, 0, 24.0, 180.0) == 0);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "animation handle");

  mbrtDefaultAnimationOptions(&options);
  options.size = 0.02;
  animation = mbrtNewAnimation(device, "skinned", &options);
  scene = mbrtGetAnimationScene(animation);
  CHECK(mbrtSetAnimationFrame(animation, 24, 24.0, 180.0) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "frames 0 to 23 at 24 fps");
  CHECK(mbrtSetAnimationFrame(animation, -1, 24.0, 180.0) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "outside the timeline");
  CHECK(mbrtSetAnimationFrame(animation, 0, 0.0, 180.0) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "frame rate");
  CHECK(mbrtGetAnimationFrames(animation, 24.0, 400.0, NULL, NULL) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "shutter angle");
  CHECK(mbrtSetAnimationShutter(animation, 0.5, 0.25) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "open <= close");
  CHECK(mbrtSetAnimationShutter(animation, 0.5, NAN) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "finite");
  CHECK(mbrtSetAnimationFrame(animation, 3, 24.0, 180.0) == 2);
  /* Only the animation changes its scene. */
  CHECK(mbrtNewTriangleMesh(scene, kTriIndices, 1, &step, 1, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "belongs to an animation");
  mbrtSetGeometryMask(scene, 0, 1);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "belongs to an animation");
  mbrtReleaseScene(scene);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "mbrtReleaseAnimation");
  other = mbrtNewScene(device);
  CHECK(mbrtNewInstance(other, scene, identity, 1, 0, 1) == MBRT_INVALID_ID);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_OPERATION, "cannot be instanced");
  mbrtReleaseScene(other);
  accel = mbrtNewAccel(scene, "bvh-interp", NULL);
  CHECK(mbrtUpdateAccel(accel, (MBRTUpdatePolicy)7, 1.5, NULL) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "update policy");
  CHECK(mbrtUpdateAccel(accel, MBRT_UPDATE_AUTO, 0.5, NULL) == 0);
  CHECK_ERROR(device, MBRT_ERROR_INVALID_ARGUMENT, "rebuild factor");
  CHECK(mbrtUpdateAccel(NULL, MBRT_UPDATE_AUTO, 1.5, NULL) == 0);
  CHECK_ERROR(NULL, MBRT_ERROR_INVALID_ARGUMENT, "accel handle");
  mbrtReleaseAccel(accel);
  mbrtReleaseAnimation(animation);
  CHECK_ERROR(device, MBRT_ERROR_NONE, "");
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
