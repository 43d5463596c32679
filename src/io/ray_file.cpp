// Ray and hit files, byte by byte so that the format is little-endian
// whatever the host.
#include "mbrt/io/ray_file.h"

#include <bit>

#include "mbrt/io/file_access.h"
#include "mbrt/scene.h"  // Error

namespace mbrt {
namespace {

void putU32(uint8_t* p, uint32_t v) {
  p[0] = uint8_t(v);
  p[1] = uint8_t(v >> 8);
  p[2] = uint8_t(v >> 16);
  p[3] = uint8_t(v >> 24);
}
uint32_t getU32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
void putF32(uint8_t* p, float v) { putU32(p, std::bit_cast<uint32_t>(v)); }
float getF32(const uint8_t* p) { return std::bit_cast<float>(getU32(p)); }

void checkSize(size_t size, size_t record, std::string_view name, const char* what) {
  if (size % record != 0)
    throw Error(std::string(name) + ": size " + std::to_string(size) + " bytes is not a multiple of " +
                std::to_string(record) + " (one " + what + " is " + std::to_string(record) + " bytes)");
}

}  // namespace

HitRecord toHitRecord(const Hit& hit) {
  if (!hit.valid()) return {};
  return {hit.t, hit.geomID, hit.primID};
}

std::vector<Ray> decodeRays(std::span<const uint8_t> bytes, std::string_view name) {
  checkSize(bytes.size(), kRayRecordBytes, name, "ray");
  std::vector<Ray> rays(bytes.size() / kRayRecordBytes);
  for (size_t i = 0; i < rays.size(); ++i) {
    const uint8_t* p = bytes.data() + i * kRayRecordBytes;
    Ray& r = rays[i];
    r.org = {getF32(p), getF32(p + 4), getF32(p + 8)};
    r.dir = {getF32(p + 12), getF32(p + 16), getF32(p + 20)};
    r.tnear = getF32(p + 24);
    r.tfar = getF32(p + 28);
    r.time = getF32(p + 32);
  }
  return rays;
}

std::vector<HitRecord> decodeHits(std::span<const uint8_t> bytes, std::string_view name) {
  checkSize(bytes.size(), kHitRecordBytes, name, "hit");
  std::vector<HitRecord> hits(bytes.size() / kHitRecordBytes);
  for (size_t i = 0; i < hits.size(); ++i) {
    const uint8_t* p = bytes.data() + i * kHitRecordBytes;
    hits[i] = {getF32(p), getU32(p + 4), getU32(p + 8)};
  }
  return hits;
}

std::vector<uint8_t> encodeRays(std::span<const Ray> rays) {
  std::vector<uint8_t> bytes(rays.size() * kRayRecordBytes);
  for (size_t i = 0; i < rays.size(); ++i) {
    uint8_t* p = bytes.data() + i * kRayRecordBytes;
    const Ray& r = rays[i];
    const float v[9] = {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tnear, r.tfar, r.time};
    for (int k = 0; k < 9; ++k) putF32(p + 4 * k, v[k]);
  }
  return bytes;
}

std::vector<uint8_t> encodeHits(std::span<const HitRecord> hits) {
  std::vector<uint8_t> bytes(hits.size() * kHitRecordBytes);
  for (size_t i = 0; i < hits.size(); ++i) {
    uint8_t* p = bytes.data() + i * kHitRecordBytes;
    putF32(p, hits[i].t);
    putU32(p + 4, hits[i].geomID);
    putU32(p + 8, hits[i].primID);
  }
  return bytes;
}

static std::span<const uint8_t> bytesOf(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

std::vector<Ray> readRays(const std::string& path) { return decodeRays(bytesOf(io::readInputFile(path)), path); }
std::vector<HitRecord> readHits(const std::string& path) {
  return decodeHits(bytesOf(io::readInputFile(path)), path);
}
void writeRays(const std::string& path, std::span<const Ray> rays) { io::writeOutputFile(path, encodeRays(rays)); }
void writeHits(const std::string& path, std::span<const HitRecord> hits) {
  io::writeOutputFile(path, encodeHits(hits));
}

void writeHits(const std::string& path, std::span<const Hit> hits) {
  std::vector<HitRecord> records(hits.size());
  for (size_t i = 0; i < hits.size(); ++i) records[i] = toHitRecord(hits[i]);
  writeHits(path, records);
}

}  // namespace mbrt
