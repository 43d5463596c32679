// `hair`: 200k round line segments (size 1) in 12.5k strands of 16 segments,
// rooted on a (not rendered) head and tapering from root to tip, 3 steps;
// motion as `hairball`: each strand moves its own way by ~5 % of the scene's
// size along a bent path.
#include "scenes/mesh_builders.h"
#include "scenes/scene_makers.h"
#include "scenes/strands.h"

namespace mbrt::scenes {

ProceduralScene makeHair(double size, uint64_t seed) {
  constexpr int kPoints = 17;  // 16 segments per strand
  const size_t strands = scaledCount(size, 200000.0 / (kPoints - 1), 1);
  constexpr float kHead = 0.5f;
  constexpr float kRootRadius = 0.0025f, kTipRadius = 0.0008f;
  constexpr float kMove = 0.05f * 2.2f;  // 5 % of the scene's diameter (~2.2)

  std::vector<Segment> segments;
  segments.reserve(strands * (kPoints - 1));
  std::vector<float> radii;
  radii.reserve(strands * kPoints);
  std::vector<std::vector<Vec3f>> steps(3);
  for (auto& s : steps) s.reserve(strands * kPoints);
  for (size_t i = 0; i < strands; ++i) {
    const std::vector<Vec3f> pts = rootedStrand(seed, 0x68720000000ull + i, kPoints, 0.04f, kHead);
    const StrandMotion motion = strandMotion(seed, 0x686d0000000ull + i, kMove, 0.35f);
    const uint32_t first = uint32_t(radii.size());
    for (int j = 0; j < kPoints; ++j) {
      const float f = float(j) / float(kPoints - 1);
      radii.push_back(kRootRadius + (kTipRadius - kRootRadius) * f);
      for (int k = 0; k < 3; ++k) steps[k].push_back(pts[j] + motion.offset[k]);
      if (j + 1 < kPoints) segments.push_back({first + uint32_t(j), first + uint32_t(j) + 1});
    }
  }
  auto scene = std::make_shared<Scene>();
  scene->addSegments(std::move(segments), std::move(steps), std::move(radii));
  ProceduralScene out;
  out.camera = viewFrom(sceneBounds(*scene), {0.5f, 0.35f, 1.0f}, 40.0f, 0.75f);
  out.scene = std::move(scene);
  return out;
}

}  // namespace mbrt::scenes
