// The loader tests' way to look at an error: the message of the
// mbrt::Error that `f` throws, or "(no error)".
#pragma once

#include <functional>
#include <string>

#include "mbrt/scene.h"

namespace mbrt::test {

inline std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace mbrt::test
