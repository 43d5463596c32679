// Pinhole and thin-lens camera over the shutter interval, with moving keys.
#include <cmath>
#include <numbers>

#include "mbrt/render.h"

namespace mbrt {
namespace {

CameraSpec frameBounds(const Box3f& box) {
  CameraSpec cam;
  if (box.empty()) return cam;
  const Vec3f c = box.center();
  const float radius = std::max(0.5f * length(box.size()), 1e-6f);
  const float half = 0.5f * cam.verticalFovDegrees * std::numbers::pi_v<float> / 180.0f;
  cam.target = c;
  cam.eye = c + normalize(Vec3f(0.35f, 0.3f, 1.0f)) * (1.1f * radius / std::sin(half));
  return cam;
}

// Concentric mapping of the unit square onto the unit disk (Shirley & Chiu).
void sampleDisk(float u1, float u2, float& x, float& y) {
  const float a = 2.0f * u1 - 1.0f, b = 2.0f * u2 - 1.0f;
  if (a == 0.0f && b == 0.0f) {
    x = y = 0.0f;
    return;
  }
  constexpr float kQuarterPi = std::numbers::pi_v<float> / 4.0f;
  float r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = kQuarterPi * (b / a);
  } else {
    r = b;
    phi = 2.0f * kQuarterPi - kQuarterPi * (a / b);
  }
  x = r * std::cos(phi);
  y = r * std::sin(phi);
}

}  // namespace

RenderCamera::RenderCamera(const SceneDescription& scene, int width, int height, float shutterOpen,
                           float shutterClose)
    : keys_(scene.camera.keys),
      aperture_(scene.camera.apertureRadius),
      focusDistance_(scene.camera.focusDistance),
      aspect_(float(width) / float(height)),
      width_(float(width)),
      height_(float(height)),
      open_(shutterOpen),
      close_(shutterClose) {
  if (width < 1 || height < 1) throw Error("render: image size must be at least 1x1");
  if (!(shutterOpen >= 0.0f && shutterClose <= 1.0f && shutterOpen <= shutterClose))
    throw Error("render: shutter [" + std::to_string(shutterOpen) + ", " + std::to_string(shutterClose) +
                "] must lie within [0,1] with open <= close");
  if (!(aperture_ >= 0.0f) || !std::isfinite(aperture_)) throw Error("render: camera aperture must be >= 0");
  if (!(focusDistance_ >= 0.0f) || !std::isfinite(focusDistance_))
    throw Error("render: camera focus distance must be >= 0");
  if (keys_.empty()) keys_.push_back(frameBounds(sceneBounds(*scene.scene)));
  for (const CameraSpec& k : keys_) {
    const Vec3f w = k.eye - k.target;
    if (!isFinite(k.eye) || !isFinite(k.target) || !isFinite(k.up) || dot(w, w) <= 0.0f ||
        dot(cross(k.up, w), cross(k.up, w)) <= 0.0f || !(k.verticalFovDegrees > 0.0f && k.verticalFovDegrees < 180.0f))
      throw Error("render: degenerate camera (eye on the target, up along the view, or a bad field of view)");
  }
}

CameraSpec RenderCamera::viewAt(float time) const {
  CameraSpec k = keys_.front();
  if (keys_.size() > 1) {
    const float x = std::clamp(time, 0.0f, 1.0f) * float(keys_.size() - 1);
    const size_t i = std::min(size_t(x), keys_.size() - 2);
    const float f = x - float(i);
    const CameraSpec &a = keys_[i], &b = keys_[i + 1];
    k.eye = lerp(a.eye, b.eye, f);
    k.target = lerp(a.target, b.target, f);
    k.up = lerp(a.up, b.up, f);
    k.verticalFovDegrees = a.verticalFovDegrees + (b.verticalFovDegrees - a.verticalFovDegrees) * f;
  }
  return k;
}

float RenderCamera::focusOf(const CameraSpec& view) const {
  return focusDistance_ > 0.0f ? focusDistance_ : length(view.eye - view.target);
}

Ray RenderCamera::generate(float px, float py, float lu, float lv, float u) const {
  const float time = shutterTime(u);
  const CameraSpec view = viewAt(time);
  const PinholeCamera pinhole(view, aspect_);
  const float x = px / width_, y = py / height_;
  if (!(aperture_ > 0.0f)) return pinhole.ray(x, y, time);
  // Thin lens: every lens point sees the same point on the plane of focus.
  float dx, dy;
  sampleDisk(lu, lv, dx, dy);
  const Vec3f lens = pinhole.right() * (dx * aperture_) + pinhole.up() * (dy * aperture_);
  const Vec3f focal = pinhole.direction(x, y) * focusOf(view);
  Ray r;
  r.org = pinhole.eye() + lens;
  r.dir = normalize(focal - lens);
  r.tnear = 0.0f;
  r.tfar = kInf;
  r.time = time;
  return r;
}

}  // namespace mbrt
