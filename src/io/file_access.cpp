#include "mbrt/io/file_access.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <algorithm>
#include <filesystem>
#include <vector>

#include "mbrt/scene.h"  // Error

namespace mbrt::io {
namespace fs = std::filesystem;

namespace {

std::string reason(int e) { return std::strerror(e); }

std::string humanSize(uint64_t bytes) {
  char buf[64];
  if (bytes >= (uint64_t(1) << 30)) std::snprintf(buf, sizeof buf, "%.1f GiB", double(bytes) / double(1 << 30));
  else if (bytes >= (uint64_t(1) << 20)) std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / double(1 << 20));
  else std::snprintf(buf, sizeof buf, "%llu bytes", (unsigned long long)bytes);
  return buf;
}

// What is wrong with `st` as a file to read or replace, or "" when it is a
// regular file.
std::string notRegular(const struct stat& st) {
  if (S_ISREG(st.st_mode)) return "";
  if (S_ISDIR(st.st_mode)) return "is a folder";
  if (S_ISFIFO(st.st_mode)) return "is a FIFO (named pipe), not a regular file";
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) return "is a device, not a regular file";
  if (S_ISSOCK(st.st_mode)) return "is a socket, not a regular file";
  return "is not a regular file";
}

// The file an output path names: itself, or the end of its symlink chain.
fs::path outputTarget(const std::string& path) {
  if (path.empty()) throw Error("the output file name is empty");
  std::error_code ec;
  if (!fs::is_symlink(path, ec)) return fs::path(path);
  const fs::path target = fs::weakly_canonical(path, ec);
  if (ec) throw Error("cannot write '" + path + "': cannot follow the symlink: " + ec.message());
  return target;
}

fs::path folderOf(const fs::path& target) {
  const fs::path parent = target.parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

// Refuses a destination that exists and is not a regular file, or a missing
// folder.
void checkTarget(const std::string& path, const fs::path& target) {
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0) {
    const std::string what = notRegular(st);
    if (!what.empty())
      throw Error("cannot write '" + path + "': '" + target.string() + "' " + what);
  }
  const fs::path folder = folderOf(target);
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw Error("cannot write '" + path + "': no folder '" + folder.string() + "'");
}

// Creates an empty temporary file in `folder`; returns its descriptor.
int makeTemp(const std::string& path, const fs::path& target, std::string& tempPath) {
  std::string pattern = (folderOf(target) / ("." + target.filename().string() + ".tmp-XXXXXX")).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  const int fd = ::mkstemp(name.data());
  if (fd < 0)
    throw Error("cannot write '" + path + "': cannot create a file in '" + folderOf(target).string() +
                "': " + reason(errno));
  tempPath = name.data();
  return fd;
}

// The mode a new output gets: the old file's when there is one, else
// 0666 less the umask (what open(O_CREAT) would give).
mode_t outputMode(const fs::path& target) {
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0) return st.st_mode & 07777;
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return 0666 & ~mask;
}

}  // namespace

std::string readInputFile(const std::string& path, uint64_t limit) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer (it is refused below).
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw Error("cannot open '" + path + "': " + reason(errno));
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw Error("cannot open '" + path + "': " + reason(errno));
  if (const std::string what = notRegular(st); !what.empty()) throw Error("cannot read '" + path + "': it " + what);
  const uint64_t size = uint64_t(st.st_size);
  if (size > limit)
    throw Error("cannot read '" + path + "': it has " + humanSize(size) + ", more than the limit of " +
                humanSize(limit) + " for an input file");
  // Files of /proc and /sys report size 0 and have content: read those to
  // their end, within the limit; others only up to the size found.
  const bool sizeUnknown = size == 0;
  // Up to one byte over the limit, which tells a file that is too large.
  const uint64_t most = sizeUnknown ? std::min<uint64_t>(limit, uint64_t(SIZE_MAX) - 1) + 1 : size;
  std::string bytes(size_t(sizeUnknown ? std::min<uint64_t>(most, 1 << 16) : size), '\0');
  size_t done = 0;
  for (;;) {
    if (done == bytes.size()) {
      if (bytes.size() >= most) break;
      bytes.resize(size_t(std::min<uint64_t>(uint64_t(bytes.size()) * 2, most)));
    }
    const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw Error("cannot read '" + path + "': " + reason(errno));
    if (n == 0) break;  // the end (or the file shrank while read: what is there)
    done += size_t(n);
  }
  if (sizeUnknown && done > limit)
    throw Error("cannot read '" + path + "': it has more than the limit of " + humanSize(limit) +
                " for an input file");
  bytes.resize(done);
  return bytes;
}

void checkOutputPath(const std::string& path) {
  const fs::path target = outputTarget(path);
  checkTarget(path, target);
  if (::access(target.c_str(), F_OK) == 0 && ::access(target.c_str(), W_OK) != 0)
    throw Error("cannot write '" + path + "': " + reason(errno));
  std::string temp;
  const int fd = makeTemp(path, target, temp);
  ::close(fd);
  ::unlink(temp.c_str());
}

PendingOutput::PendingOutput(const std::string& path) : path_(path) {
  const fs::path target = outputTarget(path);
  checkTarget(path, target);
  target_ = target.string();
  const int fd = makeTemp(path, target, temp_);
  ::fchmod(fd, outputMode(target));
  ::close(fd);
}

PendingOutput::~PendingOutput() {
  if (!committed_) ::unlink(temp_.c_str());
}

void PendingOutput::commit() {
  if (::rename(temp_.c_str(), target_.c_str()) != 0)
    throw Error("cannot write '" + path_ + "': cannot rename the finished file into place: " + reason(errno));
  committed_ = true;
}

void writeOutputFile(const std::string& path, std::span<const uint8_t> bytes) {
  PendingOutput out(path);
  const int fd = ::open(out.tempPath().c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0) throw Error("cannot write '" + path + "': " + reason(errno));
  size_t done = 0;
  int error = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = n < 0 ? errno : EIO;
      break;
    }
    done += size_t(n);
  }
  if (error == 0 && ::fsync(fd) != 0 && errno != EINVAL) error = errno;
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) throw Error("cannot write '" + path + "': " + reason(error));
  out.commit();
}

void writeOutputFile(const std::string& path, std::string_view text) {
  writeOutputFile(path, std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
}

}  // namespace mbrt::io
