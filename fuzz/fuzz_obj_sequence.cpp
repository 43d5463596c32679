// libFuzzer target: an OBJ keyframe sequence. The input is cut into up to 4
// files at lines "#--key--" (the seeds use that), written to a scratch folder
// and loaded with loadObjSequence.
#include <string_view>
#include <vector>

#include "fuzz_common.h"
#include "mbrt/io/mesh_files.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view all(reinterpret_cast<const char*>(data), size);
  constexpr std::string_view kSep = "#--key--";
  std::vector<std::string> files;
  size_t pos = 0;
  while (files.size() < 4) {
    const size_t next = files.size() == 3 ? std::string_view::npos : all.find(kSep, pos);
    const std::string_view part = all.substr(pos, next == std::string_view::npos ? all.size() - pos : next - pos);
    const std::string name = "key_" + std::to_string(files.size()) + ".obj";
    files.push_back(mbrt::fuzz::writeScratch(name, reinterpret_cast<const uint8_t*>(part.data()), part.size()));
    if (next == std::string_view::npos) break;
    pos = next + kSep.size();
  }
  try {
    auto scene = mbrt::loadObjSequence(files);
    mbrt::fuzz::exercise(*scene);
  } catch (const mbrt::Error&) {
  }
  return 0;
}
