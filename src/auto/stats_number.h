// Figures in auto's stats lines.
#pragma once

#include <cstdio>
#include <string>

namespace mbrt::detail {

// Three significant digits.
inline std::string statsNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace mbrt::detail
