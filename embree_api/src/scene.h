// RTCScene: the geometry table (ids as Embree hands them out), flags and
// build quality, and what the last commit left for tracing: the snapshot
// and the mbrt Accel over it.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <set>
#include <vector>

#include "geometry.h"
#include "handles.h"
#include "mbrt/accel.h"
#include "snapshot.h"

namespace mbrt::embree_api {

struct Committed {
  std::shared_ptr<Snapshot> snapshot;
  std::unique_ptr<Accel> accel;  // null when there is nothing to trace; destroyed before the snapshot
  bool contextFilter = false;
  ssize_t monitoredBytes = 0;    // told to the device's memory monitor
  ~Committed() { accel.reset(); }
};

class Scene final : public Object {
 public:
  static constexpr Tag kTag = Tag::Scene;
  explicit Scene(Device* device);
  ~Scene() override;

  // rtcAttachGeometry takes the lowest free id (freed ids first), as
  // Embree's id pool does; rtcAttachGeometryByID a given one.
  uint32_t attach(Geometry& g);
  void attachAt(Geometry& g, uint32_t id);
  void detach(uint32_t id);
  Geometry* geometry(uint32_t id) const { return id < geometries_.size() ? geometries_[id].get() : nullptr; }
  const std::vector<Ref<Geometry>>& geometries() const { return geometries_; }

  RTCSceneFlags flags = RTC_SCENE_FLAG_NONE;
  RTCBuildQuality buildQuality = RTC_BUILD_QUALITY_MEDIUM;
  RTCProgressMonitorFunction progress = nullptr;
  void* progressUserPtr = nullptr;

  // rtcCommitScene / rtcJoinCommitScene (commit.cpp).
  void commit(const char* function);
  // Null before the first successful commit.
  const Committed* committed() const { return committed_.load(std::memory_order_acquire); }
  std::shared_ptr<const Committed> committedShared() const;
  // Whether geometries or the table changed since the last commit.
  bool modifiedSinceCommit() const;

 private:
  void publish(std::shared_ptr<Committed> c);

  std::vector<Ref<Geometry>> geometries_;
  std::set<uint32_t> freeIds_;
  bool tableChanged_ = true;
  // What the last commit read of each geometry (by id).
  struct ReadState {
    uint64_t topologyVersion = 0, vertexVersion = 0;
    const Snapshot* childSnapshot = nullptr;  // instances: the instanced scene's
    uint64_t childGeneration = 0;
    bool operator==(const ReadState&) const = default;
  };
  static ReadState stateOf(const Geometry& g);
  std::vector<ReadState> committedStates_;
  bool tryRefit(const char* function, std::vector<std::string>& errors);
  std::mutex buildMutex_;           // one commit at a time
  mutable std::mutex commitMutex_;  // guards current_
  std::shared_ptr<Committed> current_;
  std::atomic<const Committed*> committed_{nullptr};
};

}  // namespace mbrt::embree_api
