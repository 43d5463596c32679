/* A triangle moving along x over the shutter, one ray at the end of the
 * shutter (a hit) and one at the start (a miss), through the C API.
 * Prints the hit; exits 1 when an answer is wrong, 2 on an API error.
 *
 *   cc -std=c99 trace.c $(pkg-config --cflags --libs mbrt) -o trace && ./trace
 */
#include <math.h>
#include <stdio.h>

#include <mbrt/mbrt.h>

static int apiError(MBRTDevice device, const char* what) {
  const char* message;
  MBRTError code = mbrtGetError(device, &message);
  fprintf(stderr, "trace: %s failed (error %d): %s\n", what, (int)code, message);
  return 2;
}

int main(void) {
  /* Two time steps: at time 0 the triangle spans x in [-1, 1], at time 1 it
   * has moved by +2 along x. */
  const float step0[] = {-1, -1, 0, 1, -1, 0, 0, 1, 0};
  const float step1[] = {1, -1, 0, 3, -1, 0, 2, 1, 0};
  const uint32_t indices[] = {0, 1, 2};
  MBRTVertexBuffer steps[2] = {{step0, 3 * sizeof(float), 3}, {step1, 3 * sizeof(float), 3}};
  MBRTRay ray = {{2, 0, -5}, 0.0f, {0, 0, 1}, INFINITY, 1.0f, 0xFFFFFFFFu};
  MBRTHit hit;
  MBRTDevice device;
  MBRTScene scene;
  MBRTAccel accel;
  int wrong = 0, hitAtEnd, hitAtStart;

  printf("mbrt %d\n", mbrtGetVersion(NULL, NULL, NULL));
  device = mbrtNewDevice();
  if (!device) return apiError(NULL, "mbrtNewDevice");
  scene = mbrtNewScene(device);
  if (!scene) return apiError(device, "mbrtNewScene");
  if (mbrtNewTriangleMesh(scene, indices, 1, steps, 2, 0.0f, 1.0f) == MBRT_INVALID_ID)
    return apiError(device, "mbrtNewTriangleMesh");
  accel = mbrtNewAccel(scene, "stbvh", NULL);
  if (!accel) return apiError(device, "mbrtNewAccel");

  /* At time 1 the ray meets the triangle's centroid column at z = 0. */
  hitAtEnd = mbrtIntersect1(accel, &ray, &hit);
  printf("time 1: hit %d t %g u %g v %g ng (%g %g %g) geomID %u primID %u\n", hitAtEnd, hit.t, hit.u, hit.v,
         hit.ng[0], hit.ng[1], hit.ng[2], (unsigned)hit.geomID, (unsigned)hit.primID);
  if (!hitAtEnd || fabsf(hit.t - 5.0f) > 1e-5f || hit.geomID != 0 || hit.primID != 0 ||
      fabsf(hit.u - 0.25f) > 1e-5f || fabsf(hit.v - 0.5f) > 1e-5f || fabsf(hit.ng[2] - 4.0f) > 1e-4f) {
    fprintf(stderr, "trace: wrong hit at time 1 (expected t 5, u 0.25, v 0.5, ng (0 0 4), ids 0 0)\n");
    wrong = 1;
  }
  /* At time 0 the triangle is still around x = 0: the ray at x = 2 misses. */
  ray.time = 0.0f;
  hitAtStart = mbrtIntersect1(accel, &ray, &hit);
  printf("time 0: hit %d\n", hitAtStart);
  if (hitAtStart || hit.geomID != MBRT_INVALID_ID) {
    fprintf(stderr, "trace: the ray at time 0 should miss\n");
    wrong = 1;
  }
  if (mbrtGetError(device, NULL) != MBRT_ERROR_NONE) return apiError(device, "tracing");

  mbrtReleaseAccel(accel);
  mbrtReleaseScene(scene);
  mbrtReleaseDevice(device);
  return wrong;
}
