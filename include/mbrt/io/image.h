// A small linear-RGB float image and its PNG writer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace mbrt {

// Linear (not gamma-encoded) RGB.
struct Rgb {
  float r = 0.0f, g = 0.0f, b = 0.0f;
};

// Row-major, top row first.
class Image {
 public:
  Image() = default;
  // Throws Error for negative or huge sizes.
  Image(int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return pixels_.empty(); }

  Rgb& at(int x, int y) { return pixels_[size_t(y) * size_t(width_) + size_t(x)]; }
  const Rgb& at(int x, int y) const { return pixels_[size_t(y) * size_t(width_) + size_t(x)]; }
  std::span<Rgb> pixels() { return pixels_; }
  std::span<const Rgb> pixels() const { return pixels_; }

 private:
  int width_ = 0, height_ = 0;
  std::vector<Rgb> pixels_;
};

// Linear [0,1] to the sRGB transfer curve, as 8 bits (clamped; NaN gives 0).
uint8_t linearToSrgb8(float v);

// Encodes the image as an 8-bit sRGB PNG in memory. Throws Error for an
// empty image.
std::vector<uint8_t> encodePng(const Image& image);

// Writes the image as an 8-bit sRGB PNG. Throws Error naming the path and
// the reason when the file cannot be written.
void writePng(const std::string& path, const Image& image);

// Reads an 8-bit or 16-bit PNG of any colour type as linear RGB (the sRGB
// curve undone; alpha dropped). Throws Error naming the path for a missing,
// non-regular or bad file.
Image readPng(const std::string& path);

// OpenEXR, linear float RGB (channels R, G, B as 32-bit floats). Built in
// when mbrt was configured with OpenEXR (MBRT_WITH_OPENEXR); otherwise
// exrSupported() is false and both calls throw Error saying so.
bool exrSupported();
// Throws Error naming the path and the reason when the file cannot be written.
void writeExr(const std::string& path, const Image& image);
// Reads R, G, B (missing channels are 0). Throws Error for a missing or bad file.
Image readExr(const std::string& path);

}  // namespace mbrt
