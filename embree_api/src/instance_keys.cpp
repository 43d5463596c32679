// Instance keys into mbrt's scene model (instance_keys.h).
#include "instance_keys.h"

#include <cmath>
#include <vector>

#include "errors.h"

namespace mbrt::embree_api {

Affine3f scaleSkewShift(const RTCQuaternionDecomposition& d) {
  Affine3f s;
  s.vx = {d.scale_x, 0, 0};
  s.vy = {d.skew_xy, d.scale_y, 0};
  s.vz = {d.skew_xz, d.skew_yz, d.scale_z};
  s.p = {d.shift_x, d.shift_y, d.shift_z};
  return s;
}

namespace {

Quaternion rotationOf(const RTCQuaternionDecomposition& d) {
  return {d.quaternion_r, d.quaternion_i, d.quaternion_j, d.quaternion_k};
}

bool usableMatrix(const Affine3f& m) { return m.isFinite() && std::fabs(m.determinant()) > 1e-30f; }

bool usableRotation(const Quaternion& q) { return q.isFinite() && q.norm() > 1e-20f; }

}  // namespace

Affine3f loadTransform(RTCFormat format, const float* m) {
  Affine3f a;
  switch (format) {
    case RTC_FORMAT_FLOAT3X4_ROW_MAJOR:
      a.vx = {m[0], m[4], m[8]};
      a.vy = {m[1], m[5], m[9]};
      a.vz = {m[2], m[6], m[10]};
      a.p = {m[3], m[7], m[11]};
      return a;
    case RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR:
      a.vx = {m[0], m[1], m[2]};
      a.vy = {m[3], m[4], m[5]};
      a.vz = {m[6], m[7], m[8]};
      a.p = {m[9], m[10], m[11]};
      return a;
    case RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR:
      a.vx = {m[0], m[1], m[2]};
      a.vy = {m[4], m[5], m[6]};
      a.vz = {m[8], m[9], m[10]};
      a.p = {m[12], m[13], m[14]};
      return a;
    default:
      fail(RTC_ERROR_INVALID_OPERATION, "invalid matrix format");
  }
}

void storeTransform(const Affine3f& a, RTCFormat format, float* m) {
  switch (format) {
    case RTC_FORMAT_FLOAT3X4_ROW_MAJOR: {
      const float r[12] = {a.vx.x, a.vy.x, a.vz.x, a.p.x, a.vx.y, a.vy.y, a.vz.y, a.p.y, a.vx.z, a.vy.z, a.vz.z, a.p.z};
      for (int i = 0; i < 12; ++i) m[i] = r[i];
      return;
    }
    case RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR: {
      const float c[12] = {a.vx.x, a.vx.y, a.vx.z, a.vy.x, a.vy.y, a.vy.z, a.vz.x, a.vz.y, a.vz.z, a.p.x, a.p.y, a.p.z};
      for (int i = 0; i < 12; ++i) m[i] = c[i];
      return;
    }
    case RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR: {
      const float c[16] = {a.vx.x, a.vx.y, a.vx.z, 0, a.vy.x, a.vy.y, a.vy.z, 0,
                           a.vz.x, a.vz.y, a.vz.z, 0, a.p.x,  a.p.y,  a.p.z,  1};
      for (int i = 0; i < 16; ++i) m[i] = c[i];
      return;
    }
    default:
      fail(RTC_ERROR_INVALID_OPERATION, "invalid matrix format");
  }
}

Affine3f decompositionMatrix(const RTCQuaternionDecomposition& d) {
  Affine3f r;
  rotationOf(d).normalized().toMatrix(r.vx, r.vy, r.vz);
  r.p = {d.translation_x, d.translation_y, d.translation_z};
  return r * scaleSkewShift(d);
}

Affine3f transformAt(const Geometry& g, float time) {
  const uint32_t steps = uint32_t(g.keys.size());
  if (steps == 0) return Affine3f();
  if (steps == 1) return g.keys[0].quaternion ? decompositionMatrix(g.keys[0].decomposition) : g.keys[0].matrix;
  const float range = g.timeEnd - g.timeStart;
  const float local = std::clamp((time - g.timeStart) / range, 0.0f, 1.0f) * float(steps - 1);
  const uint32_t s = std::min(uint32_t(local), steps - 2);
  const float f = local - float(s);
  const InstanceKey &a = g.keys[s], &b = g.keys[s + 1];
  if (!a.quaternion || !b.quaternion) return lerp(a.matrix, b.matrix, f);
  const RTCQuaternionDecomposition &da = a.decomposition, &db = b.decomposition;
  Affine3f r;
  slerp(rotationOf(da).normalized(), rotationOf(db).normalized(), f).toMatrix(r.vx, r.vy, r.vz);
  r.p = lerp(Vec3f{da.translation_x, da.translation_y, da.translation_z},
             Vec3f{db.translation_x, db.translation_y, db.translation_z}, f);
  return r * lerp(scaleSkewShift(da), scaleSkewShift(db), f);
}

bool addInstance(mbrt::Scene& scene, const Geometry& g, std::shared_ptr<const mbrt::Scene> child, uint32_t& id,
                 InstancePath& path, std::string& error) {
  const size_t steps = g.keys.size();
  if (steps == 0) {
    error = "has 0 time steps";
    return false;
  }
  const TimeRange range = steps > 1 ? TimeRange{g.timeStart, g.timeEnd} : TimeRange{};
  size_t quaternions = 0;
  for (const InstanceKey& k : g.keys) quaternions += k.quaternion ? 1 : 0;
  if (quaternions != 0 && quaternions != steps) {
    error = "mixes matrix and quaternion keys (rtcSetGeometryTransform and rtcSetGeometryTransformQuaternion)";
    return false;
  }
  if (quaternions == 0) {
    std::vector<Affine3f> keys;
    for (size_t k = 0; k < steps; ++k) {
      if (!usableMatrix(g.keys[k].matrix)) {
        error = "has a singular or non-finite transform at time step " + std::to_string(k);
        return false;
      }
      keys.push_back(g.keys[k].matrix);
    }
    id = scene.addInstance(std::move(child), std::move(keys), range);
    path.outer = &scene.geometry(id);
    return true;
  }
  // Quaternion keys: one SRT instance, or SRT over the S matrices.
  bool plain = true;
  for (size_t k = 0; k < steps; ++k) {
    const RTCQuaternionDecomposition& d = g.keys[k].decomposition;
    const Vec3f scale{d.scale_x, d.scale_y, d.scale_z}, t{d.translation_x, d.translation_y, d.translation_z};
    if (!usableRotation(rotationOf(d)) || !isFinite(t) || !usableMatrix(scaleSkewShift(d))) {
      error = "has a singular or non-finite quaternion decomposition at time step " + std::to_string(k);
      return false;
    }
    plain = plain && d.skew_xy == 0 && d.skew_xz == 0 && d.skew_yz == 0 && d.shift_x == 0 && d.shift_y == 0 &&
            d.shift_z == 0;
    if (k > 0) {
      const RTCQuaternionDecomposition& p = g.keys[k - 1].decomposition;
      plain = plain && (scale.x > 0) == (p.scale_x > 0) && (scale.y > 0) == (p.scale_y > 0) &&
              (scale.z > 0) == (p.scale_z > 0);
    }
  }
  std::vector<SRTKey> srt;
  for (const InstanceKey& k : g.keys) {
    const RTCQuaternionDecomposition& d = k.decomposition;
    const Vec3f scale = plain ? Vec3f{d.scale_x, d.scale_y, d.scale_z} : Vec3f{1, 1, 1};
    srt.push_back({scale, rotationOf(d), {d.translation_x, d.translation_y, d.translation_z}});
  }
  if (plain) {
    id = scene.addInstance(std::move(child), std::move(srt), range);
    path.outer = &scene.geometry(id);
    return true;
  }
  auto inner = std::make_shared<mbrt::Scene>();
  std::vector<Affine3f> s;
  for (const InstanceKey& k : g.keys) s.push_back(scaleSkewShift(k.decomposition));
  const uint32_t innerId = inner->addInstance(std::move(child), std::move(s), range);
  path.inner = &inner->geometry(innerId);
  id = scene.addInstance(std::move(inner), std::move(srt), range);
  path.outer = &scene.geometry(id);
  return true;
}

}  // namespace mbrt::embree_api
