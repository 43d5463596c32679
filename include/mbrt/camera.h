// The one pinhole camera: a view (CameraSpec) and the ray through a point of
// its image plane. `mbrt trace --generate`, the benchmark's camera rays and
// the renderer (which adds a thin lens and moving keys) all use it.
#pragma once

#include <cmath>
#include <numbers>

#include "mbrt/math.h"
#include "mbrt/ray.h"

namespace mbrt {

// A pinhole camera looking at a point.
struct CameraSpec {
  Vec3f eye{0, 0, 5};
  Vec3f target{0, 0, 0};
  Vec3f up{0, 1, 0};
  float verticalFovDegrees = 40.0f;
};

class PinholeCamera {
 public:
  // aspect: image width / height.
  PinholeCamera(const CameraSpec& spec, float aspect) : eye_(spec.eye) {
    w_ = normalize(spec.eye - spec.target);
    u_ = normalize(cross(spec.up, w_));
    v_ = cross(w_, u_);
    halfH_ = std::tan(0.5f * spec.verticalFovDegrees * std::numbers::pi_v<float> / 180.0f);
    halfW_ = aspect * halfH_;
  }

  // The direction through (x, y) in [0,1]^2 over the image, y = 0 at the
  // top, one unit along the view axis (not normalized: a thin lens scales it
  // to the plane of focus).
  Vec3f direction(float x, float y) const {
    return u_ * ((2.0f * x - 1.0f) * halfW_) + v_ * ((1.0f - 2.0f * y) * halfH_) - w_;
  }
  // The primary ray through (x, y) at `time`, normalized, over [0, inf).
  Ray ray(float x, float y, float time) const {
    Ray r;
    r.org = eye_;
    r.dir = normalize(direction(x, y));
    r.tnear = 0.0f;
    r.tfar = kInf;
    r.time = time;
    return r;
  }

  Vec3f eye() const { return eye_; }
  Vec3f right() const { return u_; }
  Vec3f up() const { return v_; }

 private:
  Vec3f eye_, u_, v_, w_;
  float halfW_ = 1.0f, halfH_ = 1.0f;
};

}  // namespace mbrt
