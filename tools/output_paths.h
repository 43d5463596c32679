// Output files of the subcommands: never one of the inputs, never each other.
#pragma once

#include <filesystem>
#include <string>

#include "scene_loading.h"

namespace mbrt::tools {

// True when `a` and `b` name the same file (through symlinks and relative
// parts), whether or not it exists yet.
inline bool samePath(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return false;
  std::error_code ec1, ec2;
  if (std::filesystem::exists(a, ec1) && std::filesystem::exists(b, ec2))
    return std::filesystem::equivalent(a, b, ec1);
  return std::filesystem::weakly_canonical(a, ec1) == std::filesystem::weakly_canonical(b, ec2);
}

// Throws UsageError when the output `path` (named by `option`) is the file
// `other` (named by `otherOption`) too.
inline void refuseSamePath(const std::string& option, const std::string& path, const std::string& otherOption,
                           const std::string& other) {
  if (samePath(path, other))
    throw UsageError(option + " and " + otherOption + " name the same file '" + path + "': writing " + option +
                     " would overwrite it");
}

}  // namespace mbrt::tools
