// The command-line options of frame sequences and of the camera (frames.h).
#include <algorithm>

#include "frames.h"

namespace mbrt::tools {
namespace {

Vec3f vec(const std::vector<float>& v) { return {v[0], v[1], v[2]}; }

void addVector(CLI::App& cmd, const std::string& name, std::vector<float>& v, const std::string& help) {
  cmd.add_option(name, v, help)->delimiter(',')->expected(3)->check(finiteIn(-1e18, 1e18));
}

}  // namespace

void addSequenceOptions(CLI::App& cmd, SequenceArgs& args) {
  cmd.add_option("--frames", args.frames,
                 "Render frames A to B (inclusive) every STEP: A:B[:STEP]; frame f's shutter opens at f/fps seconds "
                 "of the input's timeline; -o is then a pattern such as frame_%04d.png");
  cmd.add_option("--shutter-angle", args.shutterAngle, "Shutter of a frame in degrees of its 1/fps (--frames)")
      ->check(finiteIn(0.0, 360.0))
      ->capture_default_str();
  cmd.add_option("--update", args.update,
                 "How the structure follows the scene per frame: refit, rebuild, or auto (refit until the SAH cost "
                 "grows past --rebuild-factor times the last rebuild's)")
      ->check(CLI::IsMember({"refit", "rebuild", "auto"}))
      ->capture_default_str();
  cmd.add_option("--rebuild-factor", args.rebuildFactor, "SAH growth over the last rebuild that makes auto rebuild")
      ->check(finiteIn(1.0, 1e6))
      ->capture_default_str();
  cmd.add_flag("--resume", args.resume, "Skip frames whose file exists (files are only ever written whole)");
  cmd.add_option("--mp4", args.mp4, "Also make this MP4 of the PNG frames with ffmpeg, when it is installed");
}

void addCameraOptions(CLI::App& cmd, SequenceArgs& args) {
  addVector(cmd, "--eye", args.eye, "Camera position X,Y,Z (default: the input's camera, or a framing of the scene)");
  addVector(cmd, "--target", args.target, "Point X,Y,Z the camera looks at");
  addVector(cmd, "--up", args.up, "Up direction X,Y,Z of the camera");
  cmd.add_option("--fov", args.fov, "Vertical field of view in degrees")->check(finiteIn(0.0, 179.0, true));
}

void refuseSequenceOptions(const CLI::App& cmd, const SequenceArgs& args) {
  if (!args.frames.empty()) return;
  for (const char* option : {"--shutter-angle", "--update", "--rebuild-factor", "--resume", "--mp4"})
    if (cmd.count(option) > 0) throw UsageError(std::string(option) + " applies to a sequence: give --frames A:B");
}

CameraOverrides cameraOverrides(const SequenceArgs& args, float aperture, float focus) {
  CameraOverrides c;
  if (!args.eye.empty()) c.eye = vec(args.eye);
  if (!args.target.empty()) c.target = vec(args.target);
  if (!args.up.empty()) c.up = vec(args.up);
  if (args.fov > 0.0f) c.fov = args.fov;
  if (aperture >= 0.0f) c.aperture = aperture;
  if (focus >= 0.0f) c.focus = focus;
  return c;
}

}  // namespace mbrt::tools
