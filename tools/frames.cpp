#include "frames.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "mbrt/io/file_access.h"
#include "mbrt/io/image.h"
#include "mpi_frames.h"
#include "output_paths.h"
#include "progress_bar.h"
#include "stop_signal.h"

namespace mbrt::tools {
namespace {

int64_t parseFrameNumber(const std::string& text, const std::string& spec) {
  int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() || v < 0 || v > (int64_t(1) << 40))
    throw UsageError("--frames must be A:B[:STEP] with whole numbers 0 <= A <= B and STEP >= 1, got '" + spec + "'");
  return v;
}

// The position and length of the pattern's frame conversion (%d, %4d, %04d);
// npos when none.
std::pair<size_t, size_t> frameConversion(const std::string& pattern) {
  std::pair<size_t, size_t> found{std::string::npos, 0};
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') continue;
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      ++i;
      continue;
    }
    size_t j = i + 1;
    while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j])) && j - i <= 3) ++j;
    if (j >= pattern.size() || pattern[j] != 'd')
      throw UsageError("output pattern '" + pattern + "': only %d, %4d or %04d (the frame number) and %% may follow %");
    if (found.first != std::string::npos)
      throw UsageError("output pattern '" + pattern + "' has more than one %d: one frame number per file name");
    found = {i, j + 1 - i};
    i = j;
  }
  return found;
}

// A progress bar over the frames on a terminal (stderr), redrawn per frame.
class FrameBar {
 public:
  FrameBar(bool enabled, size_t total) : enabled_(enabled && stderrIsTerminal()), total_(total) {}
  void update(size_t done, const FrameRecord& last, double seconds) {
    if (!enabled_ || total_ == 0) return;
    constexpr int kWidth = 30;
    const double fraction = double(done) / double(total_);
    std::string bar(size_t(fraction * kWidth + 0.5), '#');
    bar.resize(kWidth, '.');
    const double left = done > 0 ? seconds / double(done) * double(total_ - done) : 0.0;
    std::fprintf(stderr, "\r[%s] %zu/%zu frames  update %.1f ms  render %.2f s  %s left   ", bar.c_str(), done,
                 total_, last.update.seconds * 1e3, last.renderSeconds, formatSeconds(left).c_str());
    std::fflush(stderr);
    drawn_ = true;
  }
  void finish() {
    if (drawn_) std::fprintf(stderr, "\n");
    drawn_ = false;
  }
  ~FrameBar() { finish(); }

 private:
  bool enabled_;
  size_t total_;
  bool drawn_ = false;
};

struct Spread {
  double sum = 0.0, min = 1e300, max = 0.0;
  size_t n = 0;
  void add(double v) {
    sum += v;
    min = std::min(min, v);
    max = std::max(max, v);
    ++n;
  }
  void print(const char* name, double scale, const char* unit) const {
    if (n == 0) return;
    std::printf("  %-16s %6zu  %10.3f  %10.3f  %10.3f  %10.3f %s\n", name, n, sum / double(n) * scale, min * scale,
                max * scale, sum * scale, unit);
  }
};

// Runs argv, waiting; the exit status (127 when it cannot start).
int runProgram(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::fflush(stdout);
  const pid_t pid = ::fork();
  if (pid < 0) return 127;
  if (pid == 0) {
    ::execvp(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  if (::waitpid(pid, &status, 0) < 0) return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

bool ffmpegInstalled() { return runProgram({"sh", "-c", "command -v ffmpeg >/dev/null 2>&1"}) == 0; }

}  // namespace

OutFormat formatOf(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".png") return OutFormat::Png;
  if (ext == ".exr") return OutFormat::Exr;
  throw UsageError("cannot tell the image format of '" + path + "': use a .png or .exr file name");
}

std::vector<int64_t> parseFrames(const std::string& spec) {
  std::vector<std::string> parts(1);
  for (char c : spec) {
    if (c == ':') parts.emplace_back();
    else parts.back() += c;
  }
  if (parts.size() > 3)
    throw UsageError("--frames must be A:B[:STEP] with whole numbers 0 <= A <= B and STEP >= 1, got '" + spec + "'");
  const int64_t first = parseFrameNumber(parts[0], spec);
  const int64_t last = parts.size() > 1 ? parseFrameNumber(parts[1], spec) : first;
  const int64_t step = parts.size() > 2 ? parseFrameNumber(parts[2], spec) : 1;
  if (last < first || step < 1)
    throw UsageError("--frames must be A:B[:STEP] with whole numbers 0 <= A <= B and STEP >= 1, got '" + spec + "'");
  if ((last - first) / step >= 1000000) throw UsageError("--frames '" + spec + "': more than a million frames");
  std::vector<int64_t> frames;
  for (int64_t f = first; f <= last; f += step) frames.push_back(f);
  return frames;
}

bool hasFrameNumber(const std::string& pattern) { return frameConversion(pattern).first != std::string::npos; }

std::string framePath(const std::string& pattern, int64_t frame) {
  const auto [at, length] = frameConversion(pattern);
  std::string out;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (i == at) {
      const std::string spec = pattern.substr(at + 1, length - 2);  // "", "4" or "04"
      const int width = spec.empty() ? 0 : std::stoi(spec);
      const std::string digits = std::to_string(frame);
      const char fill = !spec.empty() && spec[0] == '0' ? '0' : ' ';
      if (int(digits.size()) < width) out += std::string(size_t(width) - digits.size(), fill);
      out += digits;
      i += length - 1;
    } else {
      out += pattern[i];
      if (pattern[i] == '%') ++i;  // %% stands for %
    }
  }
  return out;
}

void writeFrameImage(const std::string& path, const FrameOutput& out, IntegratorKind integrator, const Image& image) {
  if (out.format == OutFormat::Exr)
    writeExr(path, image);
  else
    writePng(path, tonemap(image, integrator, out.exposure));
}

void checkFrameOutputs(const FrameJob& job, const std::vector<int64_t>& frames, const FrameOutput& out) {
  if (frames.size() > 1 && !hasFrameNumber(out.pattern))
    throw UsageError("-o '" + out.pattern + "' has no %d for the frame number, but --frames gives " +
                     std::to_string(frames.size()) + " frames (e.g. -o frame_%04d.png)");
  const std::string first = framePath(out.pattern, frames.front());
  formatOf(first);
  if (out.format == OutFormat::Exr && !exrSupported()) writeExr(first, Image());  // throws the explanation
  for (int64_t f : {frames.front(), frames.back()})
    refuseSamePath("--out", framePath(out.pattern, f), "the scene", job.scene.scene);
  io::checkOutputPath(first);
  if (!out.mp4.empty()) {
    refuseSamePath("--mp4", out.mp4, "the scene", job.scene.scene);
    io::checkOutputPath(out.mp4);
  }
}

std::vector<int64_t> framesToRender(const std::vector<int64_t>& frames, const FrameOutput& out) {
  if (!out.resume) return frames;
  std::vector<int64_t> left;
  for (int64_t f : frames) {
    std::error_code ec;
    const std::string path = framePath(out.pattern, f);
    if (!(std::filesystem::is_regular_file(path, ec) && std::filesystem::file_size(path, ec) > 0)) left.push_back(f);
  }
  return left;
}

void printFrameLine(const FrameRecord& r, const std::string& path, int rank) {
  char who[32] = "";
  if (rank >= 0) std::snprintf(who, sizeof who, "  rank %d", rank);
  std::printf("frame %6lld  scene %8.2f ms  %-27s %8.2f ms  render %7.3f s  %s%s\n", (long long)r.frame,
              r.sceneSeconds * 1e3, r.update.what.c_str(), r.update.seconds * 1e3, r.renderSeconds, path.c_str(), who);
  std::fflush(stdout);
}

void printSummary(const std::vector<FrameRecord>& records, size_t skipped, double wallSeconds, int workers) {
  Spread scene, refit, rebuild, render;
  for (const FrameRecord& r : records) {
    scene.add(r.sceneSeconds);
    (r.update.refitted ? refit : rebuild).add(r.update.seconds);
    render.add(r.renderSeconds);
  }
  std::printf("summary %zu frames rendered, %zu skipped (--resume), %.3f s, %.3f frames/s, %d worker%s\n",
              records.size(), skipped, wallSeconds, wallSeconds > 0 ? double(records.size()) / wallSeconds : 0.0,
              workers, workers == 1 ? "" : "s");
  std::printf("  %-16s %6s  %10s  %10s  %10s  %10s\n", "", "frames", "mean", "min", "max", "total");
  scene.print("scene", 1e3, "ms");
  refit.print("update: refit", 1e3, "ms");
  rebuild.print("update: (re)build", 1e3, "ms");
  render.print("render", 1.0, "s");
  if (refit.n > 0 && rebuild.n > 0)
    std::printf("  refit is %.1fx faster than a (re)build per frame\n", (rebuild.sum / double(rebuild.n)) /
                                                                           std::max(refit.sum / double(refit.n), 1e-12));
  std::fflush(stdout);
}

std::string frameList(std::vector<int64_t> frames) {
  std::sort(frames.begin(), frames.end());
  std::string s;
  for (size_t i = 0; i < frames.size();) {
    size_t j = i;
    while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
    s += (s.empty() ? "" : ", ") + std::to_string(frames[i]) + (j > i ? "-" + std::to_string(frames[j]) : "");
    i = j + 1;
  }
  return s;
}

void writeMp4(const std::vector<int64_t>& frames, const FrameOutput& out, double fps) {
  if (out.mp4.empty()) return;
  auto skip = [](const std::string& why) { std::printf("mp4     skipped: %s\n", why.c_str()); };
  if (out.format != OutFormat::Png) return skip("the frames are EXR (an MP4 is made from PNG frames)");
  for (size_t i = 1; i < frames.size(); ++i)
    if (frames[i] != frames[i - 1] + 1) return skip("the frames are not consecutive (--frames A:B with STEP 1)");
  for (int64_t f : frames)
    if (!std::filesystem::exists(framePath(out.pattern, f))) return skip("frame " + std::to_string(f) + " is missing");
  if (!ffmpegInstalled()) return skip("ffmpeg is not installed");
  const std::filesystem::path target(out.mp4);
  const std::string temp = (target.parent_path() / ("." + target.filename().string() + ".tmp-ffmpeg.mp4")).string();
  char rate[32];
  std::snprintf(rate, sizeof rate, "%.9g", fps);
  const int rc = runProgram({"ffmpeg", "-nostdin", "-y", "-loglevel", "error", "-framerate", rate, "-start_number",
                             std::to_string(frames.front()), "-i", out.pattern, "-frames:v",
                             std::to_string(frames.size()), "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264",
                             "-pix_fmt", "yuv420p", temp});
  std::error_code ec;
  if (rc != 0) {
    std::filesystem::remove(temp, ec);
    throw Error("ffmpeg failed (exit status " + std::to_string(rc) + ") making '" + out.mp4 + "'");
  }
  std::filesystem::rename(temp, target, ec);
  if (ec) throw Error("cannot write '" + out.mp4 + "': " + ec.message());
  std::printf("wrote   %s (%zu frames at %s fps, ffmpeg)\n", out.mp4.c_str(), frames.size(), rate);
}

void runFrameSequence(const FrameJob& job, const std::vector<int64_t>& frames, const FrameOutput& out) {
  checkFrameOutputs(job, frames, out);
  if (mpiWorldSize() > 1) return runFramesMpi(job, frames, out);
  const StopSignalGuard guard;
  SequenceRenderer renderer(job, &gStopRequested);
  for (int64_t f : frames) renderer.checkFrame(f);
  std::printf("frames  %zu of %s (%s, %g fps, %g degree shutter), update %s\n", frames.size(),
              job.scene.scene.c_str(), renderer.timeline().what.c_str(), job.clock.fps,
              job.clock.shutterAngleDegrees, std::string(toString(job.policy)).c_str());
  const std::vector<int64_t> todo = framesToRender(frames, out);
  const auto start = std::chrono::steady_clock::now();
  std::vector<FrameRecord> records;
  std::vector<int64_t> notWritten = todo;
  FrameBar bar(out.progress, todo.size());
  for (int64_t f : todo) {
    if (gStopRequested.load()) break;
    FrameRecord record;
    RenderResult result;
    try {
      result = renderer.render(f, record);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "mbrt: error: frame %lld: %s\nmbrt: frames not written: %s\n", (long long)f, e.what(),
                   frameList(notWritten).c_str());
      throw ExitStatus(1);
    }
    if (!record.complete) break;  // stopped: a partial frame is not written, so --resume renders it
    const std::string path = framePath(out.pattern, f);
    writeFrameImage(path, out, job.options.integrator, result.image);
    notWritten.erase(std::find(notWritten.begin(), notWritten.end(), f));
    printFrameLine(record, path);
    records.push_back(record);
    bar.update(records.size(), record, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  bar.finish();
  printSummary(records, frames.size() - todo.size(), std::chrono::duration<double>(
                                                          std::chrono::steady_clock::now() - start).count(),
               1);
  if (const int sig = gStopSignal.load(); sig != 0) {
    std::fprintf(stderr, "mbrt: stopped by %s: frames not written: %s (rerun with --resume)\n", signalName(sig),
                 notWritten.empty() ? "none" : frameList(notWritten).c_str());
    throw ExitStatus(128 + sig);
  }
  writeMp4(frames, out, job.clock.fps);
}

}  // namespace mbrt::tools
