// Checks the files the `mbrt` command writes, for the CLI tests
// (tests/cli_tests.cmake, run by tests/cli/run_cli_test.sh):
//   mbrt_cli_check image FILE W H [nonblack]  a PNG or EXR that decodes to W x H
//                                             (and has a pixel that is not black)
//   mbrt_cli_check same A B                   two non-empty files with the same bytes
//   mbrt_cli_check close A B                  two images of one size where at most 0.1% of the pixels
//                                             (and at least one) differ by more than 1/255 (the
//                                             render tests' ties tolerance)
//   mbrt_cli_check rays FILE N                N rays that decode and encode back to the same bytes
//   mbrt_cli_check hits FILE N                N hit records: hits with t > 0, misses as written for a miss
// Exit 0 when the check holds, 1 with the reason on stderr otherwise.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "mbrt/io/image.h"
#include "mbrt/io/ray_file.h"
#include "mbrt/scene.h"

namespace {

std::vector<uint8_t> bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw mbrt::Error("cannot open '" + path + "'");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

size_t count(const char* text) {
  char* end = nullptr;
  const unsigned long long v = std::strtoull(text, &end, 10);
  if (!*text || *end) throw mbrt::Error(std::string("bad number '") + text + "'");
  return size_t(v);
}

int fail(const std::string& why) {
  std::fprintf(stderr, "mbrt_cli_check: %s\n", why.c_str());
  return 1;
}

int checkImage(const std::string& path, size_t w, size_t h, bool nonBlack) {
  const std::string ext = std::filesystem::path(path).extension().string();
  const mbrt::Image image = ext == ".exr" ? mbrt::readExr(path) : mbrt::readPng(path);
  if (size_t(image.width()) != w || size_t(image.height()) != h)
    return fail(path + ": " + std::to_string(image.width()) + "x" + std::to_string(image.height()) + ", expected " +
                std::to_string(w) + "x" + std::to_string(h));
  if (nonBlack) {
    bool any = false;
    for (const mbrt::Rgb& c : image.pixels()) any = any || c.r > 0.0f || c.g > 0.0f || c.b > 0.0f;
    if (!any) return fail(path + ": every pixel is black");
  }
  std::printf("%s: %zux%zu\n", path.c_str(), w, h);
  return 0;
}

int checkSame(const std::string& a, const std::string& b) {
  const auto x = bytesOf(a), y = bytesOf(b);
  if (x.empty()) return fail(a + " is empty");
  if (x != y) return fail(a + " (" + std::to_string(x.size()) + " bytes) and " + b + " (" +
                          std::to_string(y.size()) + " bytes) differ");
  std::printf("%s and %s: the same %zu bytes\n", a.c_str(), b.c_str(), x.size());
  return 0;
}

int checkClose(const std::string& a, const std::string& b) {
  auto read = [](const std::string& path) {
    return std::filesystem::path(path).extension() == ".exr" ? mbrt::readExr(path) : mbrt::readPng(path);
  };
  const mbrt::Image x = read(a), y = read(b);
  if (x.width() != y.width() || x.height() != y.height()) return fail(a + " and " + b + " differ in size");
  size_t differing = 0;
  for (size_t i = 0; i < x.pixels().size(); ++i) {
    const mbrt::Rgb &p = x.pixels()[i], &q = y.pixels()[i];
    if (std::max({std::fabs(p.r - q.r), std::fabs(p.g - q.g), std::fabs(p.b - q.b)}) > 1.0f / 255.0f) ++differing;
  }
  const size_t allowed = std::max<size_t>(1, x.pixels().size() / 1000);
  if (differing > allowed)
    return fail(a + " and " + b + ": " + std::to_string(differing) + " pixels differ (at most " +
                std::to_string(allowed) + " may)");
  std::printf("%s and %s: %zu of %zu pixels differ\n", a.c_str(), b.c_str(), differing, x.pixels().size());
  return 0;
}

int checkRays(const std::string& path, size_t n) {
  const std::vector<mbrt::Ray> rays = mbrt::readRays(path);
  if (rays.size() != n) return fail(path + ": " + std::to_string(rays.size()) + " rays, expected " + std::to_string(n));
  if (mbrt::encodeRays(rays) != bytesOf(path)) return fail(path + ": the rays do not encode back to the file's bytes");
  for (size_t i = 0; i < rays.size(); ++i)
    if (!mbrt::isValidRay(rays[i])) return fail(path + ": ray " + std::to_string(i) + " is not a valid ray");
  std::printf("%s: %zu valid rays, round trip exact\n", path.c_str(), n);
  return 0;
}

int checkHits(const std::string& path, size_t n) {
  const std::vector<mbrt::HitRecord> hits = mbrt::readHits(path);
  if (hits.size() != n) return fail(path + ": " + std::to_string(hits.size()) + " hits, expected " + std::to_string(n));
  size_t found = 0;
  for (size_t i = 0; i < hits.size(); ++i) {
    const mbrt::HitRecord& h = hits[i];
    if (h.valid()) {
      if (!(h.t > 0.0f && std::isfinite(h.t)) || h.primID == mbrt::kInvalidId)
        return fail(path + ": record " + std::to_string(i) + " is a hit without a finite t > 0 or a primitive");
      ++found;
    } else if (!(h == mbrt::HitRecord{})) {
      return fail(path + ": record " + std::to_string(i) + " is a miss not written as {+inf, -1, -1}");
    }
  }
  std::printf("%s: %zu records, %zu hits\n", path.c_str(), n, found);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "image" && (argc == 5 || (argc == 6 && std::string(argv[5]) == "nonblack")))
      return checkImage(argv[2], count(argv[3]), count(argv[4]), argc == 6);
    if (mode == "same" && argc == 4) return checkSame(argv[2], argv[3]);
    if (mode == "close" && argc == 4) return checkClose(argv[2], argv[3]);
    if (mode == "rays" && argc == 4) return checkRays(argv[2], count(argv[3]));
    if (mode == "hits" && argc == 4) return checkHits(argv[2], count(argv[3]));
    return fail("usage: mbrt_cli_check image FILE W H [nonblack] | same A B | close A B | rays FILE N | hits FILE N");
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}
