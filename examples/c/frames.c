/* An animation through the C API: an input loaded once (a built-in scene,
 * or the glTF file, OBJ sequence or mesh named on the command line), its
 * scene sampled frame by frame, an accel that follows it by refitting, and
 * one ray per frame through the middle of the scene's bounds.
 * Exits 1 when a frame misses, 2 on an API error.
 *
 *   cc -std=c99 frames.c $(pkg-config --cflags --libs mbrt) -o frames && ./frames [INPUT]
 */
#include <math.h>
#include <stdio.h>

#include <mbrt/mbrt.h>

static int apiError(MBRTDevice device, const char* what) {
  const char* message;
  MBRTError code = mbrtGetError(device, &message);
  fprintf(stderr, "frames: %s failed (error %d): %s\n", what, (int)code, message);
  return 2;
}

int main(int argc, char** argv) {
  const char* input = argc > 1 ? argv[1] : "skinned";
  const double fps = 24.0, shutterAngle = 180.0;
  MBRTDevice device = mbrtNewDevice();
  MBRTAnimationOptions options;
  MBRTAnimation animation;
  MBRTAccel accel = NULL;
  int64_t first = 0, count = 0, f;
  int misses = 0;
  mbrtDefaultAnimationOptions(&options);
  options.size = 0.05; /* a small built-in scene */
  animation = mbrtNewAnimation(device, input, &options);
  if (!animation) return apiError(device, "mbrtNewAnimation");
  if (!mbrtGetAnimationFrames(animation, fps, shutterAngle, &first, &count)) return apiError(device, "frames");
  if (count > 8) count = 8;
  for (f = first; f < first + count; ++f) {
    /* A ray down the middle of the skinned figure, at the middle of the
     * frame's shutter (time 0.5 of its normalized [0, 1]). */
    MBRTRay ray = {{0.0f, 1.0f, -10.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, INFINITY, 0.5f, 0xFFFFFFFFu};
    MBRTHit hit;
    MBRTAccelUpdate update;
    const int change = mbrtSetAnimationFrame(animation, f, fps, shutterAngle);
    if (!change) return apiError(device, "mbrtSetAnimationFrame");
    if (!accel) {
      accel = mbrtNewAccel(mbrtGetAnimationScene(animation), "bvh-interp", NULL);
      if (!accel) return apiError(device, "mbrtNewAccel");
      snprintf(update.what, sizeof update.what, "build");
    } else if (!mbrtUpdateAccel(accel, MBRT_UPDATE_AUTO, 1.5, &update)) {
      return apiError(device, "mbrtUpdateAccel");
    }
    if (mbrtIntersect1(accel, &ray, &hit)) {
      printf("frame %lld: %-8s %s, hit t = %.4f\n", (long long)f, change == 1 ? "vertices" : "layout", update.what,
             hit.t);
    } else {
      const char* message;
      if (mbrtGetError(device, &message) != MBRT_ERROR_NONE) return apiError(device, "mbrtIntersect1");
      printf("frame %lld: miss\n", (long long)f);
      ++misses;
    }
  }
  mbrtReleaseAccel(accel);
  mbrtReleaseAnimation(animation);
  mbrtReleaseDevice(device);
  return misses && argc == 1 ? 1 : 0;
}
