// Triangle and quad meshes into mbrt's scene model (mesh_read.h).
#include "mesh_read.h"

#include <cmath>
#include <cstring>
#include <memory>

namespace mbrt::embree_api {
namespace {

bool validVertex(Vec3f v) {
  auto ok = [](float c) { return std::isfinite(c) && std::fabs(c) <= kMaxCoordinate; };
  return ok(v.x) && ok(v.y) && ok(v.z);
}

}  // namespace

std::vector<VertexBuffer> vertexViews(const Geometry& g) {
  std::vector<VertexBuffer> views;
  for (const BufferView& b : g.vertices) {
    // The bytes the buffer holds past the last vertex's x, y, z: owned
    // buffers have 16 more, so the leaves may read each vertex as 16 bytes
    // (VertexBuffer::padding); a shared one ends where its items end.
    size_t padding = 0;
    if (b.isSet() && b.count > 0) {
      const size_t end = b.offset + (b.count - 1) * b.stride + 3 * sizeof(float);
      if (b.buffer->readable() > end) padding = b.buffer->readable() - end;
    }
    views.push_back({b.data(), b.stride, b.count, padding});
  }
  return views;
}

bool readMesh(const Geometry& g, MeshData& out, std::string& error) {
  const uint32_t steps = g.timeSteps();
  const size_t prims = g.index.isSet() ? g.index.count : 0;
  if (steps == 0) {
    error = "has 0 time steps";
    return false;
  }
  if (prims == 0) return true;  // an empty mesh: nothing to add
  for (uint32_t k = 0; k < steps; ++k) {
    if (!g.vertices[k].isSet()) {
      error = "has no vertex buffer for time step " + std::to_string(k);
      return false;
    }
    if (g.vertices[k].count != g.vertices[0].count) {
      error = "has vertex buffers of different sizes (time step " + std::to_string(k) + ")";
      return false;
    }
  }
  const size_t count = g.vertices[0].count;
  out.views = vertexViews(g);
  for (const BufferView& b : g.vertices) out.buffers.push_back(b.buffer);
  out.buffers.push_back(g.index.buffer);

  // Invalid vertices, at any step.
  std::vector<bool> bad;
  for (uint32_t k = 0; k < steps; ++k)
    for (size_t i = 0; i < count; ++i)
      if (!validVertex(out.views[k][i])) {
        if (bad.empty()) bad.assign(count, false);
        bad[i] = true;
      }
  auto usable = [&](uint32_t v) { return v < count && (bad.empty() || !bad[v]); };

  const unsigned corners = g.corners();
  const bool quads = corners == 4;
  out.prims.quads = quads;
  std::vector<uint32_t> kept;
  bool dropped = false;
  out.triangles.reserve(quads ? 2 * prims : prims);
  for (size_t p = 0; p < prims; ++p) {
    uint32_t v[4];
    std::memcpy(v, g.index.item(p), corners * sizeof(uint32_t));
    bool ok = true;
    for (unsigned c = 0; c < corners; ++c) ok = ok && usable(v[c]);
    if (!ok) {
      dropped = true;
      continue;
    }
    if (quads) {
      out.triangles.push_back({v[0], v[1], v[3]});
      out.triangles.push_back({v[2], v[3], v[1]});
      kept.push_back(uint32_t(2 * p));
      kept.push_back(uint32_t(2 * p + 1));
    } else {
      out.triangles.push_back({v[0], v[1], v[2]});
      kept.push_back(uint32_t(p));
    }
  }
  if (dropped) out.prims.kept = std::make_shared<const std::vector<uint32_t>>(std::move(kept));

  if (!bad.empty()) {
    // Copies with the invalid vertices (used by no kept primitive) zeroed,
    // so that mbrt's scene validation accepts the steps.
    out.copies.resize(steps);
    for (uint32_t k = 0; k < steps; ++k) {
      out.copies[k].resize(count);
      for (size_t i = 0; i < count; ++i) out.copies[k][i] = bad[i] ? Vec3f(0.0f) : out.views[k][i];
    }
    out.views.clear();
  }
  // A static mesh exists at every time, as Embree traces it whatever its
  // time range; a moving one only inside its range.
  out.range = steps > 1 ? TimeRange{g.timeStart, g.timeEnd} : TimeRange{};
  return true;
}

}  // namespace mbrt::embree_api
