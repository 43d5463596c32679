// Motion decomposition (decompose/decompose.h): parts moved by known affine
// maps are recovered, a rigidly rotating mesh is one cluster.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "decompose/decompose.h"

using namespace mbrt;
using namespace mbrt::detail;

namespace {

// A closed box subdivided n x n per face (welded: one connected piece), centred at c.
void addBox(Vec3f c, Vec3f half, int n, std::vector<Triangle>& tris, std::vector<Vec3f>& verts) {
  const size_t firstVertex = verts.size(), firstTri = tris.size();
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const uint32_t base = uint32_t(verts.size());
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          Vec3f p;
          p[axis] = side ? 1.0f : -1.0f;
          p[u] = -1.0f + 2.0f * i / n;
          p[v] = -1.0f + 2.0f * j / n;
          verts.push_back(c + p * half);
        }
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const uint32_t a = base + i * (n + 1) + j, b = a + 1, d = a + (n + 1), e = d + 1;
          tris.push_back({a, b, e});
          tris.push_back({a, e, d});
        }
    }
  // Weld equal positions.
  std::vector<uint32_t> map(verts.size());
  std::vector<Vec3f> kept(verts.begin(), verts.begin() + firstVertex);
  for (size_t i = firstVertex; i < verts.size(); ++i) {
    size_t j = firstVertex;
    while (j < kept.size() && !(kept[j].x == verts[i].x && kept[j].y == verts[i].y && kept[j].z == verts[i].z)) ++j;
    if (j == kept.size()) kept.push_back(verts[i]);
    map[i] = uint32_t(j);
  }
  verts = kept;
  for (size_t t = firstTri; t < tris.size(); ++t) tris[t] = {map[tris[t].v0], map[tris[t].v1], map[tris[t].v2]};
}

Affine3f randomAffine(std::mt19937& rng, float amount) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Affine3f a = Affine3f::rotate(normalize(Vec3f{u(rng), u(rng), u(rng)}), 1.5f * amount * u(rng));
  a.vx = a.vx * (1.0f + 0.3f * amount * u(rng));
  a.vy = a.vy + Vec3f{u(rng), u(rng), u(rng)} * (0.2f * amount);
  a.p = Vec3f{u(rng), u(rng), u(rng)} * amount;
  return a;
}

}  // namespace

TEST(Decompose, PartsMovedByKnownAffineMapsAreRecovered) {
  std::mt19937 rng(7);
  std::vector<Triangle> tris;
  std::vector<Vec3f> rest;
  std::vector<uint32_t> partOf;
  const Vec3f centres[3] = {{-2, 0, 0}, {0, 0.5f, 0}, {2, 0, 0.3f}};
  for (int p = 0; p < 3; ++p) {
    const size_t before = tris.size();
    addBox(centres[p], {0.4f + 0.1f * p, 0.5f, 0.3f}, 3, tris, rest);
    partOf.resize(tris.size(), uint32_t(p));
    (void)before;
  }
  const uint32_t K = 6;
  std::vector<std::vector<Vec3f>> keys(K);
  for (uint32_t k = 0; k < K; ++k) {
    Affine3f maps[3];
    for (auto& m : maps) m = k == 0 ? Affine3f::identity() : randomAffine(rng, 0.3f * k);
    for (size_t v = 0; v < rest.size(); ++v) {
      const int part = v < rest.size() / 3 ? 0 : (v < 2 * rest.size() / 3 ? 1 : 2);
      keys[k].push_back(maps[part].xfmPoint(rest[v]));
    }
  }
  DecomposeParams params;
  params.startFromPieces = false;  // the parts must be found, not given
  const Decomposition d = decomposeMotion(tris, keys, params);
  std::printf("[ info ] %u clusters, rms residual %.3g, %zu curve rows, %.3f s\n", d.numClusters, d.rmsResidual,
              d.curve.size(), d.seconds);
  ASSERT_EQ(d.numClusters, 3u);
  // Every part maps to exactly one cluster, and distinct parts to distinct ones.
  std::set<std::pair<uint32_t, uint32_t>> pairs;
  for (size_t j = 0; j < tris.size(); ++j) pairs.insert({partOf[j], d.clusterOf[j]});
  EXPECT_EQ(pairs.size(), 3u);
  std::set<uint32_t> clusters;
  for (auto [p, c] : pairs) clusters.insert(c);
  EXPECT_EQ(clusters.size(), 3u);
  EXPECT_LT(d.rmsResidual, 1e-5);
  // The curve drops with every cluster.
  for (size_t i = 1; i < d.curve.size(); ++i) EXPECT_LT(d.curve[i].residual, d.curve[i - 1].residual);
  // The returned maps take the local frame to each key: the local positions
  // (inverse map of the key positions) agree over keys.
  for (size_t j = 0; j < tris.size(); j += 7) {
    const auto& W = d.transforms[d.clusterOf[j]];
    Affine3d inv0;
    ASSERT_TRUE(W[0].inverse(inv0));
    const Vec3d q0 = inv0.apply(toD(keys[0][tris[j].v0]));
    for (uint32_t k = 1; k < K; ++k) {
      Affine3d inv;
      ASSERT_TRUE(W[k].inverse(inv));
      EXPECT_LT(std::sqrt(norm2(inv.apply(toD(keys[k][tris[j].v0])) - q0)), 1e-4);
    }
  }
}

TEST(Decompose, RigidlyRotatingMeshIsOneClusterWithZeroResidual) {
  std::vector<Triangle> tris;
  std::vector<Vec3f> rest;
  addBox({0.3f, 0.2f, -0.1f}, {1.0f, 0.5f, 0.25f}, 6, tris, rest);
  const uint32_t K = 9;
  std::vector<std::vector<Vec3f>> keys(K);
  for (uint32_t k = 0; k < K; ++k) {
    Affine3f m = Affine3f::rotate(normalize(Vec3f{0.2f, 1.0f, 0.3f}), 0.4f * float(k));
    m.p = {0.1f * k, 0.0f, -0.05f * k};
    for (const Vec3f& v : rest) keys[k].push_back(m.xfmPoint(v));
  }
  const Decomposition d = decomposeMotion(tris, keys);
  EXPECT_EQ(d.numClusters, 1u);
  EXPECT_LT(d.rmsResidual, 1e-5);
  EXPECT_EQ(d.curve.size(), 1u);
}

TEST(Decompose, SeparatePiecesStartAsTheirOwnClusters) {
  std::vector<Triangle> tris;
  std::vector<Vec3f> rest;
  for (int i = 0; i < 5; ++i) addBox({float(i), 0, 0}, {0.3f, 0.3f, 0.3f}, 1, tris, rest);
  uint32_t pieces = 0;
  connectedPieces(tris, uint32_t(rest.size()), pieces);
  EXPECT_EQ(pieces, 5u);
  std::vector<std::vector<Vec3f>> keys(3);
  for (uint32_t k = 0; k < 3; ++k)
    for (size_t v = 0; v < rest.size(); ++v)
      keys[k].push_back(rest[v] + Vec3f{0.0f, float(k) * float(v / 8), 0.0f});  // each box its own speed
  const Decomposition d = decomposeMotion(tris, keys);
  EXPECT_EQ(d.numClusters, 5u);
  EXPECT_LT(d.rmsResidual, 1e-5);
}
