// Guarded file access (mbrt/io/file_access.h) and the loaders on hostile
// files: FIFOs, devices and folders are refused at once, inputs over the
// size limit are refused, outputs replace their file only when complete.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "error_of.h"
#include "temp_dir.h"
#include "mbrt/io/file_access.h"
#include "mbrt/io/image.h"
#include "mbrt/io/mesh_files.h"
#include "mbrt/io/loaders.h"
#include "mbrt/io/ray_file.h"

using namespace mbrt;
using mbrt::test::errorOf;
using mbrt::test::TempDir;
namespace fs = std::filesystem;

namespace {

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Sets the largest file this process may write for its lifetime (EFBIG
// beyond, with SIGXFSZ ignored): a write that fails half way.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    previousHandler_ = std::signal(SIGXFSZ, SIG_IGN);
    ::getrlimit(RLIMIT_FSIZE, &previous_);
    rlimit limit = previous_;
    limit.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &previous_);
    std::signal(SIGXFSZ, previousHandler_);
  }

 private:
  rlimit previous_{};
  void (*previousHandler_)(int) = SIG_DFL;
};

Image noise(int w, int h) {
  Image image(w, h);
  uint32_t state = 12345;
  for (Rgb& c : image.pixels()) {
    state = state * 1664525u + 1013904223u;
    c = {float(state >> 8 & 255) / 255.0f, float(state >> 16 & 255) / 255.0f, float(state >> 24) / 255.0f};
  }
  return image;
}

}  // namespace

TEST(FileAccess, InputsMustBeRegularFiles) {
  TempDir dir;
  EXPECT_TRUE(contains(errorOf([&] { io::readInputFile(dir.fifo("f.obj")); }), "is a FIFO"));
  EXPECT_TRUE(contains(errorOf([] { io::readInputFile("/dev/zero"); }), "is a device"));
  EXPECT_TRUE(contains(errorOf([&] { io::readInputFile(dir.file("")); }), "is a folder"));
  EXPECT_TRUE(contains(errorOf([&] { io::readInputFile(dir.file("none")); }), "cannot open"));
  EXPECT_EQ(io::readInputFile(dir.write("a.txt", "hello")), "hello");
}

TEST(FileAccess, InputsOverTheLimitAreRefused) {
  TempDir dir;
  const std::string path = dir.write("big.obj", std::string(100, 'x'));
  const std::string msg = errorOf([&] { io::readInputFile(path, 99); });
  EXPECT_TRUE(contains(msg, "has 100 bytes, more than the limit of 99 bytes")) << msg;
  EXPECT_EQ(io::readInputFile(path, 100).size(), 100u);
  EXPECT_GE(io::kMaxInputFileBytes, uint64_t(1) << 30);  // real scenes and ray files fit
}

TEST(FileAccess, FilesReportingSizeZeroAreReadToTheirEnd) {
  // /proc files are regular, report size 0 and have content.
  const std::string status = io::readInputFile("/proc/self/status");
  EXPECT_NE(status.find("Name:"), std::string::npos);
  const std::string msg = errorOf([] { io::readInputFile("/proc/self/status", 16); });
  EXPECT_TRUE(contains(msg, "more than the limit of 16 bytes")) << msg;
}

TEST(FileAccess, EveryLoaderRefusesAFifoWithoutWaiting) {
  // Without the check each would block in open() or read() (no writer).
  TempDir dir;
  for (const char* name : {"f.obj", "f.ply", "f.json", "f.gltf", "f.glb"}) {
    const std::string path = dir.fifo(name);
    const std::string msg = errorOf([&] { loadSceneSpec(path); });
    EXPECT_TRUE(contains(msg, "not a regular file") || contains(msg, "is a FIFO")) << name << ": " << msg;
  }
  EXPECT_TRUE(contains(errorOf([&] { readRays(dir.fifo("r.bin")); }), "is a FIFO"));
  EXPECT_TRUE(contains(errorOf([&] { readHits(dir.fifo("h.bin")); }), "is a FIFO"));
  EXPECT_TRUE(contains(errorOf([&] { readPng(dir.fifo("i.png")); }), "is a FIFO"));
}

TEST(FileAccess, DevZeroAsASceneIsRefusedAtOnce) {
  // Read as a file, /dev/zero never ends: memory would run out.
  TempDir dir;
  fs::create_symlink("/dev/zero", dir.file("zero.obj"));
  fs::create_symlink("/dev/zero", dir.file("zero.ply"));
  EXPECT_TRUE(contains(errorOf([&] { loadSceneSpec(dir.file("zero.obj")); }), "is a device"));
  EXPECT_TRUE(contains(errorOf([&] { loadSceneSpec(dir.file("zero.ply")); }), "is a device"));
  EXPECT_TRUE(contains(errorOf([] { readRays("/dev/zero"); }), "is a device"));
}

TEST(FileAccess, AFailedWriteKeepsTheOldFile) {
  TempDir dir;
  const std::string png = dir.write("old.png", "old picture");
  const std::string rays = dir.write("old.bin", "old rays");
  {
    const FileSizeLimit limit(512);
    const std::string msg = errorOf([&] { writePng(png, noise(64, 64)); });
    EXPECT_TRUE(contains(msg, "cannot write '" + png + "': File too large")) << msg;
    EXPECT_TRUE(contains(errorOf([&] { writeRays(rays, std::vector<Ray>(100)); }), "File too large"));
  }
  EXPECT_EQ(contents(png), "old picture");
  EXPECT_EQ(contents(rays), "old rays");
  EXPECT_EQ(dir.hiddenFiles(), 0u);  // no temporary file left
  writePng(png, noise(64, 64));       // without the limit: replaced
  EXPECT_EQ(readPng(png).width(), 64);
}

TEST(FileAccess, OutputsGoThroughSymlinks) {
  // A failed write must leave the link and its target as they were.
  TempDir dir;
  dir.write("target.png", "old");
  fs::create_symlink("target.png", dir.file("link.png"));
  {
    const FileSizeLimit limit(512);
    EXPECT_NE(errorOf([&] { writePng(dir.file("link.png"), noise(64, 64)); }), "(no error)");
  }
  EXPECT_TRUE(fs::is_symlink(dir.file("link.png")));
  EXPECT_EQ(contents(dir.file("target.png")), "old");
  writePng(dir.file("link.png"), noise(8, 4));
  EXPECT_TRUE(fs::is_symlink(dir.file("link.png")));
  EXPECT_EQ(readPng(dir.file("target.png")).height(), 4);
  EXPECT_EQ(dir.hiddenFiles(), 0u);
}

TEST(FileAccess, UnwritableOutputsAreFoundBeforeTheWork) {
  TempDir dir;
  EXPECT_TRUE(contains(errorOf([] { io::checkOutputPath("/proc/x.png"); }), "cannot create a file in '/proc'"));
  EXPECT_TRUE(contains(errorOf([&] { io::checkOutputPath(dir.file("")); }), "is a folder"));
  fs::create_directory(dir.file("sub.png"));
  EXPECT_TRUE(contains(errorOf([&] { io::checkOutputPath(dir.file("sub.png")); }), "is a folder"));
  EXPECT_TRUE(contains(errorOf([] { io::checkOutputPath("/dev/full"); }), "is a device"));
  fs::create_symlink("/dev/full", dir.file("full.png"));
  EXPECT_TRUE(contains(errorOf([&] { io::checkOutputPath(dir.file("full.png")); }), "'/dev/full' is a device"));
  EXPECT_TRUE(contains(errorOf([&] { io::checkOutputPath(dir.file("none/x.png")); }), "no folder"));
  EXPECT_TRUE(contains(errorOf([] { io::checkOutputPath(""); }), "empty"));
  io::checkOutputPath(dir.file("fine.png"));
  EXPECT_FALSE(fs::exists(dir.file("fine.png")));  // the check creates nothing
  EXPECT_EQ(dir.hiddenFiles(), 0u);
}

TEST(FileAccess, ReplacedOutputsKeepTheirMode) {
  TempDir dir;
  const std::string path = dir.write("a.bin", "x");
  fs::permissions(path, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  writeRays(path, std::vector<Ray>(1));
  EXPECT_EQ(fs::status(path).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  EXPECT_EQ(fs::file_size(path), kRayRecordBytes);
}

TEST(PngReader, ReadsWhatTheWriterWrote) {
  TempDir dir;
  Image image(5, 3);
  image.at(0, 0) = {1, 0, 0};
  image.at(4, 2) = {0, 0.5f, 1};
  writePng(dir.file("a.png"), image);
  const Image back = readPng(dir.file("a.png"));
  ASSERT_EQ(back.width(), 5);
  ASSERT_EQ(back.height(), 3);
  EXPECT_NEAR(back.at(0, 0).r, 1.0f, 1e-6f);
  EXPECT_NEAR(back.at(4, 2).g, 0.5f, 0.01f);  // 8-bit sRGB quantization
  EXPECT_EQ(back.at(2, 1).b, 0.0f);
  EXPECT_TRUE(contains(errorOf([&] { readPng(dir.write("bad.png", "not a png")); }), "as PNG"));
}

// ---- loader options that would otherwise be ignored or overflow ------------

TEST(ProceduralMotion, StepsAreCapped) {
  // One step per 10 degrees: rotate:2e8 would need 2e7 copies of the mesh.
  EXPECT_EQ(parseProceduralMotion("rotate:10230").steps, kMaxProceduralMotionSteps);
  const std::string msg = errorOf([] { parseProceduralMotion("rotate:2e8"); });
  EXPECT_TRUE(contains(msg, "needs 20000001 steps")) << msg;
  EXPECT_TRUE(contains(msg, "limit of 1024")) << msg;
  EXPECT_NE(errorOf([] { parseProceduralMotion("rotate:10231"); }), "(no error)");
  EXPECT_NE(errorOf([] { parseProceduralMotion("rotate:-1e30"); }), "(no error)");
}

TEST(ProceduralMotion, RefusedForInputsThatAreNotStaticMeshes) {
  TempDir dir;
  LoadOptions o;
  o.motion = "rotate:90";
  for (const std::string spec : {std::string("translate"), dir.file("a.gltf"), dir.file("a.glb"), dir.file("a.json"),
                                 dir.file("keys_*.obj")}) {
    const std::string msg = errorOf([&] { loadSceneSpec(spec, o); });
    EXPECT_TRUE(contains(msg, "applies to a static .obj or .ply mesh only")) << spec << ": " << msg;
  }
}

TEST(SceneFile, ColoursMustBeNonNegative) {
  TempDir dir;
  dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const auto msgOf = [&](const std::string& extra) {
    const std::string path = dir.write("s.json", R"({"objects": [{"file": "tri.obj")" + extra + "}");
    return errorOf([&] { loadSceneFile(path); });
  };
  EXPECT_TRUE(contains(msgOf(R"(}], "lights": [{"direction": [0, -1, 0], "radiance": [1, -2, 1]}])"),
                       "'light radiance' values must be in [0, 1e6]"));
  EXPECT_TRUE(contains(msgOf(R"(}], "sky": [0, -0.1, 0])"), "'sky' values"));
  EXPECT_TRUE(contains(msgOf(R"(, "diffuse": [0.5, 0.5, 2]}])"), "diffuse' values must be in [0, 1]"));
  EXPECT_TRUE(contains(msgOf(R"(}], "lights": [{"direction": [0, -1, 0], "radiance": [1e39, 1, 1]}])"),
                       "radiance"));
  EXPECT_EQ(msgOf(R"(, "diffuse": [0.5, 0.5, 1]}], "sky": [0.1, 0.2, 0.3])"), "(no error)");
}

TEST(SceneFile, StepsAreCapped) {
  TempDir dir;
  dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string path = dir.write("s.json", R"({"steps": 100000000, "objects": [{"file": "tri.obj"}]})");
  const std::string msg = errorOf([&] { loadSceneFile(path); });
  EXPECT_TRUE(contains(msg, "'steps' must be at most 1024")) << msg;
  dir.write("s.json", R"({"steps": 1024, "objects": [{"file": "tri.obj"}]})");
  EXPECT_EQ(errorOf([&] { loadSceneFile(path); }), "(no error)");
}
