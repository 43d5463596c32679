// The C API's animations and the update of an accel from frame to frame
// (mbrt/mbrt.h): an mbrt::Animation behind a handle, its scene a scene
// handle that only the animation changes.
#include <cmath>

#include "c/handles.h"

using namespace mbrt::capi;

namespace {

mbrt::AnimationOptions animationOptions(const MBRTAnimationOptions& c) {
  mbrt::AnimationOptions o;
  if (c.clip) o.clip = c.clip;
  o.steps.steps = c.steps;
  o.keysPerSecond = c.keysPerSecond;
  if (c.motion) o.motion = c.motion;
  o.size = c.size;
  o.seed = c.seed;
  o.stage = c.stage != 0;
  return o;
}

mbrt::FrameClock clock(double fps, double shutterAngleDegrees) {
  mbrt::FrameClock c;
  c.fps = fps;
  c.shutterAngleDegrees = shutterAngleDegrees;
  return c;
}

// 1 when the frame replaced the scene's vertices in place, 2 when it
// replaced its geometries.
int changeCode(const mbrt::Animation& a) { return a.change() == mbrt::SceneChange::Vertices ? 1 : 2; }

}  // namespace

extern "C" {

void mbrtDefaultAnimationOptions(MBRTAnimationOptions* options) {
  guarded(nullptr, 0, "mbrtDefaultAnimationOptions", [&] {
    require(options != nullptr, "options is NULL");
    const mbrt::AnimationOptions o;
    options->clip = nullptr;
    options->steps = o.steps.steps;
    options->keysPerSecond = o.keysPerSecond;
    options->motion = nullptr;
    options->size = o.size;
    options->seed = o.seed;
    options->stage = o.stage ? 1 : 0;
    return 0;
  });
}

MBRTAnimation mbrtNewAnimation(MBRTDevice device, const char* input, const MBRTAnimationOptions* options) {
  return guarded<MBRTAnimation>(deviceOf(device), nullptr, "mbrtNewAnimation", [&] {
    checkDevice(device);
    require(input != nullptr, "input is NULL");
    MBRTAnimationOptions given;
    mbrtDefaultAnimationOptions(&given);
    if (options) given = *options;
    auto a = std::make_unique<MBRTAnimationT>();
    a->device = device;
    a->animation = std::make_unique<mbrt::Animation>(input, animationOptions(given));
    auto scene = std::make_unique<MBRTSceneT>();
    scene->device = device;
    scene->data->scene = a->animation->current().scene;
    scene->animation = a.get();
    a->scene = scene.release();
    device->liveScenes.fetch_add(1);
    return a.release();
  });
}

void mbrtReleaseAnimation(MBRTAnimation animation) {
  guarded(deviceOf(animation), 0, "mbrtReleaseAnimation", [&] {
    checkAnimation(animation);
    const uint64_t live = animation->scene->liveAccels.load();
    if (live)
      fail(MBRT_ERROR_INVALID_OPERATION, "the animation's scene has " + std::to_string(live) +
                                             " live accel(s) built on it; release them first");
    animation->device->liveScenes.fetch_sub(1);
    animation->scene->tag = 0;
    delete animation->scene;
    animation->tag = 0;
    delete animation;
    return 0;
  });
}

int mbrtGetAnimationTimeline(MBRTAnimation animation, double* start, double* end) {
  return guarded(deviceOf(animation), 0, "mbrtGetAnimationTimeline", [&] {
    checkAnimation(animation);
    const mbrt::Timeline& t = animation->animation->timeline();
    if (start) *start = t.start;
    if (end) *end = t.end;
    return 1;
  });
}

int mbrtGetAnimationFrames(MBRTAnimation animation, double fps, double shutterAngleDegrees, int64_t* first,
                           int64_t* count) {
  return guarded(deviceOf(animation), 0, "mbrtGetAnimationFrames", [&] {
    checkAnimation(animation);
    const mbrt::FrameRange r = animation->animation->frames(clock(fps, shutterAngleDegrees));
    if (first) *first = r.first;
    if (count) *count = r.count;
    return 1;
  });
}

MBRTScene mbrtGetAnimationScene(MBRTAnimation animation) {
  return guarded<MBRTScene>(deviceOf(animation), nullptr, "mbrtGetAnimationScene", [&] {
    checkAnimation(animation);
    return animation->scene;
  });
}

int mbrtSetAnimationFrame(MBRTAnimation animation, int64_t frame, double fps, double shutterAngleDegrees) {
  return guarded(deviceOf(animation), 0, "mbrtSetAnimationFrame", [&] {
    checkAnimation(animation);
    animation->animation->frame(frame, clock(fps, shutterAngleDegrees));
    return changeCode(*animation->animation);
  });
}

int mbrtSetAnimationShutter(MBRTAnimation animation, double open, double close) {
  return guarded(deviceOf(animation), 0, "mbrtSetAnimationShutter", [&] {
    checkAnimation(animation);
    animation->animation->sceneOver(open, close);
    return changeCode(*animation->animation);
  });
}

int mbrtUpdateAccel(MBRTAccel accel, MBRTUpdatePolicy policy, double rebuildFactor, MBRTAccelUpdate* update) {
  return guarded(deviceOf(accel), 0, "mbrtUpdateAccel", [&] {
    checkAccel(accel);
    require(policy == MBRT_UPDATE_AUTO || policy == MBRT_UPDATE_REFIT || policy == MBRT_UPDATE_REBUILD,
            "unknown update policy (MBRT_UPDATE_AUTO, MBRT_UPDATE_REFIT or MBRT_UPDATE_REBUILD)");
    const mbrt::UpdatePolicy p = policy == MBRT_UPDATE_REFIT     ? mbrt::UpdatePolicy::Refit
                                 : policy == MBRT_UPDATE_REBUILD ? mbrt::UpdatePolicy::Rebuild
                                                                 : mbrt::UpdatePolicy::Auto;
    if (p != accel->updater.policy() || rebuildFactor != accel->updater.rebuildFactor())
      accel->updater = mbrt::AccelUpdater(p, rebuildFactor);  // a new policy starts afresh
    const mbrt::Scene& scene = *accel->scene->data->scene;
    const mbrt::AccelUpdate done = accel->updater.update(accel->accel, scene, accel->options);
    accel->sceneVersion = scene.version();
    if (update) {
      std::memset(update, 0, sizeof(*update));
      std::strncpy(update->what, done.what.c_str(), sizeof(update->what) - 1);
      update->refitted = done.refitted ? 1 : 0;
      update->seconds = done.seconds;
      update->sahCost = done.sah;
    }
    return 1;
  });
}

}  // extern "C"
