/* The C API tests' shared checks and helpers (capi_test.h). */
#include "capi_test.h"

int gFailures = 0;

void checkError(MBRTDevice device, MBRTError expected, const char* part, const char* file, int line) {
  const char* message = NULL;
  MBRTError code = mbrtGetError(device, &message);
  if (code != expected || message == NULL || (part && !strstr(message, part))) {
    fprintf(stderr, "%s:%d: expected error %d containing \"%s\", got %d: \"%s\"\n", file, line, (int)expected,
            part ? part : "", (int)code, message ? message : "(null)");
    ++gFailures;
  }
}

/* xorshift */
static uint64_t gRng = 88172645463325252ull;
float uniform(void) {
  gRng ^= gRng << 13;
  gRng ^= gRng >> 7;
  gRng ^= gRng << 17;
  return (float)((gRng >> 40) * (1.0 / 16777216.0));
}
float between(float lo, float hi) { return lo + (hi - lo) * uniform(); }

const float kTri0[9] = {-1, -1, 0, 1, -1, 0, 0, 1, 0};
const float kTri1[9] = {1, -1, 0, 3, -1, 0, 2, 1, 0};
const uint32_t kTriIndices[3] = {0, 1, 2};

/* One triangle moving by +2 in x over [time0, time1]. */
uint32_t addMovingTriangle(MBRTScene scene, float time0, float time1) {
  MBRTVertexBuffer steps[2] = {{kTri0, 12, 3}, {kTri1, 12, 3}};
  return mbrtNewTriangleMesh(scene, kTriIndices, 1, steps, 2, time0, time1);
}

MBRTRay makeRay(float ox, float oy, float oz, float dx, float dy, float dz, float time) {
  MBRTRay r;
  r.org[0] = ox, r.org[1] = oy, r.org[2] = oz;
  r.dir[0] = dx, r.dir[1] = dy, r.dir[2] = dz;
  r.tnear = 0.0f;
  r.tfar = INFINITY;
  r.time = time;
  r.mask = 0xFFFFFFFFu;
  return r;
}

void randomRays(MBRTRay* rays, size_t n, float fixedTime) {
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


int sameHit(const MBRTHit* a, const MBRTHit* b, float tol) {
  float scale;
  if ((a->geomID == MBRT_INVALID_ID) != (b->geomID == MBRT_INVALID_ID)) return 0;
  if (a->geomID == MBRT_INVALID_ID) return 1;
  scale = fabsf(a->t) > 1.0f ? fabsf(a->t) : 1.0f;
  if (fabsf(a->t - b->t) > tol * scale) return 0;
  if (a->geomID == b->geomID && a->primID == b->primID && a->instID == b->instID) return 1;
  return fabsf(a->t - b->t) <= 1e-4f * scale; /* a tie */
}


RandomScene makeRandomScene(MBRTDevice device) {
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
