/* The C API of mbrt (C99): motion-blur ray tracing behind opaque handles, for
 * renderers and bindings written in C, Rust, Julia, Python, ...
 *
 * Handles. MBRTDevice records errors; MBRTScene holds geometries (triangle
 * meshes and round segments with vertex time steps, instances of other
 * scenes with matrix keys); MBRTAccel is an acceleration structure built
 * over a scene by kind name ("bvh-interp", "stbvh", ...: mbrtGetKindName).
 * Every handle carries a tag checked on every call: a NULL handle or a
 * handle of the wrong type is an error (never a crash), as is every bad
 * argument. Vertex, index, radius and key arrays are copied when a
 * geometry is added: the caller's memory may be freed afterwards.
 *
 * Errors. No call lets an exception or a crash through. A failing call
 * returns its failure value (NULL, MBRT_INVALID_ID, 0) and records an error
 * code and message on the device it concerns, then calls the device's error
 * callback if one is set. mbrtGetError(device, &message) returns the last
 * error and clears it. An error that names no valid device (a NULL or bad
 * handle) is recorded per thread and read with mbrtGetError(NULL, &message).
 *
 * Ownership. A scene belongs to the device it was made on, an accel to the
 * scene it was built on. Releasing a device with live scenes, or a scene
 * with live accels, is refused with MBRT_ERROR_INVALID_OPERATION and
 * nothing is released. A scene instanced by another one stays alive (shared)
 * until every scene instancing it is released, even after its own handle is.
 * A scene traced by a live accel, directly or through instances, is frozen:
 * adding geometry or setting a mask or filter is refused with
 * MBRT_ERROR_INVALID_OPERATION until those accels are released.
 *
 * Thread safety.
 *  - Tracing (mbrtIntersect1, mbrtOccluded1, mbrtIntersectM, mbrtOccludedM,
 *    mbrtIntersectSoA, mbrtOccludedSoA) and mbrtGetAccelStats may run from any number of threads at once, on
 *    the same accel or on different ones. The batched calls run in parallel
 *    themselves (TBB).
 *  - Intersection filters run on the tracing threads, concurrently when
 *    several threads trace: they must be thread-safe then.
 *  - Building (mbrtNewAccel), releasing any handle and changing a scene
 *    (adding geometry, setting masks or filters) need exclusive access: no other call
 *    may use that scene, or an accel built on it, at the same time.
 *  - The C++ contract behind these rules is in mbrt/accel.h; the
 *    concurrent part runs under ThreadSanitizer (scripts/test-tsan.sh).
 *  - Errors and the error callback may be raised from any thread; the
 *    callback must be thread-safe when tracing runs on several threads.
 *    The message passed to it is valid during the call only; the message
 *    returned by mbrtGetError is valid until that thread's next
 *    mbrtGetError.
 */
#ifndef MBRT_MBRT_H
#define MBRT_MBRT_H

#include <stddef.h>
#include <stdint.h>

#define MBRT_VERSION_MAJOR 0
#define MBRT_VERSION_MINOR 1
#define MBRT_VERSION_PATCH 0
/* major * 10000 + minor * 100 + patch */
#define MBRT_VERSION (MBRT_VERSION_MAJOR * 10000 + MBRT_VERSION_MINOR * 100 + MBRT_VERSION_PATCH)

#if defined(_WIN32)
#define MBRT_API
#elif defined(__GNUC__)
#define MBRT_API __attribute__((visibility("default")))
#else
#define MBRT_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* The id of no geometry / primitive / instance (misses, failed calls). */
#define MBRT_INVALID_ID 0xFFFFFFFFu

typedef struct MBRTDeviceT* MBRTDevice;
typedef struct MBRTSceneT* MBRTScene;
typedef struct MBRTAccelT* MBRTAccel;
typedef struct MBRTAnimationT* MBRTAnimation;

typedef enum MBRTError {
  MBRT_ERROR_NONE = 0,
  MBRT_ERROR_INVALID_ARGUMENT = 1,  /* NULL or bad handle, bad value, invalid scene */
  MBRT_ERROR_INVALID_OPERATION = 2, /* not allowed now (e.g. releasing a scene in use) */
  MBRT_ERROR_OUT_OF_MEMORY = 3,     /* allocation failed or memory budget exceeded */
  MBRT_ERROR_UNKNOWN = 4
} MBRTError;

typedef void (*MBRTErrorCallback)(void* userPtr, MBRTError code, const char* message);

/* A ray segment [tnear, tfar] along org + t*dir at shutter time `time` in
 * [0,1]; only geometries whose mask shares a bit with `mask` are hit. Rays
 * with NaN/inf components, zero direction, a time outside [0,1] or
 * tnear > tfar miss (they are counted in MBRTAccelStats.invalidRays). */
typedef struct MBRTRay {
  float org[3];
  float tnear;
  float dir[3];
  float tfar;
  float time;
  uint32_t mask;
} MBRTRay;

/* The closest hit. geomID == MBRT_INVALID_ID on a miss. Inside an instance,
 * geomID/primID name the primitive in the instanced scene and instID the
 * instance's geometry id in the traced scene (MBRT_INVALID_ID otherwise).
 * ng: the unnormalized geometric normal in world space. u, v: barycentrics
 * of v1, v2 for triangles; u along the segment for segments. */
typedef struct MBRTHit {
  float t;
  float u, v;
  float ng[3];
  uint32_t geomID;
  uint32_t primID;
  uint32_t instID;
} MBRTHit;

/* Vertex positions of one time step: `count` xyz float triples, `stride`
 * bytes apart (at least 12). */
typedef struct MBRTVertexBuffer {
  const void* data;
  size_t stride;
  size_t count;
} MBRTVertexBuffer;

/* An instance key as scale, rotation and translation, composed as T*R*S;
 * between keys, scale and translation are interpolated linearly and the
 * rotation by slerp along the shorter arc. rotation: a quaternion
 * (w, x, y, z), normalized by mbrt; a zero or non-finite one, a zero scale
 * component or one that changes sign between keys is refused at the build. */
typedef struct MBRTSRTKey {
  float scale[3];
  float rotation[4];
  float translation[3];
} MBRTSRTKey;

/* An intersection filter: called for each candidate hit on the geometry,
 * with the ray in the geometry's space (inside an instance: the instanced
 * scene's space). Returning 0 rejects the candidate and traversal goes on
 * (alpha testing, transparent shadows); nonzero accepts it. It runs on the
 * tracing threads, concurrently when several threads trace. */
typedef int (*MBRTFilterFunc)(void* userPtr, const MBRTRay* ray, const MBRTHit* candidate);

/* Build options; mbrtDefaultBuildOptions fills the defaults. */
typedef struct MBRTBuildOptions {
  int branching;         /* BVH node width: 2, 4 or 8 */
  int maxLeafSize;       /* primitives per BVH leaf at most */
  int sahBins;           /* bins of the binned SAH */
  float traversalCost;   /* C_T of the SAH (intersection cost is 1) */
  float frozenTime;      /* time of the "frozen" kind */
  size_t memoryBudget;   /* bytes the build may use; 0 = unlimited */
  int maxInstanceDepth;  /* nesting of instances */
  /* "auto" only (docs/auto.md): a part becomes an instance when one affine
   * key per step reproduces every vertex within this fraction of the part's
   * diagonal (0: only exact fits; default 1e-5), and the kind of every object
   * below the top level by name (NULL: chosen per object by cost; "auto" is
   * refused). mbrtNewAccel reads the name during the call only. */
  float autoFitTolerance;
  const char* autoLeafKind;
} MBRTBuildOptions;

typedef struct MBRTAccelStats {
  char kind[32];              /* the kind name, NUL-terminated */
  size_t primitives;          /* triangles + segments + instances, all levels */
  size_t references;          /* primitive references in leaves */
  size_t innerNodes;
  size_t leafNodes;
  size_t maxDepth;
  size_t bytes;               /* structure memory, excluding vertex data */
  size_t peakBuildBytes;      /* largest memory in use during the build */
  double sahCost;
  double buildSeconds;
  uint64_t invalidRays;       /* rays refused since the build */
} MBRTAccelStats;

/* ---- version --------------------------------------------------------------- */
/* Returns MBRT_VERSION of the library; fills the parts where not NULL. */
MBRT_API int mbrtGetVersion(int* major, int* minor, int* patch);

/* ---- device and errors ------------------------------------------------------- */
MBRT_API MBRTDevice mbrtNewDevice(void);
/* Refused (MBRT_ERROR_INVALID_OPERATION) while scenes of the device live. */
MBRT_API void mbrtReleaseDevice(MBRTDevice device);
/* Called on every error recorded on the device; NULL removes it. */
MBRT_API void mbrtSetErrorCallback(MBRTDevice device, MBRTErrorCallback callback, void* userPtr);
/* The last error recorded on the device (NULL: on this thread without a
 * device), cleared by this call. *message (if message is not NULL) is set to
 * its text, "" for MBRT_ERROR_NONE. */
MBRT_API MBRTError mbrtGetError(MBRTDevice device, const char** message);

/* ---- scenes ------------------------------------------------------------------ */
MBRT_API MBRTScene mbrtNewScene(MBRTDevice device);
/* Refused (MBRT_ERROR_INVALID_OPERATION) while accels built on it live. */
MBRT_API void mbrtReleaseScene(MBRTScene scene);

/* A triangle mesh: numTriangles index triples, numSteps >= 1 vertex steps
 * (all with the same count), equidistant over the geometry's time range
 * [time0, time1] inside [0,1] (0 and 1 for the whole shutter). Returns the
 * geometry id (counting up from 0 per scene) or MBRT_INVALID_ID. */
MBRT_API uint32_t mbrtNewTriangleMesh(MBRTScene scene, const uint32_t* indices, size_t numTriangles,
                                      const MBRTVertexBuffer* steps, uint32_t numSteps, float time0,
                                      float time1);
/* Round linear segments: numSegments index pairs, one radius per vertex
 * (steps[0].count of them, the same at every step). */
MBRT_API uint32_t mbrtNewSegments(MBRTScene scene, const uint32_t* indices, size_t numSegments,
                                  const MBRTVertexBuffer* steps, uint32_t numSteps, const float* radii,
                                  float time0, float time1);
/* An instance of `child` (another scene of the same device) with numKeys
 * object-to-world keys, each 12 floats: a row-major 3x4 matrix [R | t]
 * (x' = m[0]x + m[1]y + m[2]z + m[3], ...), interpolated element-wise. */
MBRT_API uint32_t mbrtNewInstance(MBRTScene scene, MBRTScene child, const float* keys, uint32_t numKeys,
                                  float time0, float time1);
/* Same, with SRT keys. */
MBRT_API uint32_t mbrtNewInstanceSRT(MBRTScene scene, MBRTScene child, const MBRTSRTKey* keys, uint32_t numKeys,
                                     float time0, float time1);
/* Sets (NULL: removes) the intersection filter of a triangle or segment
 * geometry; userPtr is passed to it. */
MBRT_API void mbrtSetGeometryFilter(MBRTScene scene, uint32_t geomID, MBRTFilterFunc filter, void* userPtr);
/* Only rays whose mask shares a bit with the geometry's mask hit it. */
MBRT_API void mbrtSetGeometryMask(MBRTScene scene, uint32_t geomID, uint32_t mask);
MBRT_API uint32_t mbrtGetGeometryCount(MBRTScene scene);

/* ---- accels ------------------------------------------------------------------ */
/* The kinds this library can build, in a stable order: names for
 * mbrtNewAccel. Returns NULL for index >= mbrtGetKindCount(). */
MBRT_API uint32_t mbrtGetKindCount(void);
MBRT_API const char* mbrtGetKindName(uint32_t index);

MBRT_API void mbrtDefaultBuildOptions(MBRTBuildOptions* options);
/* Builds the structure `kind` over the scene (options NULL: the defaults).
 * Invalid scenes, unknown kinds and bad options are MBRT_ERROR_INVALID_ARGUMENT,
 * an exceeded memory budget MBRT_ERROR_OUT_OF_MEMORY. */
MBRT_API MBRTAccel mbrtNewAccel(MBRTScene scene, const char* kind, const MBRTBuildOptions* options);
MBRT_API void mbrtReleaseAccel(MBRTAccel accel);
/* Returns 1 on success, 0 on error. */
MBRT_API int mbrtGetAccelStats(MBRTAccel accel, MBRTAccelStats* stats);

/* ---- tracing ----------------------------------------------------------------- */
/* Closest hit: returns 1 on a hit, 0 on a miss or an error (hit->geomID is
 * MBRT_INVALID_ID then). */
MBRT_API int mbrtIntersect1(MBRTAccel accel, const MBRTRay* ray, MBRTHit* hit);
/* Any hit in [tnear, tfar]: returns 1 when occluded, 0 otherwise or on error. */
MBRT_API int mbrtOccluded1(MBRTAccel accel, const MBRTRay* ray);
/* Arrays of `count` rays (array of structs), traced in parallel; hits[i] /
 * occluded[i] (1 or 0) for rays[i]. Returns 1 on success, 0 on error
 * (nothing is written then). */
MBRT_API int mbrtIntersectM(MBRTAccel accel, const MBRTRay* rays, MBRTHit* hits, size_t count);
MBRT_API int mbrtOccludedM(MBRTAccel accel, const MBRTRay* rays, uint8_t* occluded, size_t count);

/* Struct-of-arrays rays: one array of `count` entries per component.
 * orgX ... dirZ are required; tnear, tfar, time and mask may be NULL (every
 * ray then has 0, +inf, 0, all bits). */
typedef struct MBRTRaySoA {
  const float *orgX, *orgY, *orgZ;
  const float *dirX, *dirY, *dirZ;
  const float *tnear, *tfar, *time;
  const uint32_t* mask;
} MBRTRaySoA;

/* Struct-of-arrays hits: one array of `count` entries per field; a NULL
 * field is not written (t, geomID and primID are required). */
typedef struct MBRTHitSoA {
  float *t, *u, *v;
  float *ngX, *ngY, *ngZ;
  uint32_t *geomID, *primID, *instID;
} MBRTHitSoA;

/* The same as mbrtIntersectM / mbrtOccludedM over struct-of-arrays rays
 * (and hits). Returns 1 on success, 0 on error (nothing is written then). */
MBRT_API int mbrtIntersectSoA(MBRTAccel accel, const MBRTRaySoA* rays, const MBRTHitSoA* hits, size_t count);
MBRT_API int mbrtOccludedSoA(MBRTAccel accel, const MBRTRaySoA* rays, uint8_t* occluded, size_t count);

/* ---- animations ------------------------------------------------------------ */
/* An input over its timeline in seconds, loaded once (a glTF file is read
 * and its textures decoded once), and its scene frame by frame: the
 * animation's scene (mbrtGetAnimationScene) is sampled over each frame's
 * shutter, its motion normalized to [0,1], and updated in place. Accels are
 * built on it with mbrtNewAccel and follow it with mbrtUpdateAccel after
 * every mbrtSetAnimationFrame; until then tracing them is refused
 * (MBRT_ERROR_INVALID_OPERATION). The scene belongs to the animation: it is
 * released with it, and adding geometry to it, setting its masks or
 * filters, releasing it or instancing it is refused. Timelines (seconds):
 * a glTF clip's own (a file without a clip: [0, INFINITY), static); an OBJ
 * keyframe sequence's key k at k / keysPerSecond; a built-in scene's or a
 * mesh's motion over [0, 1]. docs/c-api.md, "Animations". */

/* mbrtDefaultAnimationOptions fills the defaults. */
typedef struct MBRTAnimationOptions {
  const char* clip;      /* glTF: the animation by name or index; NULL or "": the first */
  uint32_t steps;        /* glTF: time steps per moving mesh or instance; 0: automatic */
  double keysPerSecond;  /* OBJ sequences: key k at k / keysPerSecond seconds (24) */
  const char* motion;    /* a static .obj/.ply mesh's procedural motion, e.g. "rotate:90"; NULL: none */
  double size;           /* built-in scenes: size factor (1) */
  uint64_t seed;         /* built-in scenes (1) */
  int stage;             /* nonzero: a loaded model stands on a ground plane (geometry after its own) */
} MBRTAnimationOptions;

/* How mbrtUpdateAccel follows the scene: REFIT refits where the kind can
 * (bvh-interp, msbvh) and rebuilds elsewhere; REBUILD rebuilds every frame;
 * AUTO refits until the SAH cost grows past rebuildFactor times the cost
 * right after the last rebuild, then rebuilds. */
typedef enum MBRTUpdatePolicy {
  MBRT_UPDATE_AUTO = 0,
  MBRT_UPDATE_REFIT = 1,
  MBRT_UPDATE_REBUILD = 2,
  MBRT_UPDATE_POLICY_MAX = 0x7FFFFFFF /* not a policy: keeps every int a value of the type (others are refused) */
} MBRTUpdatePolicy;

/* What one mbrtUpdateAccel did. */
typedef struct MBRTAccelUpdate {
  char what[160]; /* "build", "refit", "rebuild", "rebuild (kind cannot refit)", "rebuild (SAH x1.62)",
                      "rebuild (new layout)", or auto's summary of its refit ("refit: 2 instances' keys,
                      1 tree refitted (msbvh)"); NUL-terminated, cut at 159 bytes */
  int refitted;    /* 1 when the tree was refitted and kept */
  double seconds;  /* the refit or (re)build */
  double sahCost;  /* after the update (MBRT_UPDATE_AUTO only; 0 otherwise) */
} MBRTAccelUpdate;

MBRT_API void mbrtDefaultAnimationOptions(MBRTAnimationOptions* options);
/* Loads a .gltf/.glb file (options->clip), an OBJ keyframe sequence (a
 * folder, or a pattern with * ? [), a built-in scene name or an .obj/.ply
 * mesh (options->motion); options NULL: the defaults. A JSON scene file, an
 * unknown name, a missing or bad file is MBRT_ERROR_INVALID_ARGUMENT, with
 * the loader's message. The scene is empty until the first frame. */
MBRT_API MBRTAnimation mbrtNewAnimation(MBRTDevice device, const char* input, const MBRTAnimationOptions* options);
/* Refused (MBRT_ERROR_INVALID_OPERATION) while accels built on its scene live. */
MBRT_API void mbrtReleaseAnimation(MBRTAnimation animation);
/* The timeline in seconds (*end is INFINITY without a clip). Returns 1, 0 on error. */
MBRT_API int mbrtGetAnimationTimeline(MBRTAnimation animation, double* start, double* end);
/* The frames whose shutters lie in the timeline at fps frames per second
 * and a shutter of shutterAngleDegrees / 360 of a frame: *first, *first + 1,
 * ..., *first + *count - 1 (*count is INT64_MAX without a clip). Frame f's
 * shutter opens at f / fps seconds. Returns 1, 0 on error (fps <= 0, an
 * angle outside [0, 360]). */
MBRT_API int mbrtGetAnimationFrames(MBRTAnimation animation, double fps, double shutterAngleDegrees, int64_t* first,
                                    int64_t* count);
/* The animation's scene: the same handle for every frame. */
MBRT_API MBRTScene mbrtGetAnimationScene(MBRTAnimation animation);
/* Samples the scene over frame `frame`'s shutter (open at frame / fps
 * seconds, for shutterAngleDegrees / 360 of a frame). Returns 1 when the
 * scene kept its layout (the same geometries, primitive counts, steps and
 * masks, no instances: its vertices were replaced, and accels can refit), 2
 * when its geometries were replaced (accels are built anew by
 * mbrtUpdateAccel), 0 on error: a frame whose shutter lies outside the
 * timeline (the message names the frames it allows), a bad clock. */
MBRT_API int mbrtSetAnimationFrame(MBRTAnimation animation, int64_t frame, double fps, double shutterAngleDegrees);
/* The same over the shutter [open, close] seconds of the timeline. */
MBRT_API int mbrtSetAnimationShutter(MBRTAnimation animation, double open, double close);
/* Brings an accel up to date with its scene after the scene changed: built
 * anew (with its kind and options) when the scene's geometries were
 * replaced, otherwise refitted or rebuilt by the policy (rebuildFactor >= 1:
 * AUTO's limit, 1.5 is mbrt's default). *update (when not NULL) says what
 * was done. Returns 1, 0 on error (the accel is then without a structure:
 * tracing it is refused until an update succeeds). */
MBRT_API int mbrtUpdateAccel(MBRTAccel accel, MBRTUpdatePolicy policy, double rebuildFactor,
                             MBRTAccelUpdate* update);

#ifdef __cplusplus
}
#endif

#endif /* MBRT_MBRT_H */
