// rtcNewDevice's config string: comma- or space-separated tokens
// `name=value` (Embree's own: threads, verbose, isa, set_affinity,
// start_threads, frequency_level, ... are accepted; threads and verbose
// are used) and mbrt's: mbrt.kind=NAME.
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "device.h"
#include "errors.h"

namespace mbrt::embree_api {
namespace {

std::string kindList() {
  std::string list;
  for (AccelKind k : availableAccelKinds()) list += (list.empty() ? "" : ", ") + std::string(toString(k));
  return list;
}

AccelKind kindNamed(std::string_view name, const char* source) {
  const auto kind = parseAccelKind(name);
  bool available = false;
  for (AccelKind k : availableAccelKinds()) available |= kind && k == *kind;
  if (!available)
    fail(RTC_ERROR_INVALID_ARGUMENT, std::string(source) + ": unknown mbrt kind '" + std::string(name) +
                                         "' (this library has: " + kindList() + ")");
  return *kind;
}

int integerValue(std::string_view token, std::string_view value) {
  const std::string v(value);
  char* end = nullptr;
  const long n = std::strtol(v.c_str(), &end, 10);
  if (v.empty() || *end != '\0' || n < 0 || n > 1 << 20)
    fail(RTC_ERROR_UNKNOWN, "config token '" + std::string(token) + "' needs a non-negative integer");  // Embree's code
  return int(n);
}

std::vector<std::string_view> tokens(std::string_view s) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ',' || s[i] == ' ' || s[i] == '\t' || s[i] == '\n')) ++i;
    size_t j = i;
    while (j < s.size() && s[j] != ',' && s[j] != ' ' && s[j] != '\t' && s[j] != '\n') ++j;
    if (j > i) out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

}  // namespace

DeviceConfig parseDeviceConfig(const char* config, const char* environmentKind) {
  DeviceConfig c;
  bool kindGiven = false;
  for (std::string_view token : tokens(config ? config : "")) {
    const size_t eq = token.find('=');
    const std::string_view name = token.substr(0, eq);
    const std::string_view value = eq == std::string_view::npos ? std::string_view() : token.substr(eq + 1);
    if (name == "mbrt.kind") {
      c.kind = kindNamed(value, "config mbrt.kind");
      kindGiven = true;
    } else if (name.substr(0, 5) == "mbrt.") {
      fail(RTC_ERROR_INVALID_ARGUMENT, "unknown config token '" + std::string(token) + "' (mbrt's token: mbrt.kind=NAME)");
    } else if (name == "threads") {
      c.threads = integerValue(token, value);
    } else if (name == "verbose") {
      c.verbose = integerValue(token, value);
    }
    // Embree's other tokens tune its own threads and ISA: accepted, no effect.
  }
  if (!kindGiven && environmentKind && *environmentKind) c.kind = kindNamed(environmentKind, "MBRT_EMBREE_KIND");
  return c;
}

}  // namespace mbrt::embree_api
