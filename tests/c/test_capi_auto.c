/* Tests of the C API (mbrt/mbrt.h): `auto`'s options and animations
 * (mbrtAnimation...). Cases run by test_capi.c's main. */
#include <stdlib.h>

#include "capi_test.h"

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
void testAutoOptions(void) {
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
void testAnimation(void) {
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
void testAnimationLayouts(void) {
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
void testAnimationErrors(void) {
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
