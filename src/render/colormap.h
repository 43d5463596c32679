// Heat-map colours: a perceptually ordered map from black through purple,
// red and orange to pale yellow, a colour bar along the bottom of the image
// with its scale written in a tiny bitmap font.
#pragma once

#include <span>
#include <string>

#include "mbrt/io/image.h"

namespace mbrt::renderer {

// x in [0,1] (clamped) to linear RGB.
Rgb heatColor(float x);

// Height in pixels of the colour bar drawn for an image of this height
// (0 when the image is too small for one).
int colorBarHeight(int imageHeight);

// Colours the image from per-pixel values (row-major) scaled by 1/scale;
// rows from height - barHeight down hold the bar labelled "0", the middle
// and `scale`.
void applyHeatMap(Image& image, std::span<const float> values, float scale, int barHeight);

// Writes text (digits, '.', ' ', '-') at (x, y) with pixel size `scale`.
void drawText(Image& image, int x, int y, const std::string& text, int scale, Rgb color);
int textWidth(const std::string& text, int scale);

}  // namespace mbrt::renderer
