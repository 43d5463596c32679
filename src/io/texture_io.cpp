// PNG and JPEG textures through stb_image (Debian's libstb-dev), compiled
// here with only those two decoders and private (static) symbols.
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-function"
#endif
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#define STBI_MAX_DIMENSIONS 16384
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <climits>
#include <cstring>
#include <memory>

#include "mbrt/io/file_access.h"
#include "mbrt/io/texture.h"

namespace mbrt {

static_assert(STBI_MAX_DIMENSIONS == kMaxTextureSide);

Texture decodeTexture(std::span<const uint8_t> bytes, const std::string& name) {
  if (bytes.empty()) throw Error(name + ": the texture is empty");
  if (bytes.size() > size_t(INT_MAX)) throw Error(name + ": the texture is larger than 2 GiB");
  const int len = int(bytes.size());
  int w = 0, h = 0, channels = 0;
  if (!stbi_info_from_memory(bytes.data(), len, &w, &h, &channels))
    throw Error(name + ": not a PNG or JPEG image, or a truncated or corrupt one (" + std::string(stbi_failure_reason()) +
                ")");
  if (w < 1 || h < 1 || w > kMaxTextureSide || h > kMaxTextureSide)
    throw Error(name + ": texture size " + std::to_string(w) + " x " + std::to_string(h) + " is outside [1, " +
                std::to_string(kMaxTextureSide) + "]");
  std::unique_ptr<stbi_uc, void (*)(void*)> pixels(stbi_load_from_memory(bytes.data(), len, &w, &h, &channels, 3),
                                                   stbi_image_free);
  if (!pixels) throw Error(name + ": corrupt or truncated image (" + std::string(stbi_failure_reason()) + ")");
  Texture t;
  t.name = name;
  t.width = w;
  t.height = h;
  t.rgb.assign(pixels.get(), pixels.get() + size_t(w) * size_t(h) * 3);
  return t;
}

Texture readTexture(const std::string& path) {
  const std::string bytes = io::readInputFile(path, uint64_t(1) << 30);
  return decodeTexture({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}, path);
}

}  // namespace mbrt
