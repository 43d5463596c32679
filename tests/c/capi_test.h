/* What the C API's tests share (tests/c/): the checks, deterministic random
 * numbers, small scenes and rays, and the cases defined outside
 * test_capi.c. C99, no test framework. */
#ifndef MBRT_TESTS_C_CAPI_TEST_H
#define MBRT_TESTS_C_CAPI_TEST_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "mbrt/mbrt.h"

/* The number of failed checks of the case that runs. */
extern int gFailures;

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
void checkError(MBRTDevice device, MBRTError expected, const char* part, const char* file, int line);

/* Deterministic random numbers (xorshift): in [0, 1), in [lo, hi). */
float uniform(void);
float between(float lo, float hi);

/* One triangle (kTri0 at the first step, kTri1 at the second). */
extern const float kTri0[9];
extern const float kTri1[9];
extern const uint32_t kTriIndices[3];
/* One triangle moving by +2 in x over [time0, time1]. */
uint32_t addMovingTriangle(MBRTScene scene, float time0, float time1);
MBRTRay makeRay(float ox, float oy, float oz, float dx, float dy, float dz, float time);
/* Rays from a box around [-9, 9]^3 towards points inside [-5, 5]^3, at random
 * times (or all at `fixedTime` when it is >= 0), some with a partial mask. */
void randomRays(MBRTRay* rays, size_t n, float fixedTime);
/* Same answer: both miss, or both hit at t within `tol` (relative) and the
 * same primitive unless another one lies at the same t (a tie). */
int sameHit(const MBRTHit* a, const MBRTHit* b, float tol);

/* A random moving scene: a triangle soup with 3 steps (strided vertices),
 * round segments with 2 steps, and two instances (moving matrix keys) of a
 * child scene with a static mesh. Geometries 0..3 of the top scene. */
enum { kSoupTriangles = 300, kSegments = 60, kChildTriangles = 80 };
typedef struct RandomScene {
  MBRTScene top, child;
} RandomScene;

RandomScene makeRandomScene(MBRTDevice device);

/* Cases of test_capi_errors.c: wrong calls. */
void testNullHandles(void);
void testWrongHandles(void);
void testBadArguments(void);
void testBadKind(void);
void testErrorCallback(void);
void testReleaseInUse(void);

/* Cases of test_capi_batches.c: batches, threads, statistics. */
void testBatched(void);
void testSoA(void);
void testThreads(void);
void testStats(void);
void testMemoryBudget(void);

/* Cases of test_capi_auto.c: auto's options, animations. */
void testAutoOptions(void);
void testAnimation(void);
void testAnimationLayouts(void);
void testAnimationErrors(void);

#endif
