// Formatting helpers shared by the bench's report writers.
#pragma once

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "mbrt/bench.h"

namespace mbrt::bench {


inline std::string fmt(double v, int digits = 3) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}
template <class T>
std::string opt(const std::optional<T>& v, int digits = 3) {
  return v ? fmt(double(*v), digits) : "n/a";
}

inline std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (uint8_t(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}
inline std::string jsonNum(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}
template <class T>
std::string jsonOpt(const std::optional<T>& v) {
  return v ? jsonNum(double(*v)) : "null";
}

inline const Result* find(const Report& r, const std::string& scene, const std::string& accel) {
  for (const Result& x : r.results)
    if (x.scene == scene && x.accel == accel) return &x;
  return nullptr;
}

inline std::vector<std::string> sceneOrder(const Report& r) {
  std::vector<std::string> s;
  for (const Result& x : r.results)
    if (s.empty() || s.back() != x.scene) s.push_back(x.scene);
  return s;
}


inline std::string escapeXml(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else out += c;
  }
  return out;
}

}  // namespace mbrt::bench
