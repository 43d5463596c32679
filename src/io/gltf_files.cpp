// Guarded file access for glTF: regular files only, external buffers inside
// the glTF's folder and of a declared size.
#include "io/gltf_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "mbrt/io/file_access.h"
#include "mbrt/scene.h"

namespace mbrt::gltf {
namespace {

class FileHandle {
 public:
  explicit FileHandle(const std::string& path) : fd_(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)) {}
  ~FileHandle() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileHandle(const FileHandle&) = delete;
  FileHandle& operator=(const FileHandle&) = delete;
  int fd() const { return fd_; }

 private:
  int fd_;
};

// Reads `path` when it is a regular file (and, with `allowedSizes`, of one of
// those sizes); else false with the reason in `err`. The checks look at the
// opened file, so that the file read is the file checked.
bool readIfRegular(const std::string& path, const std::vector<uint64_t>* allowedSizes, std::vector<unsigned char>& out,
                   std::string& err) {
  const FileHandle file(path);  // O_NONBLOCK: opening a FIFO must not wait for a writer
  struct stat st {};
  if (file.fd() < 0 || ::fstat(file.fd(), &st) != 0) {
    err = "cannot open '" + path + "': " + std::strerror(errno);
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    err = "'" + path + "' is not a regular file";
    return false;
  }
  const uint64_t size = uint64_t(st.st_size);
  if (allowedSizes && std::find(allowedSizes->begin(), allowedSizes->end(), size) == allowedSizes->end()) {
    err = "'" + path + "' has " + std::to_string(size) + " bytes, the size of no declared buffer (byteLength)";
    return false;
  }
  if (size > io::kMaxInputFileBytes) {
    err = "'" + path + "' has " + std::to_string(size) + " bytes, more than the limit of " +
          std::to_string(io::kMaxInputFileBytes) + " for an input file";
    return false;
  }
  out.resize(size_t(size));
  size_t done = 0;
  while (done < out.size()) {
    const ssize_t n = ::read(file.fd(), out.data() + done, out.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      err = "cannot read '" + path + "'";
      return false;
    }
    done += size_t(n);
  }
  return true;
}

// The buffer's path relative to the glTF's folder, or "" when `path` is not
// of the form folder/relative (tinygltf also tries ./uri) or leaves it.
std::string relativeToFolder(const std::string& path, const std::string& folder) {
  std::string prefix = folder;
  if (!prefix.empty() && prefix.back() != '/') prefix += '/';
  if (path.compare(0, prefix.size(), prefix) != 0) return "";
  const std::filesystem::path rel(path.substr(prefix.size()));
  if (rel.empty() || rel.is_absolute()) return "";
  for (const auto& part : rel)
    if (part == "..") return "";
  return rel.string();
}

// The JSON text of a .gltf, or of a .glb's first chunk ("" when absent).
std::string_view jsonText(const std::vector<unsigned char>& bytes, bool glb) {
  const char* text = reinterpret_cast<const char*>(bytes.data());
  if (!glb) return {text, bytes.size()};
  if (bytes.size() < 20) return {};
  uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  return {text + 20, std::min<size_t>(length, bytes.size() - 20)};
}

}  // namespace

std::vector<unsigned char> readRegularFile(const std::string& path) {
  std::vector<unsigned char> bytes;
  std::string err;
  if (!readIfRegular(path, nullptr, bytes, err)) throw Error(err);
  return bytes;
}

ExternalBufferRules externalBufferRules(const std::string& path, const std::vector<unsigned char>& bytes, bool glb) {
  ExternalBufferRules rules;
  const size_t slash = path.find_last_of('/');
  rules.folder = slash == std::string::npos ? "" : path.substr(0, slash);  // as tinygltf's GetBaseDir
  const std::string_view text = jsonText(bytes, glb);
  const nlohmann::json doc = nlohmann::json::parse(text.begin(), text.end(), nullptr, false);
  if (!doc.is_object()) return rules;  // tinygltf reports what is wrong
  const auto buffers = doc.find("buffers");
  if (buffers == doc.end() || !buffers->is_array()) return rules;
  for (const nlohmann::json& b : *buffers) {
    if (!b.is_object()) continue;
    const auto length = b.find("byteLength");
    if (length != b.end() && length->is_number_unsigned()) rules.declaredSizes.push_back(length->get<uint64_t>());
  }
  return rules;
}

bool readExternalBuffer(const ExternalBufferRules& rules, const std::string& path, std::vector<unsigned char>& out,
                        std::string& err) {
  if (relativeToFolder(path, rules.folder).empty()) {
    err = "'" + path + "' is outside the glTF's folder (buffer URIs must be relative, without \"..\")";
    return false;
  }
  return readIfRegular(path, &rules.declaredSizes, out, err);
}

bool fileExists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;  // what it is is checked when read
}

}  // namespace mbrt::gltf
