// `mbrt render --frames A:B[:STEP]`: a sequence of frames, each with its own
// shutter (frame_render.h), written as NAME_%04d.png|exr, with a progress
// line per frame, a summary table, --resume and an optional MP4 (ffmpeg).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "frame_render.h"

namespace mbrt::tools {

enum class OutFormat { Png, Exr };

// Throws UsageError unless the extension is .png or .exr.
OutFormat formatOf(const std::string& path);

// The frames A, A+STEP, ... up to B (inclusive) of "A:B[:STEP]", or "A".
// Throws UsageError for a bad spec (B < A, STEP < 1, negative frames).
std::vector<int64_t> parseFrames(const std::string& spec);

// An output pattern: one printf conversion %d, %4d or %04d for the frame
// number (%% for a percent sign). `hasFrameNumber`: whether it has one.
// Throws UsageError for other conversions or more than one.
bool hasFrameNumber(const std::string& pattern);
std::string framePath(const std::string& pattern, int64_t frame);

struct FrameOutput {
  std::string pattern;
  OutFormat format = OutFormat::Png;
  float exposure = -1.0f;  // EV of the PNG's display transform
  bool resume = false;     // skip frames whose file exists (written whole: temp file + rename)
  std::string mp4;         // also an MP4 of the frames through ffmpeg; empty: none
  bool progress = false;   // a progress bar over frames on stderr
};

// Writes a frame's picture as the pattern's format says (atomically).
void writeFrameImage(const std::string& path, const FrameOutput& out, IntegratorKind integrator, const Image& image);

// The options of a sequence and of the camera, as given.
struct SequenceArgs {
  std::string frames;  // "A:B[:STEP]"; empty: one picture
  double shutterAngle = 180.0;
  std::string update = "auto";
  double rebuildFactor = 1.5;
  bool resume = false;
  std::string mp4;
  std::vector<float> eye, target, up;
  float fov = -1.0f;  // < 0: the input's
};
// --frames, --shutter-angle, --update, --rebuild-factor, --resume, --mp4.
void addSequenceOptions(CLI::App& cmd, SequenceArgs& args);
// --eye, --target, --up, --fov.
void addCameraOptions(CLI::App& cmd, SequenceArgs& args);
// Throws UsageError for sequence options given without --frames.
void refuseSequenceOptions(const CLI::App& cmd, const SequenceArgs& args);
CameraOverrides cameraOverrides(const SequenceArgs& args, float aperture, float focus);

// Renders the sequence (over MPI ranks when started by mpirun with several
// ranks and built with MBRT_MPI). Throws UsageError before any work for bad
// frames or patterns; ExitStatus(130/143) when stopped by a signal, and
// ExitStatus(1) naming the frames not written when a frame fails.
void runFrameSequence(const FrameJob& job, const std::vector<int64_t>& frames, const FrameOutput& out);

// Shared with the MPI run: the checks before any work, the frames still to
// render (--resume), the per-frame line and the summary.
void checkFrameOutputs(const FrameJob& job, const std::vector<int64_t>& frames, const FrameOutput& out);
std::vector<int64_t> framesToRender(const std::vector<int64_t>& frames, const FrameOutput& out);
void printFrameLine(const FrameRecord& r, const std::string& path, int rank = -1);
void printSummary(const std::vector<FrameRecord>& records, size_t skipped, double wallSeconds, int workers);
// "3, 5-9, 12" (sorted).
std::string frameList(std::vector<int64_t> frames);
// The MP4 of the written frames through ffmpeg, when asked and installed.
void writeMp4(const std::vector<int64_t>& frames, const FrameOutput& out, double fps);

}  // namespace mbrt::tools
