#include "render/colormap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace mbrt::renderer {
namespace {

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

struct Stop {
  float x, r, g, b;  // sRGB
};
constexpr std::array<Stop, 7> kStops{{{0.00f, 0.00f, 0.00f, 0.02f},
                                      {0.15f, 0.16f, 0.04f, 0.35f},
                                      {0.35f, 0.50f, 0.08f, 0.45f},
                                      {0.55f, 0.82f, 0.23f, 0.30f},
                                      {0.75f, 0.98f, 0.53f, 0.10f},
                                      {0.90f, 0.98f, 0.82f, 0.25f},
                                      {1.00f, 0.99f, 1.00f, 0.75f}}};

// 3x5 glyphs, rows top to bottom, 3 bits each (MSB left).
int glyphRows(char c, int row) {
  static const char* kDigits[10] = {"111101101101111", "010110010010111", "111001111100111", "111001111001111",
                                    "101101111001001", "111100111001111", "111100111101111", "111001001001001",
                                    "111101111101111", "111101111001111"};
  const char* g = nullptr;
  if (c >= '0' && c <= '9') g = kDigits[c - '0'];
  else if (c == '.') g = "000000000000010";
  else if (c == '-') g = "000000111000000";
  else if (c == 'k') g = "100101110101101";
  if (!g) return 0;
  int bits = 0;
  for (int i = 0; i < 3; ++i) bits = (bits << 1) | (g[row * 3 + i] == '1');
  return bits;
}

std::string formatValue(float v) {
  char buf[32];
  if (v >= 10000.0f) std::snprintf(buf, sizeof buf, "%.0fk", v / 1000.0f);
  else if (v >= 10.0f || v == std::floor(v)) std::snprintf(buf, sizeof buf, "%.0f", v);
  else std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

}  // namespace

Rgb heatColor(float x) {
  x = std::isfinite(x) ? std::clamp(x, 0.0f, 1.0f) : 1.0f;
  size_t i = 1;
  while (i + 1 < kStops.size() && x > kStops[i].x) ++i;
  const Stop &a = kStops[i - 1], &b = kStops[i];
  const float f = (x - a.x) / (b.x - a.x);
  return {srgbToLinear(a.r + (b.r - a.r) * f), srgbToLinear(a.g + (b.g - a.g) * f),
          srgbToLinear(a.b + (b.b - a.b) * f)};
}

int colorBarHeight(int imageHeight) {
  if (imageHeight < 24) return 0;
  return std::clamp(imageHeight / 10, 12, 48);
}

int textWidth(const std::string& text, int scale) { return int(text.size()) * 4 * scale - scale; }

void drawText(Image& image, int x0, int y0, const std::string& text, int scale, Rgb color) {
  for (size_t c = 0; c < text.size(); ++c)
    for (int row = 0; row < 5; ++row) {
      const int bits = glyphRows(text[c], row);
      for (int col = 0; col < 3; ++col) {
        if (!(bits & (4 >> col))) continue;
        for (int dy = 0; dy < scale; ++dy)
          for (int dx = 0; dx < scale; ++dx) {
            const int x = x0 + (int(c) * 4 + col) * scale + dx, y = y0 + row * scale + dy;
            if (x >= 0 && y >= 0 && x < image.width() && y < image.height()) image.at(x, y) = color;
          }
      }
    }
}

void applyHeatMap(Image& image, std::span<const float> values, float scale, int barHeight) {
  const int w = image.width(), h = image.height();
  const float inv = scale > 0.0f ? 1.0f / scale : 0.0f;
  const int mapRows = h - barHeight;
  for (int y = 0; y < mapRows; ++y)
    for (int x = 0; x < w; ++x) image.at(x, y) = heatColor(values[size_t(y) * size_t(w) + size_t(x)] * inv);
  if (barHeight <= 0) return;
  // Bar layout: a dark label strip (digits of size `s`) above the gradient.
  const int s = std::max(1, (barHeight / 2 - 2) / 5);
  const int labelRows = 5 * s + 2;
  const Rgb dark{0.0f, 0.0f, 0.0f}, light{0.9f, 0.9f, 0.9f};
  for (int y = mapRows; y < h; ++y)
    for (int x = 0; x < w; ++x)
      image.at(x, y) = y < mapRows + labelRows ? dark : heatColor(w > 1 ? float(x) / float(w - 1) : 0.0f);
  const int ty = mapRows + 1;
  const std::string lo = "0", mid = formatValue(0.5f * scale), hi = formatValue(scale);
  drawText(image, 1, ty, lo, s, light);
  if (textWidth(lo, s) + textWidth(mid, s) + textWidth(hi, s) + 8 * s < w)
    drawText(image, (w - textWidth(mid, s)) / 2, ty, mid, s, light);
  drawText(image, w - 1 - textWidth(hi, s), ty, hi, s, light);
}

}  // namespace mbrt::renderer
