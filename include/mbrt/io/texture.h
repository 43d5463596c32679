// Reading the colour textures of materials (PNG and JPEG, through
// stb_image): into mbrt::Texture (scene_description.h).
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "mbrt/io/scene_description.h"

namespace mbrt {

// The largest texture side accepted; beyond it a file is taken as corrupt.
constexpr int kMaxTextureSide = 16384;

// Decodes PNG or JPEG bytes (8-bit sRGB; grey and alpha channels are mapped
// to RGB, alpha dropped). Throws Error naming `name` for data that is not a
// PNG or JPEG, is truncated or corrupt, or is larger than kMaxTextureSide.
Texture decodeTexture(std::span<const uint8_t> bytes, const std::string& name);

// Reads a PNG or JPEG file. Throws Error naming the path when the file is
// missing, not a regular file, or bad as above.
Texture readTexture(const std::string& path);

}  // namespace mbrt
