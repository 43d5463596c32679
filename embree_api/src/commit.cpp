// rtcCommitScene: reads the scene into mbrt (snapshot.h) and builds an
// mbrt Accel of the device's kind over it; when only the vertex data of
// meshes changed (rtcUpdateGeometryBuffer or new vertex buffers of the same
// size, rtcCommitGeometry), the snapshot keeps its topology and the Accel
// refits (mbrt's Accel::refit: in place where the kind can, else rebuilt),
// as Embree refits a dynamic scene.
#include <cstring>
#include <unordered_map>

#include "bounds.h"
#include "device.h"
#include "errors.h"
#include "mesh_read.h"
#include "scene.h"
#include "scene_dump.h"

namespace mbrt::embree_api {

Scene::ReadState Scene::stateOf(const Geometry& g) {
  ReadState s{g.topologyVersion(), g.vertexVersion(), nullptr, 0};
  if (g.isInstance() && g.instanced) {
    const auto c = g.instanced->committedShared();
    if (c) {
      s.childSnapshot = c->snapshot.get();
      s.childGeneration = c->snapshot->generation;
    }
  }
  return s;
}

void Scene::publish(std::shared_ptr<Committed> c) {
  std::lock_guard<std::mutex> lock(commitMutex_);
  current_ = std::move(c);
  committed_.store(current_.get(), std::memory_order_release);
}

// The refit path: the same table and topology, only mesh vertices changed,
// every primitive still valid with the same indices.
bool Scene::tryRefit(const char*, std::vector<std::string>&) {
  if (!current_ || tableChanged_ || committedStates_.size() != geometries_.size()) return false;
  if (current_->contextFilter != bool(flags & RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION)) return false;
  Snapshot& snap = *current_->snapshot;
  std::unordered_map<uint32_t, uint32_t> mbrtId;  // Embree id -> mbrt id
  for (uint32_t i = 0; i < snap.entries.size(); ++i) mbrtId[snap.entries[i].embreeID] = i;
  std::vector<std::pair<uint32_t, std::vector<VertexBuffer>>> updates;
  for (uint32_t id = 0; id < geometries_.size(); ++id) {
    const Geometry* g = geometries_[id].get();
    if (!g) continue;
    const ReadState now = stateOf(*g), then = committedStates_[id];
    if (now == then) continue;
    if (now.topologyVersion != then.topologyVersion || now.childSnapshot != then.childSnapshot ||
        now.childGeneration != then.childGeneration || !g->isMesh())
      return false;
    const auto it = mbrtId.find(id);
    if (it == mbrtId.end()) return false;  // left out before: read it again
    MeshData m;
    std::string error;
    if (!readMesh(*g, m, error) || !m.copies.empty() || m.prims.kept || snap.entries[it->second].prims.kept)
      return false;
    const mbrt::Geometry& old = snap.scene->geometry(it->second);
    if (old.triangles().size() != m.triangles.size() ||
        std::memcmp(old.triangles().data(), m.triangles.data(), m.triangles.size() * sizeof(Triangle)) != 0 ||
        old.vertices(0).count != m.views[0].count)
      return false;
    updates.emplace_back(it->second, std::move(m.views));
    for (auto& b : m.buffers) snap.buffers.push_back(b);
  }
  if (updates.empty()) return true;
  for (auto& [mid, views] : updates) {
    for (uint32_t k = 0; k < views.size(); ++k) snap.scene->setVertices(mid, k, views[k]);
    snap.entries[mid].vertexVersion = geometries_[snap.entries[mid].embreeID]->vertexVersion();
  }
  device()->run([&] { current_->accel->refit(); });
  const SceneBounds b = boundsOf(*snap.scene);
  snap.bounds = b.box;
  snap.linearBounds = b.linear;
  ++snap.generation;
  return true;
}

void Scene::commit(const char* function) {
  std::lock_guard<std::mutex> buildLock(buildMutex_);
  Device& d = *device();
  if (progress && !progress(progressUserPtr, 0.0)) fail(RTC_ERROR_CANCELLED, "the progress monitor cancelled the build");
  std::vector<std::string> errors;
  if (!tryRefit(function, errors)) {
    SnapshotContext context;
    context.contextFilter = (flags & RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION) != 0;
    auto c = std::make_shared<Committed>();
    c->contextFilter = context.contextFilter;
    c->snapshot = buildSnapshot(*this, context, errors);
    if (c->snapshot->scene) {
      d.run([&] { c->accel = Accel::build(*c->snapshot->scene, d.buildOptions()); });
      c->monitoredBytes = ssize_t(c->accel->stats().bytes);
    }
    if (!d.monitorMemory(c->monitoredBytes))
      fail(RTC_ERROR_OUT_OF_MEMORY, "the memory monitor refused the " + std::to_string(c->monitoredBytes) +
                                        " bytes of the build");
    if (current_) d.monitorMemory(-current_->monitoredBytes);
    publish(std::move(c));
  }
  committedStates_.assign(geometries_.size(), ReadState{});
  for (uint32_t id = 0; id < geometries_.size(); ++id)
    if (geometries_[id]) committedStates_[id] = stateOf(*geometries_[id]);
  tableChanged_ = false;
  if (!dumpIfAsked(*current_->snapshot)) errors.push_back("could not write the scene to MBRT_EMBREE_DUMP");
  for (const std::string& e : errors) report(&d, RTC_ERROR_INVALID_OPERATION, std::string(function) + ": " + e);
  if (progress) progress(progressUserPtr, 1.0);
}

}  // namespace mbrt::embree_api

using namespace mbrt::embree_api;

RTC_API void rtcCommitScene(RTCScene scene) {
  guarded("rtcCommitScene", scene, [&] { require<Scene>(scene, "RTCScene").commit("rtcCommitScene"); });
}

// Threads joining one commit: the first builds, the others wait for it
// (the build itself runs in parallel on TBB).
RTC_API void rtcJoinCommitScene(RTCScene scene) {
  guarded("rtcJoinCommitScene", scene, [&] { require<Scene>(scene, "RTCScene").commit("rtcJoinCommitScene"); });
}
