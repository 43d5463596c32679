// The files a glTF reads: the glTF itself and the external buffers its
// "uri"s name. Only regular files are read (never a device such as
// /dev/zero, a FIFO or a directory); an external buffer must lie inside the
// glTF's folder (a relative path without "..") and have the size of one of
// the declared buffer byteLengths, checked before a byte is read.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace mbrt::gltf {

// A regular file's bytes; throws Error naming the path otherwise.
std::vector<unsigned char> readRegularFile(const std::string& path);

// What the file callbacks allow: the folder buffers are resolved against
// (as tinygltf joins it) and the buffers' declared byteLengths.
struct ExternalBufferRules {
  std::string folder;
  std::vector<uint64_t> declaredSizes;
};

// The rules for a glTF (.gltf JSON or .glb) read into `bytes` from `path`.
ExternalBufferRules externalBufferRules(const std::string& path, const std::vector<unsigned char>& bytes, bool glb);

// What tinygltf's file callbacks do (gltf_document.cpp installs them): an
// external buffer at `path` (the folder joined with the URI) is read into
// `out` when `rules` allow it, else false with the reason in `err`.
bool readExternalBuffer(const ExternalBufferRules& rules, const std::string& path, std::vector<unsigned char>& out,
                        std::string& err);
bool fileExists(const std::string& path);

}  // namespace mbrt::gltf
