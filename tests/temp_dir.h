// A folder of its own per test (named after the test and the process), made
// empty on entry and removed on exit, so that tests run in parallel.
#pragma once

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace mbrt::test {

// A folder for the whole test process, named after `prefix` and the process
// id; emptied first of what an earlier process of the same id left behind
// (ids repeat across runs: a stale symlink or FIFO would break a test).
inline std::filesystem::path freshProcessDir(const std::string& prefix) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()));
  std::filesystem::remove_all(path);
  return path;
}

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("mbrt_test_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name), std::ios::binary) << text;
    return file(name);
  }
  std::string fifo(const std::string& name) const {
    EXPECT_EQ(::mkfifo(file(name).c_str(), 0600), 0);
    return file(name);
  }
  // Files whose names start with '.' (what an interrupted atomic write leaves).
  size_t hiddenFiles() const {
    size_t n = 0;
    for (const auto& e : std::filesystem::directory_iterator(path_)) n += e.path().filename().string()[0] == '.' ? 1 : 0;
    return n;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace mbrt::test
