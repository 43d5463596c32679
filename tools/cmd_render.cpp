// `mbrt render`: motion-blurred pictures with any structure (mbrt/render.h):
// normals, ambient occlusion, diffuse path tracing and heat maps of the
// traversal work, PNG or EXR by the output's extension.
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "mbrt/image.h"
#include "mbrt/render.h"
#include "progress_bar.h"
#include "scene_loading.h"

namespace mbrt::tools {
namespace {

// Inputs whose --shutter is in their own time units (seconds of a clip).
bool hasOwnClock(const std::string& spec) {
  const std::string ext = std::filesystem::path(spec).extension().string();
  return ext == ".gltf" || ext == ".glb" || ext == ".json";
}

struct RenderArgs {
  std::string positionalScene;
  SceneArgs scene;
  AccelArgs accel;
  std::string out = "mbrt.png";
  std::string integrator = "path";
  std::vector<float> shutter{0.0f, 1.0f};
  std::vector<float> cameraShutter;  // for inputs with their own clock: the part the camera sees
  RenderOptions options;
  int threads = 0;
  float aperture = -1.0f;  // < 0: the scene's camera
  float focus = -1.0f;
  bool progress = false;
  float exposure = -1.0f;  // EV of the PNG's display transform
  std::string compare;  // a second structure, rendered beside the first
};

std::atomic<bool> gInterrupted{false};

extern "C" void onInterrupt(int) {
  gInterrupted.store(true);
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the process at once
}

// Installs the Ctrl-C handler for the lifetime of a render.
class InterruptGuard {
 public:
  InterruptGuard() {
    gInterrupted.store(false);
    previous_ = std::signal(SIGINT, onInterrupt);
  }
  ~InterruptGuard() { std::signal(SIGINT, previous_ == SIG_ERR ? SIG_DFL : previous_); }

 private:
  void (*previous_)(int) = SIG_DFL;
};

enum class OutFormat { Png, Exr };

OutFormat formatOf(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".png") return OutFormat::Png;
  if (ext == ".exr") return OutFormat::Exr;
  throw UsageError("cannot tell the image format of '" + path + "': use a .png or .exr file name");
}

// The best structure this build has: stbvh once it exists, else bvh-interp.
AccelKind bestAccelKind() {
  const auto kinds = availableAccelKinds();
  for (AccelKind k : {AccelKind::Stbvh, AccelKind::BvhInterp})
    if (std::find(kinds.begin(), kinds.end(), k) != kinds.end()) return k;
  return AccelKind::Brute;
}

void run(RenderArgs& args) {
  // Check everything cheap before loading and rendering.
  if (!args.positionalScene.empty()) {
    if (!args.scene.scene.empty() && args.scene.scene != args.positionalScene)
      throw UsageError("two scenes given: '" + args.positionalScene + "' and --scene '" + args.scene.scene + "'");
    args.scene.scene = args.positionalScene;
  }
  if (args.scene.scene.empty()) args.scene.scene = "demo";
  const OutFormat format = formatOf(args.out);
  if (format == OutFormat::Exr && !exrSupported()) writeExr(args.out, Image());  // throws the explanation
  const std::filesystem::path parent = std::filesystem::path(args.out).parent_path();
  std::error_code ec;
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    throw Error("cannot write '" + args.out + "': no directory '" + parent.string() + "'");
  const auto integrator = parseIntegratorKind(args.integrator);
  if (!integrator)
    throw UsageError("unknown integrator '" + args.integrator + "' (available: " + integratorKindList() + ")");
  if (args.shutter.size() != 2 || !(args.shutter[0] >= 0.0f && args.shutter[1] <= 1.0f && args.shutter[0] <= args.shutter[1]))
    throw UsageError("--shutter A,B needs 0 <= A <= B <= 1 (the part of the normalized shutter to render)");

  // Only fuzzykd has motion clusters: refused before the scene is loaded.
  if (*integrator == IntegratorKind::Clusters &&
      (args.accel.accel != "fuzzykd" || (!args.compare.empty() && args.compare != "fuzzykd")))
    throw UsageError("--integrator clusters needs --accel fuzzykd (the motion clusters of its decomposition)");
  if (!args.compare.empty()) {
    const auto kind = parseAccelKind(args.compare);
    const auto kinds = availableAccelKinds();
    if (!kind || std::find(kinds.begin(), kinds.end(), *kind) == kinds.end())
      throw UsageError("unknown accel kind '" + args.compare + "' for --compare (available: " + accelKindList() + ")");
  }

  RenderOptions opt = args.options;
  opt.integrator = *integrator;
  opt.seed = args.scene.seed;
  opt.shutterOpen = args.shutter[0];
  opt.shutterClose = args.shutter[1];

  std::unique_ptr<tbb::task_arena> arena =
      args.threads > 0 ? std::make_unique<tbb::task_arena>(args.threads) : std::make_unique<tbb::task_arena>();
  const int threads = arena->max_concurrency();

  LoadedScene loaded = loadScene(args.scene);
  // --shutter (a shared scene option) is in seconds of the clip for inputs
  // that have a clock (glTF, JSON scene files); for the others it is the
  // part A,B of the normalized shutter [0,1] the camera sees.
  if (!args.scene.shutter.empty() && !hasOwnClock(args.scene.scene)) {
    float a = 0, b = 0;
    char comma = 0;
    std::stringstream ss(args.scene.shutter);
    if (!(ss >> a >> comma >> b) || comma != ',' || !(a >= 0.0f && b <= 1.0f && a <= b))
      throw UsageError("--shutter A,B needs 0 <= A <= B <= 1 for '" + args.scene.scene +
                       "' (the part of the normalized shutter to render), got '" + args.scene.shutter + "'");
    opt.shutterOpen = a;
    opt.shutterClose = b;
  }
  if (!args.cameraShutter.empty()) {
    if (args.cameraShutter.size() != 2 || !(args.cameraShutter[0] >= 0.0f && args.cameraShutter[1] <= 1.0f &&
                                            args.cameraShutter[0] <= args.cameraShutter[1]))
      throw UsageError("--camera-shutter A,B needs 0 <= A <= B <= 1 (the part of the normalized shutter to render)");
    opt.shutterOpen = args.cameraShutter[0];
    opt.shutterClose = args.cameraShutter[1];
  }
  if (args.aperture >= 0.0f) loaded.camera.apertureRadius = args.aperture;
  if (args.focus >= 0.0f) loaded.camera.focusDistance = args.focus;
  std::printf("scene   %s\n", describeScene(loaded).c_str());

  // One picture per structure: --accel, and --compare when given.
  std::vector<AccelArgs> kinds{args.accel};
  if (!args.compare.empty()) {
    kinds.push_back(args.accel);
    kinds.back().accel = args.compare;
  }
  std::vector<RenderResult> results;
  InterruptGuard guard;
  for (const AccelArgs& kindArgs : kinds) {
    if (gInterrupted.load() && !results.empty()) break;  // interrupted: write what there is
    std::unique_ptr<Accel> accel;
    arena->execute([&] { accel = buildAccel(*loaded.scene, kindArgs, bestAccelKind()); });
    const AccelStats built = accel->stats();
    std::printf("accel   %s, built in %.3f s\n", built.kind.c_str(), built.buildSeconds);
    if (isHeatMap(opt.integrator) && built.kind == "embree")
      std::printf("note    embree exposes no traversal counters: the heat map is empty\n");
    std::fflush(stdout);

    ProgressBar bar(args.progress || isatty(STDERR_FILENO));
    RenderResult result;
    arena->execute([&] {
      result = render(loaded, *accel, opt, &gInterrupted, [&](const RenderProgress& p) {
        bar.update(double(p.tilesDone) / double(p.tilesTotal), p.rays, p.seconds);
      });
    });
    bar.finish();
    std::printf("render  %s: %dx%d, %d spp, %s, shutter [%g, %g], %d thread%s: %llu rays in %.3f s (%.3f Mrays/s)\n",
                built.kind.c_str(), opt.width, opt.height, opt.spp, std::string(toString(opt.integrator)).c_str(),
                opt.shutterOpen, opt.shutterClose, threads, threads == 1 ? "" : "s",
                static_cast<unsigned long long>(result.rays), result.seconds, result.raysPerSecond() * 1e-6);
    if (isHeatMap(opt.integrator))
      std::printf("heat    %s: %s per primary ray: mean %.2f, max %.1f\n", built.kind.c_str(),
                  opt.integrator == IntegratorKind::HeatSteps ? "nodes visited" : "intersection tests",
                  result.heatMean, result.heatMaxValue);
    if (!result.complete)
      std::fprintf(stderr, "mbrt: interrupted: %zu of %zu tiles rendered; the rest is black\n", result.tilesDone,
                   result.tilesTotal);
    results.push_back(std::move(result));
  }

  Image picture = results.front().image;
  if (isHeatMap(opt.integrator)) {
    // One scale for every picture: the largest of their own.
    float scale = opt.heatMax;
    if (!(scale > 0.0f))
      for (const RenderResult& r : results) scale = std::max(scale, r.heatScale);
    for (RenderResult& r : results) r.image = heatImage(r.heat, opt.width, opt.height, scale, opt.colorBar);
    picture = results.front().image;
    std::printf("heat    colour bar 0 .. %.1f%s\n", scale,
                opt.heatMax > 0.0f ? " (--heat-max)" : " (99th percentile)");
  }
  if (results.size() == 2) {
    // Side by side, --accel on the left, a thin white gap between.
    const Image &a = results[0].image, &b = results[1].image;
    constexpr int kGap = 4;
    picture = Image(a.width() + kGap + b.width(), std::max(a.height(), b.height()));
    for (int y = 0; y < picture.height(); ++y)
      for (int x = 0; x < picture.width(); ++x) {
        const int xb = x - a.width() - kGap;
        picture.at(x, y) = x < a.width() ? (y < a.height() ? a.at(x, y) : Rgb{})
                           : xb < 0      ? Rgb{1.0f, 1.0f, 1.0f}
                                         : (y < b.height() ? b.at(xb, y) : Rgb{});
      }
  }

  if (format == OutFormat::Exr)
    writeExr(args.out, picture);
  else
    writePng(args.out, tonemap(picture, opt.integrator, args.exposure));
  std::printf("wrote   %s\n", args.out.c_str());
}

}  // namespace

void registerRenderCommand(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand(
      "render", "Render a motion-blurred picture of a scene (PNG, or float EXR by the file extension)");
  cmd->add_option("SCENE", args->positionalScene, "The scene (as --scene); default: demo");
  addSceneOptions(*cmd, args->scene);
  if (auto* s = cmd->get_option_no_throw("--scene")) s->required(false);
  addAccelOptions(*cmd, args->accel, std::string(toString(bestAccelKind())));
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
  // The input side may define --shutter for the source's own time units
  // (e.g. seconds of a glTF clip); then the whole normalized shutter renders.
  if (!cmd->get_option_no_throw("--shutter"))
    cmd->add_option("--shutter", args->shutter, "Part A,B of the normalized shutter [0,1] the camera sees")
        ->delimiter(',')
        ->expected(2)
        ->capture_default_str();
  cmd->add_option("--camera-shutter", args->cameraShutter,
                  "Part A,B of the normalized shutter [0,1] the camera sees when --shutter is in the input's own "
                  "time (glTF seconds): e.g. 0.5,0.5 renders a sharp middle frame of a scene loaded over a whole clip")
      ->delimiter(',')
      ->expected(2);
  cmd->add_option("--threads", args->threads, "Worker threads (0: all cores)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--ao-samples", o.aoSamples, "Occlusion rays per camera sample (ao)")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  cmd->add_option("--ao-distance", o.aoDistance, "Occlusion ray length (ao); 0: 5% of the scene's diagonal")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--depth", o.maxDepth, "Diffuse bounces (path)")->check(CLI::Range(0, 64))->capture_default_str();
  cmd->add_option("--heat-max", o.heatMax,
                  "Value at the top of the heat colour map; 0: the image's 99th percentile (fix it to compare images)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_flag("!--no-color-bar", o.colorBar, "Heat maps without the colour bar");
  cmd->add_option("--aperture", args->aperture, "Thin-lens aperture radius (0: pinhole); default: the scene's")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--focus", args->focus, "Focus distance (0: eye to target); default: the scene's")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--tile", o.tileSize, "Tile side in pixels")->check(CLI::Range(1, 4096))->capture_default_str();
  cmd->add_option("--exposure", args->exposure, "Exposure in stops for PNG output of ao and path (EXR stays linear)")
      ->capture_default_str();
  cmd->add_option("--compare", args->compare,
                  "Also render with this structure and put both pictures side by side (heat maps on one scale)");
  cmd->add_flag("--progress", args->progress, "Show the progress bar even when stderr is not a terminal");
  cmd->callback([args] { run(*args); });
}

}  // namespace mbrt::tools
