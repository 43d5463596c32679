// Ray and hit files: the exchange format of `mbrt trace`, the benchmark and
// the fuzzers. Little-endian, packed, no header.
//   rays: 9 float32 per ray: org.xyz dir.xyz tnear tfar time   (36 bytes)
//   hits: float32 t (+inf on a miss), uint32 geomID, uint32 primID
//         (0xFFFFFFFF for both on a miss)                      (12 bytes)
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mbrt/ray.h"

namespace mbrt {

constexpr size_t kRayRecordBytes = 36;
constexpr size_t kHitRecordBytes = 12;

// What a hit file keeps of a Hit.
struct HitRecord {
  float t = kInf;
  uint32_t geomID = kInvalidId;
  uint32_t primID = kInvalidId;

  bool valid() const { return geomID != kInvalidId; }
  bool operator==(const HitRecord&) const = default;
};

// A miss becomes {+inf, kInvalidId, kInvalidId}.
HitRecord toHitRecord(const Hit& hit);

// Decoding from memory; `name` is used in messages. Throws Error when the
// size is not a multiple of the record size. Rays keep the default mask.
std::vector<Ray> decodeRays(std::span<const uint8_t> bytes, std::string_view name = "rays");
std::vector<HitRecord> decodeHits(std::span<const uint8_t> bytes, std::string_view name = "hits");
std::vector<uint8_t> encodeRays(std::span<const Ray> rays);
std::vector<uint8_t> encodeHits(std::span<const HitRecord> hits);

// Files. Throw Error naming the path and the reason on any failure.
std::vector<Ray> readRays(const std::string& path);
std::vector<HitRecord> readHits(const std::string& path);
void writeRays(const std::string& path, std::span<const Ray> rays);
void writeHits(const std::string& path, std::span<const HitRecord> hits);
void writeHits(const std::string& path, std::span<const Hit> hits);

}  // namespace mbrt
