#include "render/film.h"

#include <algorithm>
#include <cmath>

#include "mbrt/scene.h"
#include "render/colormap.h"

namespace mbrt::renderer {

Film::Film(int width, int height, bool heat)
    : width_(width), height_(height), heat_(heat), colors_(heat ? Image() : Image(width, height)) {
  if (heat) values_.assign(size_t(width) * size_t(height), 0.0f);
}

void Film::develop(RenderResult& out, float scale, bool colorBar) const {
  if (!heat_) {
    out.image = colors_;
    return;
  }
  double sum = 0.0;
  float maxValue = 0.0f;
  for (float v : values_) {
    sum += v;
    maxValue = std::max(maxValue, v);
  }
  if (!(scale > 0.0f)) {
    std::vector<float> sorted(values_);
    const size_t k = std::min(sorted.size() - 1, size_t(0.99 * double(sorted.size())));
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(k), sorted.end());
    scale = sorted[k] > 0.0f ? sorted[k] : (maxValue > 0.0f ? maxValue : 1.0f);
  }
  const int bar = colorBar ? colorBarHeight(height_) : 0;
  out.image = Image(width_, height_ + bar);
  applyHeatMap(out.image, values_, scale, bar);
  out.heat = values_;
  out.heatScale = scale;
  out.heatMean = values_.empty() ? 0.0f : float(sum / double(values_.size()));
  out.heatMaxValue = maxValue;
}

}  // namespace mbrt::renderer

namespace mbrt {

Image heatImage(std::span<const float> heat, int width, int height, float scale, bool colorBar) {
  if (heat.size() != size_t(width) * size_t(height)) throw Error("heatImage: values do not match the size");
  const int bar = colorBar ? renderer::colorBarHeight(height) : 0;
  Image image(width, height + bar);
  renderer::applyHeatMap(image, heat, scale, bar);
  return image;
}

Image tonemap(const Image& linear, IntegratorKind kind, float exposureEv) {
  if (kind != IntegratorKind::Ao && kind != IntegratorKind::Path) return linear;
  // A filmic curve (Narkowicz's fit of the ACES reference rendering transform):
  // highlights roll off instead of clipping.
  auto curve = [](float x) {
    if (!(x > 0.0f)) return 0.0f;
    return std::min(1.0f, (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f));
  };
  const float gain = std::exp2(exposureEv);
  Image out(linear.width(), linear.height());
  for (int y = 0; y < linear.height(); ++y)
    for (int x = 0; x < linear.width(); ++x) {
      const Rgb& c = linear.at(x, y);
      out.at(x, y) = {curve(gain * c.r), curve(gain * c.g), curve(gain * c.b)};
    }
  return out;
}

}  // namespace mbrt
