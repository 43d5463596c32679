// PNG output through libpng, encoded in memory and then written in one go
// (mbrt/io/file_access.h: a temporary file renamed into place), so that every I/O
// failure is reported with the path and errno's reason.
#include <png.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <limits>

#include "mbrt/io/file_access.h"
#include "mbrt/io/image.h"
#include "mbrt/scene.h"  // Error

namespace mbrt {

Image::Image(int width, int height) {
  if (width <= 0 || height <= 0 || width > (1 << 16) || height > (1 << 16))
    throw Error("image size must be in [1, 65536] x [1, 65536], got " + std::to_string(width) + " x " +
                std::to_string(height));
  width_ = width;
  height_ = height;
  pixels_.resize(size_t(width) * size_t(height));
}

uint8_t linearToSrgb8(float v) {
  if (!(v > 0.0f)) return 0;  // also NaN
  if (v >= 1.0f) return 255;
  const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return uint8_t(std::lround(std::clamp(s, 0.0f, 1.0f) * 255.0f));
}

namespace {

struct PngBuffer {
  std::vector<uint8_t> bytes;
};

struct PngErrorState {
  char message[256] = "unknown libpng error";
};

void pngWrite(png_structp png, png_bytep data, png_size_t length) {
  auto* buffer = static_cast<PngBuffer*>(png_get_io_ptr(png));
  buffer->bytes.insert(buffer->bytes.end(), data, data + length);
}

void pngFlush(png_structp) {}

[[noreturn]] void pngError(png_structp png, png_const_charp message) {
  auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png));
  std::snprintf(state->message, sizeof(state->message), "%s", message ? message : "libpng error");
  png_longjmp(png, 1);
}

void pngWarning(png_structp, png_const_charp) {}

// Everything with a destructor lives outside the setjmp frame.
bool encodeRows(const std::vector<png_bytep>& rows, int width, int height, PngBuffer& out,
                PngErrorState& err) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &err, pngError, pngWarning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, &out, pngWrite, pngFlush);
  png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  png_write_image(png, const_cast<png_bytepp>(rows.data()));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

std::vector<uint8_t> encodePng(const Image& image) {
  if (image.empty()) throw Error("cannot write an empty image as PNG");
  const int w = image.width(), h = image.height();
  std::vector<uint8_t> pixels(size_t(w) * size_t(h) * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Rgb& c = image.at(x, y);
      uint8_t* p = &pixels[(size_t(y) * size_t(w) + size_t(x)) * 3];
      p[0] = linearToSrgb8(c.r);
      p[1] = linearToSrgb8(c.g);
      p[2] = linearToSrgb8(c.b);
    }
  std::vector<png_bytep> rows(static_cast<size_t>(h));
  for (int y = 0; y < h; ++y) rows[size_t(y)] = &pixels[size_t(y) * size_t(w) * 3];
  PngBuffer out;
  PngErrorState err;
  if (!encodeRows(rows, w, h, out, err)) throw Error(std::string("PNG encoding failed: ") + err.message);
  return std::move(out.bytes);
}

void writePng(const std::string& path, const Image& image) {
  const std::vector<uint8_t> bytes = encodePng(image);
  io::writeOutputFile(path, bytes);
}

Image readPng(const std::string& path) {
  const std::string bytes = io::readInputFile(path);
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size()))
    throw Error("cannot read '" + path + "' as PNG: " + png.message);
  png.format = PNG_FORMAT_RGB;
  std::vector<uint8_t> pixels(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, pixels.data(), 0, nullptr)) {
    const std::string message = png.message;
    png_image_free(&png);
    throw Error("cannot read '" + path + "' as PNG: " + message);
  }
  Image image(int(png.width), int(png.height));
  auto linear = [](uint8_t v) {
    const float s = float(v) / 255.0f;
    return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
  };
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const uint8_t* p = &pixels[(size_t(y) * size_t(image.width()) + size_t(x)) * 3];
      image.at(x, y) = {linear(p[0]), linear(p[1]), linear(p[2])};
    }
  return image;
}

}  // namespace mbrt
