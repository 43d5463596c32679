// The bench's ray sets (docs/design.md, "How we measure"): primary camera rays at
// random times; secondary rays (a cosine bounce from every primary hit, and
// rays from all around the scene into its bounds); shadow rays from the
// primary hits towards an area light and towards other hit points; and the
// secondary set again from primaries at the frozen times, grouped by time.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "mbrt/bench.h"
#include "mbrt/camera.h"
#include "bench/bench_internal.h"

namespace mbrt::bench {
namespace {

constexpr float kPi = float(std::numbers::pi);

// A primary hit the other sets start from.
struct SurfacePoint {
  Vec3f p, n;  // position, normal facing the camera ray
  float time;
};

std::vector<Ray> cameraRays(const CameraSpec& cam, int width, int height, uint64_t seed,
                            const std::vector<float>* snapTimes) {
  const PinholeCamera camera(cam, float(width) / float(height));
  const size_t n = size_t(width) * size_t(height);
  std::vector<Ray> rays(n);
  for (size_t i = 0; i < n; ++i) {
    const float px = (float(i % width) + uniform(seed, i, 0)) / float(width);
    const float py = (float(i / width) + uniform(seed, i, 1)) / float(height);
    Ray& r = rays[i] = camera.ray(px, py, uniform(seed, i, 2));
    if (snapTimes && !snapTimes->empty()) {
      float best = (*snapTimes)[0];
      for (float t : *snapTimes)
        if (std::fabs(t - r.time) < std::fabs(best - r.time)) best = t;
      r.time = best;
    }
  }
  return rays;
}

std::vector<SurfacePoint> surfacePoints(std::span<const Ray> primary, std::span<const Hit> hits) {
  std::vector<SurfacePoint> out;
  for (size_t i = 0; i < primary.size(); ++i) {
    const Hit& h = hits[i];
    if (!h.valid() || !(length(h.Ng) > 0.0f)) continue;
    Vec3f nrm = normalize(h.Ng);
    if (dot(nrm, primary[i].dir) > 0) nrm = -nrm;
    out.push_back({primary[i].org + primary[i].dir * h.t, nrm, primary[i].time});
  }
  return out;
}

Vec3f unitVector(float u1, float u2) {
  const float z = 1 - 2 * u1, r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Vec3f cosineAbout(Vec3f nrm, float u1, float u2) {
  const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
  const Vec3f a = std::fabs(nrm.x) > 0.9f ? Vec3f(0, 1, 0) : Vec3f(1, 0, 0);
  const Vec3f t1 = normalize(cross(a, nrm)), t2 = cross(nrm, t1);
  return t1 * (r * std::cos(phi)) + t2 * (r * std::sin(phi)) + nrm * std::sqrt(std::max(0.0f, 1 - u1));
}

// The box of the hit points (what the camera sees of the scene), or a box
// around the camera's target when nothing was hit.
Box3f seenBounds(const std::vector<SurfacePoint>& pts, const CameraSpec& cam) {
  Box3f b;
  for (const SurfacePoint& s : pts) b.extend(s.p);
  const float scale = std::max(1e-3f, length(cam.eye - cam.target));
  if (pts.empty()) return {cam.target - Vec3f(0.25f * scale), cam.target + Vec3f(0.25f * scale)};
  const Vec3f pad = Vec3f(1e-3f * scale) + (b.upper - b.lower) * 0.05f;
  return {b.lower - pad, b.upper + pad};
}

Vec3f pointIn(const Box3f& b, float u1, float u2, float u3) {
  return b.lower + (b.upper - b.lower) * Vec3f(u1, u2, u3);
}

// Secondary rays: max(hits, n/2) bounces (every hit at least once), then n/2
// rays from a sphere around the seen bounds (n when nothing was hit): three
// in four aimed at a hit point (they mostly hit, as a renderer's rays do),
// one in four at a random point inside the bounds.
void secondaryRays(const std::vector<SurfacePoint>& pts, const CameraSpec& cam, size_t n, uint64_t seed, float eps,
                   const std::vector<float>& times, RaySets& out, RaySet set) {
  std::vector<Ray>& rays = out.sets[size_t(set)];
  const size_t nh = pts.size();
  const size_t bounces = nh == 0 ? 0 : std::max(nh, n / 2);
  for (size_t j = 0; j < bounces; ++j) {
    const SurfacePoint& s = pts[j % nh];
    Ray b;
    b.org = s.p + s.n * eps;
    b.dir = cosineAbout(s.n, uniform(seed, j, 0), uniform(seed, j, 1));
    b.tnear = eps;
    b.time = s.time;
    rays.push_back(b);
  }
  const Box3f box = seenBounds(pts, cam);
  const float radius = length(box.upper - box.lower);
  const size_t inward = nh == 0 ? n : n / 2;
  const uint64_t s2 = seed ^ 0x2545F4914F6CDD1Dull;
  for (size_t j = 0; j < inward; ++j) {
    Ray r;
    Vec3f target;
    if (nh > 0 && j % 4 != 3) {
      const SurfacePoint& s = pts[size_t(uniform(s2, j, 0) * float(nh)) % nh];
      target = s.p;
      r.time = s.time;
    } else {
      target = pointIn(box, uniform(s2, j, 0), uniform(s2, j, 1), uniform(s2, j, 2));
      r.time = times.empty() ? uniform(s2, j, 3) : times[j % times.size()];
    }
    const Vec3f w = unitVector(uniform(s2 ^ 1, j, 0), uniform(s2 ^ 1, j, 1));
    r.org = target + w * radius;
    r.dir = -w;
    rays.push_back(r);
  }
  if (set == RaySet::Secondary) {
    out.bounces = bounces;
    out.inward = inward;
  }
}

// Shadow rays, n of them (none when nothing was hit): from a hit point
// towards a point of an area light above the seen bounds (even rays) or
// towards another hit point (odd), stopping just short of it.
std::vector<Ray> shadowRays(const std::vector<SurfacePoint>& pts, const CameraSpec& cam, size_t n, uint64_t seed,
                            float eps) {
  std::vector<Ray> rays;
  if (pts.empty()) return rays;
  const Box3f box = seenBounds(pts, cam);
  const Vec3f ext = box.upper - box.lower;
  const Vec3f up = normalize(cam.up);
  const Vec3f lightCentre = (box.lower + box.upper) * 0.5f + up * (length(ext) * 1.5f);
  const uint64_t s3 = seed ^ 0x9E3779B97F4A7C15ull;
  for (size_t j = 0; j < n; ++j) {
    const SurfacePoint& s = pts[size_t(uniform(s3, j, 0) * float(pts.size())) % pts.size()];
    Ray r;
    r.org = s.p + s.n * eps;
    r.time = s.time;
    Vec3f to;
    if (j % 2 == 0) {
      to = lightCentre + (Vec3f(uniform(s3, j, 1), uniform(s3, j, 2), uniform(s3, j, 3)) - Vec3f(0.5f)) * ext;
    } else {
      to = pts[size_t(uniform(s3 ^ 1, j, 1) * float(pts.size())) % pts.size()].p;
    }
    r.dir = to - r.org;
    if (!(length(r.dir) > 4 * eps)) continue;
    r.tnear = 0.0f;
    r.tfar = 1.0f - 2 * eps / length(r.dir);  // the light or the other point itself is not an occluder
    rays.push_back(r);
  }
  return rays;
}

}  // namespace

std::string_view toString(RaySet set) {
  switch (set) {
    case RaySet::Primary:
      return "primary";
    case RaySet::Secondary:
      return "secondary";
    case RaySet::Shadow:
      return "shadow";
    case RaySet::Frozen:
      return "frozen";
    case RaySet::Incoherent:
      return "incoherent";
  }
  return "unknown";
}

RaySets makeRaySets(const ProceduralScene& ps, const Target& reference, int width, int height, uint64_t seed,
                    const std::vector<float>& frozenTimes, bool secondaryOnly) {
  RaySets out;
  const size_t n = size_t(width) * size_t(height);
  const float eps = 1e-4f * std::max(1e-3f, length(ps.camera.eye - ps.camera.target));
  std::vector<Ray> primary = cameraRays(ps.camera, width, height, seed, nullptr);
  std::vector<Hit> hits(primary.size());
  reference.trace(primary, hits);
  const std::vector<SurfacePoint> pts = surfacePoints(primary, hits);
  secondaryRays(pts, ps.camera, n, seed ^ 0x5bd1e995u, eps, {}, out, RaySet::Secondary);
  if (secondaryOnly) return out;
  out.sets[size_t(RaySet::Shadow)] = shadowRays(pts, ps.camera, n, seed, eps);
  out.sets[size_t(RaySet::Incoherent)] = incoherentRays(*ps.scene, n, seed ^ 0x696e636f68ull);
  out.sets[size_t(RaySet::Primary)] = std::move(primary);

  std::vector<Ray> frozenPrimary = cameraRays(ps.camera, width, height, seed, &frozenTimes);
  reference.trace(frozenPrimary, hits);
  secondaryRays(surfacePoints(frozenPrimary, hits), ps.camera, n, seed ^ 0x5bd1e995u, eps, frozenTimes, out,
                RaySet::Frozen);
  // Grouped by time, as a renderer with a static tree per frame time traces
  // each time's rays on its tree: the frozen rows' K trees are then walked
  // one after the other, not all at once through a shared cache.
  std::vector<Ray>& frozen = out.sets[size_t(RaySet::Frozen)];
  std::stable_sort(frozen.begin(), frozen.end(), [](const Ray& a, const Ray& b) { return a.time < b.time; });
  return out;
}

}  // namespace mbrt::bench
