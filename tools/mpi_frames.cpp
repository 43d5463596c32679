#include "mpi_frames.h"

#include <cstdlib>

#ifdef MBRT_MPI
#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

#include "stop_signal.h"
#endif

namespace mbrt::tools {
namespace {

bool startedByMpirun() { return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE"); }

#ifdef MBRT_MPI
bool gMpiStarted = false;
#endif

}  // namespace

#ifndef MBRT_MPI

MpiSession::MpiSession(int&, char**&) {}
MpiSession::~MpiSession() = default;
int mpiWorldSize() { return 1; }
int mpiRank() { return 0; }
void runFramesMpi(const FrameJob&, const std::vector<int64_t>&, const FrameOutput&) {
  throw Error("this mbrt was built without MPI (configure with -DMBRT_MPI=ON)");
}
RenderResult renderPictureMpi(const SceneDescription&, const Accel&, const RenderOptions&, tbb::task_arena&,
                              const std::atomic<bool>*) {
  throw Error("this mbrt was built without MPI (configure with -DMBRT_MPI=ON)");
}

#else

MpiSession::MpiSession(int& argc, char**& argv) {
  if (!startedByMpirun()) return;
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);  // MPI from the main thread only
  gMpiStarted = true;
}

MpiSession::~MpiSession() {
  if (gMpiStarted) MPI_Finalize();
}

int mpiWorldSize() {
  int n = 1;
  if (gMpiStarted) MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

int mpiRank() {
  int r = 0;
  if (gMpiStarted) MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

namespace {

constexpr int kReportTag = 1, kPixelsTag = 2, kAssignTag = 3;

// What a rank sends rank 0 after a work item (a frame, a row of tiles) and,
// with status Asking, when it first asks for work; the pixels follow when
// the status is Rendered.
struct Report {
  enum Status : int32_t { Asking = 0, Rendered = 1, Failed = 2, Stopped = 3 };
  int64_t frame = -1;  // the item
  int32_t status = Asking;
  int32_t width = 0, height = 0, refitted = 0;
  double scene = 0.0, update = 0.0, render = 0.0;
  uint64_t rays = 0;
  char updateKind[160] = {};  // as MBRTAccelUpdate::what
  char error[256] = {};
};

void copyText(char* to, size_t size, const std::string& from) {
  std::strncpy(to, from.c_str(), size - 1);
  to[size - 1] = '\0';
}

FrameRecord recordOf(const Report& r) {
  FrameRecord rec;
  rec.frame = r.frame;
  rec.sceneSeconds = r.scene;
  rec.update.seconds = r.update;
  rec.renderSeconds = r.render;
  rec.rays = r.rays;
  rec.update.refitted = r.refitted != 0;
  rec.update.what = r.updateKind;
  return rec;
}

// Renders one frame into a report (never throws: a failure is reported).
Report renderInto(SequenceRenderer& renderer, int64_t frame, Image& image) {
  Report r;
  r.frame = frame;
  try {
    FrameRecord rec;
    RenderResult result = renderer.render(frame, rec);
    r.status = rec.complete ? Report::Rendered : Report::Stopped;
    r.width = result.image.width();
    r.height = result.image.height();
    r.refitted = rec.update.refitted;
    r.scene = rec.sceneSeconds;
    r.update = rec.update.seconds;
    r.render = rec.renderSeconds;
    r.rays = rec.rays;
    copyText(r.updateKind, sizeof r.updateKind, rec.update.what);
    image = std::move(result.image);
  } catch (const std::exception& e) {
    r.status = Report::Failed;
    copyText(r.error, sizeof r.error, e.what());
  }
  return r;
}

using Work = std::function<Report(int64_t item, Image& out)>;
using Finish = std::function<void(const Report&, const Image&, int rank)>;

// Rank 0's queue of work items, shared by its MPI loop and its own thread.
class WorkQueue {
 public:
  explicit WorkQueue(const std::vector<int64_t>& items) : queue_(items.begin(), items.end()) {}
  int64_t next(bool stopGiving) {
    std::lock_guard lock(mutex_);
    if (stopGiving || gStopRequested.load() || queue_.empty()) return -1;
    const int64_t f = queue_.front();
    queue_.pop_front();
    return f;
  }

 private:
  std::mutex mutex_;
  std::deque<int64_t> queue_;
};

// Rank 0's main thread: answers the ranks' reports with their next item
// (-1: none left, or the rank failed) until every rank and the local thread
// are done.
void serveRanks(WorkQueue& queue, const Finish& finish, const std::atomic<bool>& localDone) {
  const int ranks = mpiWorldSize();
  std::vector<bool> failedRank(size_t(ranks), false);
  int active = ranks - 1;
  while (active > 0 || !localDone) {
    int flag = 0;
    MPI_Status st;
    MPI_Iprobe(MPI_ANY_SOURCE, kReportTag, MPI_COMM_WORLD, &flag, &st);
    if (!flag) {
      std::this_thread::sleep_for(std::chrono::microseconds(500));
      continue;
    }
    Report r;
    const int src = st.MPI_SOURCE;
    MPI_Recv(&r, sizeof r, MPI_BYTE, src, kReportTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    Image image;
    if (r.status == Report::Rendered) {
      image = Image(r.width, r.height);
      MPI_Recv(image.pixels().data(), int(image.pixels().size() * 3), MPI_FLOAT, src, kPixelsTag, MPI_COMM_WORLD,
               MPI_STATUS_IGNORE);
    }
    if (r.status == Report::Failed) failedRank[size_t(src)] = true;
    if (r.status != Report::Asking) finish(r, image, src);
    const int64_t f = queue.next(failedRank[size_t(src)] || r.status == Report::Stopped);
    MPI_Send(&f, 1, MPI_INT64_T, src, kAssignTag, MPI_COMM_WORLD);
    if (f < 0) --active;
  }
}

// Rank 0: the items over every rank, itself included (a second thread).
// `finish` is called for every report, one at a time.
void runOnRanks(const std::vector<int64_t>& items, const Work& work, const Finish& finish) {
  WorkQueue queue(items);
  std::mutex finishing;
  const Finish serial = [&](const Report& r, const Image& image, int rank) {
    std::lock_guard lock(finishing);
    finish(r, image, rank);
  };
  std::atomic<bool> localDone{false};
  std::thread local([&] {
    for (int64_t f = queue.next(false); f >= 0; f = queue.next(false)) {
      Image image;
      const Report r = work(f, image);
      serial(r, image, 0);
      if (r.status != Report::Rendered) break;
    }
    localDone = true;
  });
  serveRanks(queue, serial, localDone);
  local.join();
}

// The other ranks: report, get the next item, until there is none.
void workForRankZero(const Work& work) {
  Report r;
  Image image;
  for (;;) {
    MPI_Send(&r, sizeof r, MPI_BYTE, 0, kReportTag, MPI_COMM_WORLD);
    if (r.status == Report::Rendered)
      MPI_Send(image.pixels().data(), int(image.pixels().size() * 3), MPI_FLOAT, 0, kPixelsTag, MPI_COMM_WORLD);
    int64_t f = -1;
    MPI_Recv(&f, 1, MPI_INT64_T, 0, kAssignTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (f < 0) return;
    r = work(f, image);
  }
}

// Every rank checks and loads (`setup`); all go on only when all could.
void startTogether(const std::function<void()>& setup) {
  std::string error;
  int code = 1;
  try {
    setup();
  } catch (const UsageError& e) {
    error = e.what();
    code = 2;
  } catch (const std::exception& e) {
    error = e.what();
  }
  int ok = error.empty() ? 1 : 0, allOk = 0;
  MPI_Allreduce(&ok, &allOk, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (allOk) return;
  if (!ok) std::fprintf(stderr, "mbrt: error: rank %d: %s\n", mpiRank(), error.c_str());
  if (mpiRank() == 0) std::fprintf(stderr, "mbrt: a rank could not start: nothing rendered\n");
  throw ExitStatus(ok ? 1 : code);
}

}  // namespace

void runFramesMpi(const FrameJob& job, const std::vector<int64_t>& frames, const FrameOutput& out) {
  const StopSignalGuard guard;
  std::unique_ptr<SequenceRenderer> renderer;
  startTogether([&] {
    checkFrameOutputs(job, frames, out);
    renderer = std::make_unique<SequenceRenderer>(job, &gStopRequested);
    for (int64_t f : frames) renderer->checkFrame(f);
  });
  const Work work = [&](int64_t f, Image& image) { return renderInto(*renderer, f, image); };
  if (mpiRank() != 0) {
    workForRankZero(work);
    throw ExitStatus(0);
  }
  const std::vector<int64_t> todo = framesToRender(frames, out);
  std::printf("frames  %zu of %s (%s) over %d MPI ranks\n", frames.size(), job.scene.scene.c_str(),
              renderer->timeline().what.c_str(), mpiWorldSize());
  std::fflush(stdout);
  std::vector<int64_t> notWritten = todo;
  std::vector<FrameRecord> records;
  bool failed = false;
  const auto start = std::chrono::steady_clock::now();
  runOnRanks(todo, work, [&](const Report& r, const Image& image, int rank) {
    if (r.status == Report::Failed) {
      std::fprintf(stderr, "mbrt: error: rank %d, frame %lld: %s\n", rank, (long long)r.frame, r.error);
      failed = true;
    }
    if (r.status != Report::Rendered) return;
    const std::string path = framePath(out.pattern, r.frame);
    writeFrameImage(path, out, job.options.integrator, image);
    notWritten.erase(std::find(notWritten.begin(), notWritten.end(), r.frame));
    records.push_back(recordOf(r));
    printFrameLine(records.back(), path, rank);
  });
  printSummary(records, frames.size() - todo.size(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), mpiWorldSize());
  if (!notWritten.empty()) {
    std::fprintf(stderr, "mbrt: frames not written: %s (rerun with --resume)\n", frameList(notWritten).c_str());
    const int sig = gStopSignal.load();
    throw ExitStatus(sig != 0 && !failed ? 128 + sig : 1);
  }
  writeMp4(frames, out, job.clock.fps);
}

RenderResult renderPictureMpi(const SceneDescription& scene, const Accel& accel, const RenderOptions& options,
                              tbb::task_arena& arena, const std::atomic<bool>* cancel) {
  if (isHeatMap(options.integrator))
    throw UsageError("heat maps are made by one process (their colour scale is the whole picture's): not under mpirun");
  const int tilesX = (options.width + options.tileSize - 1) / options.tileSize;
  const int tilesY = (options.height + options.tileSize - 1) / options.tileSize;
  // One work item per row of tiles; the reply is that band of the picture.
  const Work work = [&](int64_t row, Image& band) {
    Report r;
    r.frame = row;
    try {
      RenderOptions o = options;
      o.tileBegin = size_t(row) * size_t(tilesX);
      o.tileEnd = o.tileBegin + size_t(tilesX);
      RenderResult part;
      arena.execute([&] { part = render(scene, accel, o, cancel); });
      const int y0 = int(row) * options.tileSize, y1 = std::min(options.height, y0 + options.tileSize);
      band = Image(options.width, y1 - y0);
      for (int y = y0; y < y1; ++y)
        for (int x = 0; x < options.width; ++x) band.at(x, y - y0) = part.image.at(x, y);
      r.status = part.complete ? Report::Rendered : Report::Stopped;
      r.width = band.width();
      r.height = band.height();
      r.rays = part.rays;
    } catch (const std::exception& e) {
      r.status = Report::Failed;
      copyText(r.error, sizeof r.error, e.what());
    }
    return r;
  };
  RenderResult out;
  if (mpiRank() != 0) {
    workForRankZero(work);
    return out;
  }
  const auto start = std::chrono::steady_clock::now();
  out.image = Image(options.width, options.height);
  out.tilesTotal = size_t(tilesX) * size_t(tilesY);
  std::vector<int64_t> rows(static_cast<size_t>(tilesY));
  for (int i = 0; i < tilesY; ++i) rows[size_t(i)] = i;
  std::string failure;
  runOnRanks(rows, work, [&](const Report& r, const Image& band, int rank) {
    if (r.status == Report::Failed && failure.empty())
      failure = "rank " + std::to_string(rank) + ", tile row " + std::to_string(r.frame) + ": " + r.error;
    if (r.status != Report::Rendered) return;
    const int y0 = int(r.frame) * options.tileSize;
    for (int y = 0; y < band.height(); ++y)
      for (int x = 0; x < band.width(); ++x) out.image.at(x, y0 + y) = band.at(x, y);
    out.tilesDone += size_t(tilesX);
    out.rays += r.rays;
  });
  if (!failure.empty()) throw Error(failure);
  out.complete = out.tilesDone == out.tilesTotal;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

#endif

}  // namespace mbrt::tools
