// Tessellated shapes for the procedural scenes: spheres with a radius
// function (blobs), grids, cylinders, tori, ribbons along polylines, plus
// small helpers shared by the scene makers. All shapes are closed (watertight)
// except grids and ribbons.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "mbrt/scene.h"
#include "scenes/rng.h"

namespace mbrt::scenes {

struct MeshData {
  std::vector<Triangle> triangles;
  std::vector<Vec3f> vertices;

  size_t numTriangles() const { return triangles.size(); }
  // Appends another mesh (indices shifted).
  void append(const MeshData& other);
};

// Radius along a unit direction (for blobs and other star-shaped solids).
using RadiusFn = std::function<float(Vec3f)>;

// UV sphere with `around` (>= 3) longitude segments and `rings` (>= 2)
// latitude bands: 2*around*(rings-1) triangles. Poles on +-y. Vertex i sits
// at center + dir_i * radius(dir_i).
MeshData makeSphere(int around, int rings, const RadiusFn& radius, Vec3f center = {});
// Resolution (around, rings) of a sphere with about `triangles` triangles.
void sphereResolution(size_t triangles, int& around, int& rings);
MeshData makeSphere(size_t triangles, const RadiusFn& radius, Vec3f center = {});

// Grid of nx*nz cells (2*nx*nz triangles) in the xz plane, centred at the
// origin, extent sx by sz, y = 0.
MeshData makeGrid(int nx, int nz, float sx, float sz);

// Closed cylinder (or cone) from a to b with radii ra, rb: `around` segments,
// `along` bands, capped with fans: 2*around*along + 2*around triangles.
MeshData makeCylinder(int around, int along, Vec3f a, Vec3f b, float ra, float rb);
MeshData makeCylinder(size_t triangles, Vec3f a, Vec3f b, float ra, float rb);

// Torus in the xz plane around the origin: 2*around*tube triangles.
MeshData makeTorus(int around, int tube, float majorRadius, float minorRadius);
MeshData makeTorus(size_t triangles, float majorRadius, float minorRadius);

// A flat ribbon of the given width along a polyline (n points, 2*(n-1)
// triangles), its side perpendicular to the polyline and to `normalHint`.
void appendRibbon(MeshData& mesh, std::span<const Vec3f> polyline, Vec3f normalHint, float width);

// A blob: a sphere whose radius is a base plus Gaussian-like lobes
// amp*exp(sharpness*(dot(dir,axis)-1)).
struct Lobe {
  Vec3f axis;
  float amplitude;
  float sharpness;
};
struct BlobShape {
  float base = 1.0f;
  std::vector<Lobe> lobes;
  float operator()(Vec3f dir) const;
  // Adds `count` random lobes with amplitude and sharpness in the given ranges.
  void addRandomLobes(Rng& rng, int count, float ampLo, float ampHi, float sharpLo, float sharpHi);
};

// Helpers.
Vec3f anyPerpendicular(Vec3f n);  // a unit vector perpendicular to unit n
std::vector<Vec3f> transformed(std::span<const Vec3f> v, const Affine3f& m);
void transformInPlace(std::span<Vec3f> v, const Affine3f& m);
Box3f boundsOf(std::span<const Vec3f> v);
// Rotation by `radians` about the line through `pivot` along `axis`.
Affine3f rotateAbout(Vec3f pivot, Vec3f axis, float radians);
float smoothstep(float e0, float e1, float x);

// Primitive count for a scene knob: round(base * size), at least `minimum`.
size_t scaledCount(double size, double base, size_t minimum);

}  // namespace mbrt::scenes
