/* Tests of the C API (mbrt/mbrt.h): wrong calls and their errors (null,
 * released and wrong handles, bad arguments and kinds, the error callback,
 * releasing what is in use). Cases run by test_capi.c's main. */
#include <stdlib.h>

#include "capi_test.h"

void testNullHandles(void) {
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
void testWrongHandles(void) {
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

void testBadArguments(void) {
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

void testBadKind(void) {
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

void testErrorCallback(void) {
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

void testReleaseInUse(void) {
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
