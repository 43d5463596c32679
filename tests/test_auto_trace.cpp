// `auto`'s measured confirmation (auto/trace_confirm.h): which candidates a
// trace measures, the decision given the measurements (injected here, so
// that it is known), what mbrt stats says of it, and a correct accel
// whatever is chosen.
#include <gtest/gtest.h>

#include "auto/trace_confirm.h"
#include "auto_scene.h"
#include "oracle.h"
#include "test_util.h"

using namespace mbrt;
using detail::TraceCandidate;

namespace {

TEST(AutoTrace, OnlyCandidatesWithinTheModelsErrorAreMeasured) {
  const detail::Structure* s = reinterpret_cast<const detail::Structure*>(&s);  // never traced here
  const std::vector<TraceCandidate> c = {{"a", s, 5.0}, {"b", s, 5.7}, {"c", s, 6.0}, {"d", s, 4.9}};
  EXPECT_EQ(detail::worthMeasuring(c, 0), (std::vector<bool>{true, true, false, true}));
  EXPECT_EQ(detail::worthMeasuring(c, 3), (std::vector<bool>{true, false, false, true})) << "within 15 % of 4.9";
  const std::vector<TraceCandidate> far = {{"a", s, 5.0}, {"b", s, 6.0}};
  EXPECT_EQ(detail::worthMeasuring(far, 0), (std::vector<bool>{false, false})) << "alone: nothing to compare";
}

TEST(AutoTrace, TheMeasuredBestWinsOnlyByMoreThanTheMargin) {
  using M = std::vector<std::optional<double>>;
  EXPECT_EQ(detail::chooseByMeasurement(0, M{1.0, 0.9}), 1u);
  EXPECT_EQ(detail::chooseByMeasurement(0, M{1.0, 0.98}), 0u) << "within the margin the model's choice stands";
  EXPECT_EQ(detail::chooseByMeasurement(1, M{0.5, 1.0, 0.7}), 0u);
  EXPECT_EQ(detail::chooseByMeasurement(1, M{0.5, std::nullopt}), 1u) << "the model's choice unmeasured: it stands";
  EXPECT_EQ(detail::chooseByMeasurement(0, M{1.0, std::nullopt, 0.5}), 2u) << "unmeasured candidates never win";
}

// A mesh sliding rigidly: the decomposition (one instance) and the mesh as
// one object are within the model's error, so the trace decides. The
// injected timer makes either one the faster: the accel keeps it, says so,
// and agrees with brute.
TEST(AutoTrace, InjectedMeasurementsDecideBetweenDecompositionAndOneObject) {
  test::MeshParts m;
  test::addBlob(m, {0.0f, 0.0f, 0.0f}, 0.5f, 40, 0.1f);
  ProceduralScene ps;
  ps.scene = std::make_shared<Scene>();
  ps.scene->addTriangleMesh(m.triangles, test::movedSteps(m.vertices, {Affine3f(), Affine3f::translate({1.0f, 0, 0})},
                                                          ~0u, 0, 1, 1));
  ps.camera = frameBox(Box3f({-0.6f, -0.6f, -0.6f}, {1.6f, 0.6f, 0.6f}));
  auto oracle = test::buildBrute(*ps.scene);
  const std::vector<Ray> rays = test::oracleRays(ps, test::scaled(1500, 300), test::scaled(30, 5), 21);
  for (bool instanceFaster : {true, false}) {
    // The decomposition's top level is its one instance: one reference, no nodes.
    const detail::ScopedTraceTimer timer([instanceFaster](const detail::Structure& s, std::span<const detail::RayQuery>) {
      AccelStats st;
      s.fillStats(st);
      const bool instance = st.references == 1 && st.innerNodes == 0;
      return instance == instanceFaster ? 1e-7 : 2e-7;
    });
    auto accel = Accel::build(*ps.scene, BuildOptions{});
    const std::string objects = accel->stats().objects;
    EXPECT_NE(objects.find("measured by a trace"), std::string::npos) << objects;
    if (instanceFaster) EXPECT_NE(objects.find("kept the decomposition"), std::string::npos) << objects;
    else EXPECT_NE(objects.find("the whole scene as one object"), std::string::npos) << objects;
    const auto rep = test::compareWithOracle(*oracle, *accel, rays);
    EXPECT_EQ(rep.wrong, 0u) << rep.firstFailure;
    EXPECT_EQ(rep.anyWrong, 0u);
    EXPECT_GT(rep.hits, rep.rays / 5);
  }
  // Without the confirmation: the model's choice, nothing measured.
  BuildOptions o;
  o.autoConfirmByTrace = false;
  EXPECT_EQ(Accel::build(*ps.scene, o)->stats().objects.find("measured by a trace"), std::string::npos);
}

}  // namespace
