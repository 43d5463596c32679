#include "decompose/decompose.h"

#include <algorithm>
#include <chrono>
#include <numeric>

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

namespace mbrt::detail {
namespace {

using Clock = std::chrono::steady_clock;

// Normal tips do not move affinely under shear or non-uniform scale: they
// only pin directions the vertices leave free (flat clusters, one triangle).
constexpr double kTipWeight = 1e-4;

// The three vertices and the normal tip of a triangle in one pose.
inline void triPoints(const Triangle& t, const std::vector<Vec3f>& x, Vec3d out[4]) {
  const Vec3d a = toD(x[t.v0]), b = toD(x[t.v1]), c = toD(x[t.v2]);
  const Vec3d n = cross(b - a, c - a);
  const double l = std::sqrt(std::sqrt(norm2(n)));
  out[0] = a;
  out[1] = b;
  out[2] = c;
  out[3] = (a + b + c) * (1.0 / 3.0) + (l > 0 ? n * (1.0 / l) : Vec3d{});
}

class Decomposer {
 public:
  Decomposer(std::span<const Triangle> tris, const std::vector<std::vector<Vec3f>>& keys, const DecomposeParams& p)
      : tris_(tris), keys_(keys), params_(p), T_(uint32_t(tris.size())) {}

  Decomposition run() {
    const auto start = Clock::now();
    Decomposition out;
    const uint32_t K = uint32_t(keys_.size());
    const uint32_t numVerts = keys_.empty() ? 0 : uint32_t(keys_[0].size());
    uint32_t pieces = 0;
    assign_ = connectedPieces(tris_, numVerts, pieces);
    if (!params_.startFromPieces) {
      std::fill(assign_.begin(), assign_.end(), 0u);
      pieces = 1;
    }
    C_ = std::max(1u, pieces);
    if (C_ > params_.maxClusters)
      for (uint32_t& a : assign_) a %= params_.maxClusters;
    C_ = std::min(C_, params_.maxClusters);
    // Search keys: evenly subsampled, first and last included.
    const uint32_t ns = std::min(K, std::max(2u, params_.searchKeys));
    for (uint32_t i = 0; i < ns; ++i) {
      const uint32_t k = ns == 1 ? 0 : uint32_t((uint64_t(i) * (K - 1) + (ns - 1) / 2) / (ns - 1));
      if (keySet_.empty() || keySet_.back() != k) keySet_.push_back(k);
    }
    setRest(keySet_[keySet_.size() / 2]);
    spread_ = motionSpread();
    residual_.assign(T_, 0.0);
    compact();

    // Algorithm 1.
    double E = lloyd(fit(nullptr));
    out.curve.push_back(step(E, start));
    while (C_ < params_.maxClusters && E > params_.exactTol * spread_ && T_ > C_) {
      const std::vector<uint32_t> savedAssign = assign_;
      const uint32_t savedC = C_;
      // Re-seed: existing clusters fitted to their best triangles; the new
      // cluster to the worst triangle and its neighbours.
      std::vector<uint8_t> mask = bestHalf();
      const uint32_t worst = uint32_t(std::max_element(residual_.begin(), residual_.end()) - residual_.begin());
      for (uint32_t j : neighbours(worst)) {
        assign_[j] = C_;
        mask[j] = 1;
      }
      ++C_;
      const double Enew = lloyd(fit(&mask));
      if (!(Enew < E)) {  // no gain at all: undo
        assign_ = savedAssign;
        C_ = savedC;
        lloyd(fit(nullptr));
        break;
      }
      const double gain = (E - Enew) / E;
      E = Enew;
      out.curve.push_back(step(E, start));
      if (gain < params_.insertTol) break;
    }

    // Rest pose by Eq. 3 among the search keys, then a final pass.
    if (K > 1) {
      double best = -1;
      uint32_t bestKey = rest_;
      for (uint32_t r : keySet_) {
        setRest(r);
        const double e = totalResidual(fit(nullptr));
        if (best < 0 || e < best) {
          best = e;
          bestKey = r;
        }
      }
      setRest(bestKey);
      E = lloyd(fit(nullptr));
    }
    // Final transforms over every key.
    std::vector<uint32_t> all(K);
    std::iota(all.begin(), all.end(), 0u);
    keySet_ = all;
    keyPoints();
    const auto A = fit(nullptr);
    out.residual = totalResidual(A);
    out.rmsResidual = T_ && K ? std::sqrt(out.residual / (3.0 * T_ * K)) : 0.0;
    out.numClusters = C_;
    out.restKey = rest_;
    out.clusterOf = assign_;
    out.transforms = withFrames(A);
    out.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return out;
  }

 private:
  using Fits = std::vector<std::vector<Affine3d>>;  // [cluster][search key index]

  void setRest(uint32_t r) {
    rest_ = r;
    restPts_.resize(size_t(T_) * 4);
    tbb::parallel_for(uint32_t(0), T_, [&](uint32_t j) { triPoints(tris_[j], keys_[r], &restPts_[size_t(j) * 4]); });
    keyPoints();
  }
  // Points of every triangle at every key of keySet_ (contiguous per triangle).
  void keyPoints() {
    const size_t nk = keySet_.size();
    keyPts_.resize(size_t(T_) * nk * 4);
    tbb::parallel_for(uint32_t(0), T_, [&](uint32_t j) {
      for (size_t i = 0; i < nk; ++i) triPoints(tris_[j], keys_[keySet_[i]], &keyPts_[(size_t(j) * nk + i) * 4]);
    });
  }

  double motionSpread() const {
    double s = 0;
    for (uint32_t k : keySet_) {
      Vec3d m;
      for (const Vec3f& v : keys_[k]) m = m + toD(v);
      m = m * (1.0 / std::max<size_t>(1, keys_[k].size()));
      for (const Vec3f& v : keys_[k]) s += norm2(toD(v) - m);
    }
    return s;
  }

  // Fits every cluster to its triangles (those with mask[j] set, when given).
  Fits fit(const std::vector<uint8_t>* mask) const {
    const size_t nk = keySet_.size();
    tbb::combinable<std::vector<FitMoments>> acc([&] { return std::vector<FitMoments>(size_t(C_) * nk); });
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, T_, 1024), [&](const tbb::blocked_range<uint32_t>& r) {
      auto& m = acc.local();
      for (uint32_t j = r.begin(); j < r.end(); ++j) {
        if (mask && !(*mask)[j]) continue;
        const Vec3d* p = &restPts_[size_t(j) * 4];
        const Vec3d* x = &keyPts_[size_t(j) * nk * 4];
        for (size_t i = 0; i < nk; ++i)
          for (int v = 0; v < 4; ++v)
            m[size_t(assign_[j]) * nk + i].add(p[v], x[i * 4 + v], v == 3 ? kTipWeight : 1.0);
      }
    });
    std::vector<FitMoments> sum(size_t(C_) * nk);
    acc.combine_each([&](const std::vector<FitMoments>& m) {
      for (size_t i = 0; i < sum.size(); ++i) sum[i].add(m[i]);
    });
    Fits A(C_, std::vector<Affine3d>(nk));
    for (uint32_t c = 0; c < C_; ++c)
      for (size_t i = 0; i < nk; ++i) sum[size_t(c) * nk + i].solve(A[c][i]);
    return A;
  }

  // Residual of triangle j under cluster c's maps, stopping above `bound`.
  double residualOf(uint32_t j, const std::vector<Affine3d>& A, double bound = 1e300) const {
    const size_t nk = keySet_.size();
    const Vec3d* p = &restPts_[size_t(j) * 4];
    const Vec3d* x = &keyPts_[size_t(j) * nk * 4];
    double e = 0;
    for (size_t i = 0; i < nk; ++i) {
      for (int v = 0; v < 3; ++v) e += norm2(A[i].apply(p[v]) - x[i * 4 + v]);
      if (e > bound) return e;
    }
    return e;
  }

  double totalResidual(const Fits& A) {
    tbb::parallel_for(uint32_t(0), T_, [&](uint32_t j) { residual_[j] = residualOf(j, A[assign_[j]]); });
    return std::accumulate(residual_.begin(), residual_.end(), 0.0);
  }

  // Each triangle to the cluster of smallest residual; returns the total.
  double reassign(const Fits& A) {
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, T_, 256), [&](const tbb::blocked_range<uint32_t>& r) {
      for (uint32_t j = r.begin(); j < r.end(); ++j) {
        uint32_t best = assign_[j];
        double e = residualOf(j, A[best]);
        for (uint32_t c = 0; c < C_; ++c) {
          if (c == best) continue;
          const double ec = residualOf(j, A[c], e);
          if (ec < e) {
            e = ec;
            best = c;
          }
        }
        assign_[j] = best;
        residual_[j] = e;
      }
    });
    return std::accumulate(residual_.begin(), residual_.end(), 0.0);
  }

  // Drops empty clusters (renumbering).
  void compact() {
    std::vector<uint32_t> count(C_, 0), map(C_, 0);
    for (uint32_t a : assign_) ++count[a];
    uint32_t n = 0;
    for (uint32_t c = 0; c < C_; ++c) map[c] = count[c] ? n++ : 0;
    for (uint32_t& a : assign_) a = map[a];
    C_ = std::max(1u, n);
  }

  // Lloyd relaxation from the maps A.
  double lloyd(Fits A) {
    double E = reassign(A);
    compact();
    for (int it = 0; it < params_.maxLloyd; ++it) {
      A = fit(nullptr);
      const double En = reassign(A);
      compact();
      const bool done = !(E - En > params_.lloydTol * E);
      E = En;
      if (done) break;
    }
    return E;
  }

  // Triangles whose residual is at most their cluster's median.
  std::vector<uint8_t> bestHalf() const {
    std::vector<std::vector<double>> per(C_);
    for (uint32_t j = 0; j < T_; ++j) per[assign_[j]].push_back(residual_[j]);
    std::vector<double> median(C_, 0);
    for (uint32_t c = 0; c < C_; ++c)
      if (!per[c].empty()) {
        auto mid = per[c].begin() + per[c].size() / 2;
        std::nth_element(per[c].begin(), mid, per[c].end());
        median[c] = *mid;
      }
    std::vector<uint8_t> mask(T_);
    for (uint32_t j = 0; j < T_; ++j) mask[j] = residual_[j] <= median[assign_[j]];
    return mask;
  }

  // The triangle and those sharing a vertex with it.
  std::vector<uint32_t> neighbours(uint32_t j) const {
    std::vector<uint32_t> out{j};
    const Triangle& t = tris_[j];
    for (uint32_t i = 0; i < T_; ++i) {
      if (i == j) continue;
      const Triangle& u = tris_[i];
      for (uint32_t a : {u.v0, u.v1, u.v2})
        if (a == t.v0 || a == t.v1 || a == t.v2) {
          out.push_back(i);
          break;
        }
    }
    return out;
  }

  ClusterStep step(double E, Clock::time_point start) {
    const Fits A = fit(nullptr);
    ClusterStep s;
    s.clusters = C_;
    s.residual = E;
    s.fuzzyArea = fuzzyArea(A);
    s.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return s;
  }

  // Sum of the triangles' fuzzy-box areas in the rest frame.
  double fuzzyArea(const Fits& A) const {
    const size_t nk = keySet_.size();
    std::vector<std::vector<Affine3d>> inv(C_, std::vector<Affine3d>(nk));
    for (uint32_t c = 0; c < C_; ++c)
      for (size_t i = 0; i < nk; ++i)
        if (!A[c][i].inverse(inv[c][i])) inv[c][i] = Affine3d{};
    tbb::combinable<double> sum(0.0);
    tbb::parallel_for(uint32_t(0), T_, [&](uint32_t j) {
      Vec3d lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
      const Vec3d* x = &keyPts_[size_t(j) * nk * 4];
      for (size_t i = 0; i < nk; ++i)
        for (int v = 0; v < 3; ++v) {
          const Vec3d q = inv[assign_[j]][i].apply(x[i * 4 + v]);
          for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], q[a]);
            hi[a] = std::max(hi[a], q[a]);
          }
        }
      const Vec3d d = hi - lo;
      sum.local() += 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
    });
    return sum.combine(std::plus<double>());
  }

  // Composes each cluster's maps with its PCA frame of fuzzy positions.
  std::vector<std::vector<Affine3d>> withFrames(const Fits& A) const {
    const size_t nk = keySet_.size();
    std::vector<std::vector<Affine3d>> out(C_);
    for (uint32_t c = 0; c < C_; ++c) {
      std::vector<Affine3d> inv(nk);
      std::vector<uint8_t> ok(nk);
      for (size_t i = 0; i < nk; ++i) ok[i] = A[c][i].inverse(inv[i]);
      double w = 0;
      Vec3d mean;
      double cov[3][3] = {};
      for (uint32_t j = 0; j < T_; ++j) {
        if (assign_[j] != c) continue;
        const Vec3d* x = &keyPts_[size_t(j) * nk * 4];
        for (size_t i = 0; i < nk; ++i) {
          if (!ok[i]) continue;
          for (int v = 0; v < 3; ++v) {
            const Vec3d q = inv[i].apply(x[i * 4 + v]);
            w += 1;
            mean = mean + q;
            for (int a = 0; a < 3; ++a)
              for (int b = 0; b < 3; ++b) cov[a][b] += q[a] * q[b];
          }
        }
      }
      Affine3d frame;
      if (w > 0) {
        mean = mean * (1.0 / w);
        Mat3d C;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) C.m[a][b] = cov[a][b] / w - mean[a] * mean[b];
        Vec3d vals;
        symmetricEigen(C, frame.L, vals);
        if (frame.L.det() < 0)
          for (int r = 0; r < 3; ++r) frame.L.m[r][2] = -frame.L.m[r][2];
        frame.t = mean;
      }
      out[c].resize(nk);
      for (size_t i = 0; i < nk; ++i) out[c][i] = A[c][i] * frame;
    }
    return out;
  }

  std::span<const Triangle> tris_;
  const std::vector<std::vector<Vec3f>>& keys_;
  DecomposeParams params_;
  uint32_t T_;
  uint32_t C_ = 1;
  uint32_t rest_ = 0;
  double spread_ = 0;
  std::vector<uint32_t> keySet_;
  std::vector<uint32_t> assign_;
  std::vector<double> residual_;
  std::vector<Vec3d> restPts_, keyPts_;
};

}  // namespace

std::vector<uint32_t> connectedPieces(std::span<const Triangle> triangles, uint32_t numVertices, uint32_t& count) {
  std::vector<uint32_t> parent(numVertices);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (const Triangle& t : triangles) {
    const uint32_t a = find(t.v0), b = find(t.v1), c = find(t.v2);
    parent[b] = a;
    parent[find(c)] = find(a);
  }
  std::vector<uint32_t> id(numVertices, ~0u), out(triangles.size());
  count = 0;
  for (size_t j = 0; j < triangles.size(); ++j) {
    const uint32_t r = find(triangles[j].v0);
    if (id[r] == ~0u) id[r] = count++;
    out[j] = id[r];
  }
  return out;
}

std::vector<std::vector<Vec3f>> geometryKeys(const Geometry& g) {
  std::vector<std::vector<Vec3f>> keys(g.numSteps());
  for (uint32_t k = 0; k < g.numSteps(); ++k) {
    const VertexBuffer& b = g.vertices(k);
    keys[k].resize(b.count);
    for (size_t i = 0; i < b.count; ++i) keys[k][i] = b[i];
  }
  return keys;
}

Decomposition decomposeMotion(std::span<const Triangle> triangles, const std::vector<std::vector<Vec3f>>& keys,
                              const DecomposeParams& params) {
  if (triangles.empty() || keys.empty()) return {};
  return Decomposer(triangles, keys, params).run();
}

}  // namespace mbrt::detail
