// Guarded file access for every reader and writer of mbrt's inputs and
// outputs (scene files, ray and hit files, images).
//
// Inputs are read only from regular files and only up to a size limit, so
// that a FIFO, a device such as /dev/zero or a folder given as a scene or a
// ray file is refused at once instead of blocking or filling memory.
//
// Outputs are written to a temporary file in the destination's folder and
// renamed into place only when every byte is written, so that a failed
// write (disk full, I/O error, interruption) leaves any old file, and any
// symlink pointing at it, as it was. A symlink is written through: the file
// it points to is replaced, the link stays.
#pragma once

#include <cstdint>
#include <istream>
#include <streambuf>
#include <span>
#include <string>
#include <string_view>

namespace mbrt::io {

// The largest input file mbrt reads (4 GiB): beyond it a file is refused
// with a message instead of being read into memory.
constexpr uint64_t kMaxInputFileBytes = uint64_t(4) << 30;

// The bytes of the regular file `path`. Throws Error naming the path when it
// cannot be opened, is not a regular file (FIFO, device, folder, socket) or
// is larger than `limit` bytes. Opening never waits (O_NONBLOCK), and at most
// the size found when opening is read (files that report size 0, as in
// /proc, are read to their end within the limit).
std::string readInputFile(const std::string& path, uint64_t limit = kMaxInputFileBytes);

// An istream over bytes in memory (readInputFile's), without a copy. The
// bytes must outlive the stream.
class MemoryInput : private std::streambuf, public std::istream {
 public:
  explicit MemoryInput(std::string_view bytes) : std::istream(static_cast<std::streambuf*>(this)) {
    char* p = const_cast<char*>(bytes.data());
    setg(p, p, p + bytes.size());
  }
};

// Throws Error naming the path unless an output can be written there: it
// names a file (not a folder, not a device), its folder exists and a new file
// can be created in it. Run before long work so that a bad output path fails
// in a second, not after the work.
void checkOutputPath(const std::string& path);

// Writes `bytes` to a temporary file beside `path` and renames it onto
// `path` (through a symlink: onto the file it names). Throws Error naming
// the path and the reason; the temporary file is removed on failure.
void writeOutputFile(const std::string& path, std::span<const uint8_t> bytes);
void writeOutputFile(const std::string& path, std::string_view text);

// For writers that need a file name of their own (OpenEXR): a temporary
// file beside the destination, renamed onto it by commit(), removed by the
// destructor when not committed.
class PendingOutput {
 public:
  explicit PendingOutput(const std::string& path);
  ~PendingOutput();
  PendingOutput(const PendingOutput&) = delete;
  PendingOutput& operator=(const PendingOutput&) = delete;

  const std::string& tempPath() const { return temp_; }
  void commit();

 private:
  std::string target_;  // the destination, symlinks resolved
  std::string path_;    // as given, for messages
  std::string temp_;
  bool committed_ = false;
};

}  // namespace mbrt::io
