// `mbrt render`: motion-blurred pictures with any structure (mbrt/render.h):
// normals, ambient occlusion, diffuse path tracing and heat maps of the
// traversal work, PNG or EXR by the output's extension. Ctrl-C (SIGINT) or
// SIGTERM stops the render, writes what was rendered and exits 130 or 143.
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "mbrt/io/file_access.h"
#include "mbrt/io/image.h"
#include "mbrt/io/mesh_files.h"
#include "mbrt/io/loaders.h"
#include "mbrt/render.h"
#include "output_paths.h"
#include "progress_bar.h"
#include "frames.h"
#include "mpi_frames.h"
#include "scene_loading.h"
#include "stop_signal.h"

namespace mbrt::tools {
namespace {

// Inputs whose --shutter is in their own time units (seconds of a clip).
bool hasOwnClock(const std::string& spec) {
  const std::string ext = std::filesystem::path(spec).extension().string();
  return ext == ".gltf" || ext == ".glb" || ext == ".json";
}

struct RenderArgs {
  SceneArgs scene;
  AccelArgs accel;
  std::string out = "mbrt.png";
  std::string integrator = "path";
  std::vector<float> cameraShutter;  // for inputs with their own clock: the part the camera sees
  RenderOptions options;
  int threads = 0;
  float aperture = -1.0f;  // < 0: the scene's camera
  float focus = -1.0f;
  bool progress = false;
  float exposure = -1.0f;  // EV of the PNG's display transform
  std::string compare;  // a second structure, rendered beside the first
  SequenceArgs sequence;  // --frames and the camera's --eye, --target, --up, --fov
  const CLI::App* cmd = nullptr;
  bool stage = true;    // a loaded model stands on a ground plane (addStage)
};

// What run() settles before loading: the checked options.
struct RenderPlan {
  OutFormat format = OutFormat::Png;
  RenderOptions options;
  std::vector<float> sequenceShutter;  // an OBJ sequence's --shutter in seconds
};

bool isShutterPart(const std::vector<float>& v) {
  return v.size() == 2 && v[0] >= 0.0f && v[1] <= 1.0f && v[0] <= v[1];  // false for NaN
}

void checkAccelKinds(const RenderArgs& args, IntegratorKind integrator) {
  // Only fuzzykd (its motion clusters) and auto (its objects) group the
  // primitives: refused before the scene is loaded.
  const auto groups = [](const std::string& kind) { return kind == "fuzzykd" || kind == "auto"; };
  if (integrator == IntegratorKind::Clusters &&
      (!groups(args.accel.accel) || (!args.compare.empty() && !groups(args.compare))))
    throw UsageError("--integrator clusters needs --accel fuzzykd (its motion clusters) or auto (its objects)");
  if (!args.compare.empty()) {
    const auto kind = parseAccelKind(args.compare);
    const auto kinds = availableAccelKinds();
    if (!kind || std::find(kinds.begin(), kinds.end(), *kind) == kinds.end())
      throw UsageError("unknown accel kind '" + args.compare + "' for --compare (available: " + accelKindList() + ")");
  }
}

// The part of the normalized shutter the camera sees. --shutter is in
// seconds of the input's timeline (mbrt/io/animation.h): for glTF and JSON files
// the loader samples it; for an OBJ sequence (key k at k / fps s) it is
// scaled to the sequence once its keys are known (sequenceShutter); for the
// others (one second of motion) it is the normalized part as it is.
// --camera-shutter: the part of the loaded shutter the camera sees.
void applyShutter(const RenderArgs& args, RenderPlan& plan) {
  RenderOptions& opt = plan.options;
  opt.shutterOpen = 0.0f;
  opt.shutterClose = 1.0f;
  if (!args.scene.shutter.empty() && !hasOwnClock(args.scene.scene)) {
    std::vector<float> v(2);
    char comma = 0;
    std::stringstream ss(args.scene.shutter);
    const bool sequence = isObjSequenceSpec(args.scene.scene);
    const bool parsed = ss >> v[0] >> comma >> v[1] && comma == ',' && (ss >> std::ws).eof();
    if (!parsed || !(v[0] >= 0.0f && v[0] <= v[1] && std::isfinite(v[1])) || (!sequence && !isShutterPart(v)))
      throw UsageError("--shutter A,B needs 0 <= A <= B" + std::string(sequence ? "" : " <= 1") + " for '" +
                       args.scene.scene + "' (seconds of its timeline" +
                       (sequence ? ": key k at k / fps s" : ": its motion spans [0, 1] s") + "), got '" +
                       args.scene.shutter + "'");
    if (sequence) plan.sequenceShutter = v;
    opt.shutterOpen = v[0];
    opt.shutterClose = v[1];
  }
  if (!args.cameraShutter.empty()) {
    if (!isShutterPart(args.cameraShutter))
      throw UsageError("--camera-shutter A,B needs 0 <= A <= B <= 1 (the part of the normalized shutter to render)");
    opt.shutterOpen = args.cameraShutter[0];
    opt.shutterClose = args.cameraShutter[1];
  }
}

// An OBJ sequence's --shutter in seconds, as the part of its keys.
void applySequenceShutter(const RenderArgs& args, const LoadedScene& loaded, RenderPlan& plan) {
  if (plan.sequenceShutter.empty() || !args.cameraShutter.empty()) return;
  const uint32_t segments = loaded.scene->maxSegments();
  const double end = double(segments) / args.scene.fps;
  const double open = plan.sequenceShutter[0], close = plan.sequenceShutter[1];
  if (close > end * (1.0 + 1e-6))
    throw UsageError("--shutter " + args.scene.shutter + " s lies outside '" + args.scene.scene + "' (" +
                     std::to_string(segments + 1) + " keys at " + std::to_string(args.scene.fps) +
                     " fps: 0 to " + std::to_string(end) + " s)");
  plan.options.shutterOpen = segments == 0 ? 0.0f : float(std::min(open / end, 1.0));
  plan.options.shutterClose = segments == 0 ? 0.0f : float(std::min(close / end, 1.0));
}

// Every cheap check before loading and rendering, the output's folder and
// writability included: a bad option fails in a second, not after the render.
RenderPlan checkArgs(RenderArgs& args) {
  resolveScene(args.scene);
  RenderPlan plan;
  plan.format = formatOf(args.out);
  if (plan.format == OutFormat::Exr && !exrSupported()) writeExr(args.out, Image());  // throws the explanation
  const auto integrator = parseIntegratorKind(args.integrator);
  if (!integrator)
    throw UsageError("unknown integrator '" + args.integrator + "' (available: " + integratorKindList() + ")");
  checkAccelKinds(args, *integrator);
  // render() refuses more samples too, but only after loading and building.
  constexpr double kMaxCameraSamples = double(uint64_t(1) << 40);
  const RenderOptions& o = args.options;
  if (double(o.width) * double(o.height) * double(o.spp) > kMaxCameraSamples)
    throw UsageError("--width x --height x --spp = " + std::to_string(uint64_t(o.width) * uint64_t(o.height) *
                                                                      uint64_t(o.spp)) +
                     " camera samples is more than the limit of 2^40");
  refuseSamePath("--out", args.out, "the scene", args.scene.scene);
  io::checkOutputPath(args.out);
  plan.options = args.options;
  plan.options.integrator = *integrator;
  plan.options.seed = args.scene.seed;
  applyShutter(args, plan);
  return plan;
}

void printResult(const std::string& kind, const RenderOptions& opt, int threads, const RenderResult& result) {
  std::printf("render  %s: %dx%d, %d spp, %s, shutter [%g, %g], %d thread%s: %llu rays in %.3f s (%.3f Mrays/s)\n",
              kind.c_str(), opt.width, opt.height, opt.spp, std::string(toString(opt.integrator)).c_str(),
              opt.shutterOpen, opt.shutterClose, threads, threads == 1 ? "" : "s",
              static_cast<unsigned long long>(result.rays), result.seconds, result.raysPerSecond() * 1e-6);
  if (isHeatMap(opt.integrator))
    std::printf("heat    %s: %s per primary ray: mean %.2f, max %.1f\n", kind.c_str(),
                opt.integrator == IntegratorKind::HeatSteps ? "nodes visited" : "intersection tests",
                result.heatMean, result.heatMaxValue);
  if (!result.complete)
    std::fprintf(stderr, "mbrt: interrupted: %zu of %zu tiles rendered; the rest is black\n", result.tilesDone,
                 result.tilesTotal);
}

// Builds one structure and renders with it (stopped early by a signal).
RenderResult renderWith(const LoadedScene& loaded, const AccelArgs& kindArgs, const RenderOptions& opt,
                        bool progress, tbb::task_arena& arena) {
  std::unique_ptr<Accel> accel;
  arena.execute([&] { accel = buildAccel(*loaded.scene, kindArgs, progress); });
  gNothingToKeep.store(false);  // from here a stop keeps the tiles rendered
  const AccelStats built = accel->stats();
  std::printf("accel   %s, built in %.3f s\n", built.kind.c_str(), built.buildSeconds);
  if (isHeatMap(opt.integrator) && built.kind == "embree")
    std::printf("note    embree exposes no traversal counters: the heat map is empty\n");
  std::fflush(stdout);

  RenderResult result;
  if (mpiWorldSize() > 1) {  // under mpirun: rows of tiles over the ranks
    result = renderPictureMpi(loaded, *accel, opt, arena, &gStopRequested);
    if (mpiRank() == 0) printResult(built.kind, opt, arena.max_concurrency() * mpiWorldSize(), result);
    return result;
  }
  ProgressBar bar(progress);
  arena.execute([&] {
    result = render(loaded, *accel, opt, &gStopRequested, [&](const RenderProgress& p) {
      bar.update(double(p.tilesDone) / double(p.tilesTotal), p.rays, p.seconds);
    });
  });
  bar.finish();
  printResult(built.kind, opt, arena.max_concurrency(), result);
  std::fflush(stdout);
  return result;
}

// Heat maps of every picture on one scale: the largest of their own, or
// --heat-max.
void rescaleHeat(std::vector<RenderResult>& results, const RenderOptions& opt) {
  float scale = opt.heatMax;
  if (!(scale > 0.0f))
    for (const RenderResult& r : results) scale = std::max(scale, r.heatScale);
  for (RenderResult& r : results) r.image = heatImage(r.heat, opt.width, opt.height, scale, opt.colorBar);
  std::printf("heat    colour bar 0 .. %.1f%s\n", scale, opt.heatMax > 0.0f ? " (--heat-max)" : " (99th percentile)");
}

// Two pictures side by side, the first on the left, a thin white gap between.
Image sideBySide(const Image& a, const Image& b) {
  constexpr int kGap = 4;
  Image picture(a.width() + kGap + b.width(), std::max(a.height(), b.height()));
  for (int y = 0; y < picture.height(); ++y)
    for (int x = 0; x < picture.width(); ++x) {
      const int xb = x - a.width() - kGap;
      picture.at(x, y) = x < a.width() ? (y < a.height() ? a.at(x, y) : Rgb{})
                         : xb < 0      ? Rgb{1.0f, 1.0f, 1.0f}
                                       : (y < b.height() ? b.at(xb, y) : Rgb{});
    }
  return picture;
}

void writePicture(const RenderArgs& args, const RenderPlan& plan, const Image& picture) {
  if (plan.format == OutFormat::Exr)
    writeExr(args.out, picture);
  else
    writePng(args.out, tonemap(picture, plan.options.integrator, args.exposure));
  std::printf("wrote   %s\n", args.out.c_str());
  std::fflush(stdout);
}

// --frames: a sequence, each frame with its own shutter (frames.h).
void runSequence(RenderArgs& args) {
  if (!args.compare.empty()) throw UsageError("--compare renders one picture: not with --frames");
  if (!args.scene.shutter.empty() || !args.cameraShutter.empty())
    throw UsageError("--frames gives every frame its shutter (--fps, --shutter-angle): not with --shutter or "
                     "--camera-shutter");
  const std::vector<int64_t> frames = parseFrames(args.sequence.frames);
  if (args.cmd->count("--out") == 0) args.out = "frame_%04d.png";
  FrameOutput out;
  out.pattern = args.out;
  out.format = formatOf(framePath(args.out, frames.front()));
  out.exposure = args.exposure;
  out.resume = args.sequence.resume;
  out.mp4 = args.sequence.mp4;
  out.progress = args.progress || stderrIsTerminal();
  FrameJob job;
  args.out = framePath(args.out, frames.front());  // checkArgs checks the first frame's path
  job.options = checkArgs(args).options;
  job.scene = args.scene;
  job.accel = args.accel;
  job.camera = cameraOverrides(args.sequence, args.aperture, args.focus);
  job.clock.fps = args.scene.fps;
  job.clock.shutterAngleDegrees = args.sequence.shutterAngle;
  job.policy = *parseUpdatePolicy(args.sequence.update);  // checked by CLI11
  job.rebuildFactor = args.sequence.rebuildFactor;
  job.threads = args.threads;
  job.stage = args.stage;
  runFrameSequence(job, frames, out);
}

void run(RenderArgs& args) {
  refuseSequenceOptions(*args.cmd, args.sequence);
  if (!args.sequence.frames.empty()) return runSequence(args);
  // One picture under mpirun: rank 0 reports; the others only render rows.
  if (mpiRank() != 0 && !std::freopen("/dev/null", "w", stdout))
    throw Error("rank " + std::to_string(mpiRank()) + ": cannot send stdout to /dev/null");
  RenderPlan plan = checkArgs(args);
  const RenderOptions& opt = plan.options;
  std::unique_ptr<tbb::task_arena> arena =
      args.threads > 0 ? std::make_unique<tbb::task_arena>(args.threads) : std::make_unique<tbb::task_arena>();

  LoadedScene loaded = loadScene(args.scene);
  cameraOverrides(args.sequence, args.aperture, args.focus).apply(loaded.camera);
  applySequenceShutter(args, loaded, plan);
  if (args.stage && addStage(loaded)) std::printf("stage   ground plane, sky and sun (--no-stage: none)\n");
  std::printf("scene   %s\n", describeScene(loaded).c_str());
  std::fflush(stdout);

  // One picture per structure: --accel, and --compare when given.
  std::vector<AccelArgs> kinds{args.accel};
  if (!args.compare.empty()) {
    kinds.push_back(args.accel);
    kinds.back().accel = args.compare;
  }
  const bool progress = args.progress || stderrIsTerminal();
  std::vector<RenderResult> results;
  const StopSignalGuard guard;
  for (const AccelArgs& kindArgs : kinds) {
    if (gStopRequested.load() && !results.empty()) break;  // interrupted: write what there is
    // The first build has nothing to keep: a stop during it ends mbrt at once.
    gNothingToKeep.store(results.empty() && mpiWorldSize() == 1);
    results.push_back(renderWith(loaded, kindArgs, opt, progress, *arena));
  }
  if (mpiRank() != 0) return;  // rank 0 writes the picture
  const int sig = gStopSignal.load();
  const bool anyTile = std::any_of(results.begin(), results.end(), [](const RenderResult& r) { return r.tilesDone > 0; });
  if (sig != 0 && !anyTile) {
    // Nothing rendered (stopped during the build): an old picture is worth more than a black one.
    std::fputs(nothingWrittenNote(sig) + 1, stderr);  // without the leading newline
    throw ExitStatus(128 + sig);
  }
  if (isHeatMap(opt.integrator)) rescaleHeat(results, opt);
  const Image picture = results.size() == 2 ? sideBySide(results[0].image, results[1].image) : results.front().image;
  writePicture(args, plan, picture);
  if (sig != 0) {
    std::fprintf(stderr, "mbrt: stopped by %s: wrote the partial picture\n", signalName(sig));
    throw ExitStatus(128 + sig);
  }
}

}  // namespace

void registerRenderCommand(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand(
      "render", "Render a motion-blurred picture of a scene (PNG, or float EXR by the file extension)");
  args->scene.defaultScene = "demo";
  args->scene.shutterForAnyInput = true;  // the part of the normalized shutter for inputs without a clock
  args->scene.seedForAnyInput = true;     // the seed of the camera samples
  args->scene.fpsForAnyInput = true;      // the clock of frames and of OBJ sequences
  args->cmd = cmd;
  addSceneOptions(*cmd, args->scene);
  addAccelOptions(*cmd, args->accel);
  RenderOptions& o = args->options;
  cmd->add_option("--out,-o", args->out, "Image to write: .png (tonemapped) or .exr (linear float)")
      ->capture_default_str();
  cmd->add_option("--integrator", args->integrator, "What to compute: " + integratorKindList())
      ->capture_default_str();
  cmd->add_option("--width", o.width, "Image width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--height", o.height, "Image height in pixels (heat maps add a colour bar below)")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  cmd->add_option("--spp", o.spp, "Camera samples per pixel, each at its own stratified time")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  cmd->add_option("--camera-shutter", args->cameraShutter,
                  "Part A,B of the normalized shutter [0,1] the camera sees when --shutter is in the input's own "
                  "time (glTF seconds): e.g. 0.5,0.5 renders a sharp middle frame of a scene loaded over a whole clip")
      ->delimiter(',')
      ->expected(2);
  addThreadsOption(*cmd, args->threads);
  cmd->add_option("--ao-samples", o.aoSamples, "Occlusion rays per camera sample (ao)")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  cmd->add_option("--ao-distance", o.aoDistance, "Occlusion ray length (ao); 0: 5% of the scene's diagonal")
      ->check(finiteIn(0.0, 1e18))
      ->capture_default_str();
  cmd->add_option("--depth", o.maxDepth, "Diffuse bounces (path)")->check(CLI::Range(0, 64))->capture_default_str();
  cmd->add_option("--heat-max", o.heatMax,
                  "Value at the top of the heat colour map; 0: the image's 99th percentile (fix it to compare images)")
      ->check(finiteIn(0.0, 1e18))
      ->capture_default_str();
  cmd->add_flag("!--no-color-bar", o.colorBar, "Heat maps without the colour bar");
  cmd->add_option("--aperture", args->aperture, "Thin-lens aperture radius (0: pinhole); default: the scene's")
      ->check(finiteIn(0.0, 1e18));
  cmd->add_option("--focus", args->focus, "Focus distance (0: eye to target); default: the scene's")
      ->check(finiteIn(0.0, 1e18));
  cmd->add_option("--tile", o.tileSize, "Tile side in pixels")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--exposure", args->exposure, "Exposure in stops for PNG output of ao and path (EXR stays linear)")
      ->check(finiteIn(-64.0, 64.0))
      ->capture_default_str();
  cmd->add_option("--compare", args->compare,
                  "Also render with this structure and put both pictures side by side (heat maps on one scale)");
  addSequenceOptions(*cmd, args->sequence);
  addCameraOptions(*cmd, args->sequence);
  cmd->add_flag("!--no-stage", args->stage,
                "A loaded model (glTF, OBJ, PLY) without surroundings: no ground plane under it");
  cmd->add_flag("--progress", args->progress, "Show the progress bar even when stderr is not a terminal");
  cmd->callback([args] { run(*args); });
}

}  // namespace mbrt::tools
