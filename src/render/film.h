// The film: per-pixel results (colours, or work counts for heat maps) and
// the step from them to a picture (heat colour map and bar, tonemapping).
#pragma once

#include <vector>

#include "mbrt/io/image.h"
#include "mbrt/render.h"

namespace mbrt::renderer {

class Film {
 public:
  Film(int width, int height, bool heat);

  void setColor(int x, int y, Vec3f c) { colors_.at(x, y) = {c.x, c.y, c.z}; }
  void setValue(int x, int y, float v) { values_[size_t(y) * size_t(width_) + size_t(x)] = v; }

  // Colours (linear), or for heat maps the colour-mapped values with a bar of
  // colorBarHeight() rows appended below when `colorBar`. `scale` = 0 picks
  // the 99th percentile of the values; the result's heat fields are filled.
  void develop(RenderResult& out, float scale, bool colorBar) const;

 private:
  int width_, height_;
  bool heat_;
  Image colors_;
  std::vector<float> values_;
};

}  // namespace mbrt::renderer
