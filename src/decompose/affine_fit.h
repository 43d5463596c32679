// Small double-precision linear algebra for motion decomposition: 3x4
// affine maps, least-squares fits from accumulated moments, 3x3 inverses
// and norms, and a symmetric 3x3 eigen solver (Jacobi) for PCA frames.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "core/vec3d.h"
#include "mbrt/math.h"

namespace mbrt::detail {

// 3x3 matrix, row-major.
struct Mat3d {
  double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3d operator*(Vec3d v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  Mat3d operator*(const Mat3d& b) const {
    Mat3d r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r.m[i][j] = m[i][0] * b.m[0][j] + m[i][1] * b.m[1][j] + m[i][2] * b.m[2][j];
    return r;
  }
  Mat3d operator-(const Mat3d& b) const {
    Mat3d r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r.m[i][j] = m[i][j] - b.m[i][j];
    return r;
  }
  double det() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
  // Induced infinity norm (largest absolute row sum).
  double normInf() const {
    double r = 0;
    for (int i = 0; i < 3; ++i) r = std::max(r, std::fabs(m[i][0]) + std::fabs(m[i][1]) + std::fabs(m[i][2]));
    return r;
  }
  // False when singular (relative to the matrix scale).
  bool inverse(Mat3d& out) const {
    const double d = det();
    const double s = normInf();
    if (!(std::fabs(d) > 1e-12 * s * s * s) || !std::isfinite(d)) return false;
    const double id = 1.0 / d;
    out.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * id;
    out.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * id;
    out.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * id;
    out.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * id;
    out.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * id;
    out.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * id;
    out.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * id;
    out.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * id;
    out.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * id;
    return true;
  }
};

// x -> L x + t.
struct Affine3d {
  Mat3d L;
  Vec3d t;
  Vec3d apply(Vec3d p) const { return L * p + t; }
  Affine3d operator*(const Affine3d& b) const { return {L * b.L, L * b.t + t}; }
  bool inverse(Affine3d& out) const {
    if (!L.inverse(out.L)) return false;
    out.t = (out.L * t) * -1.0;
    return true;
  }
  Affine3f toFloat() const {
    Affine3f a;
    a.vx = {float(L.m[0][0]), float(L.m[1][0]), float(L.m[2][0])};
    a.vy = {float(L.m[0][1]), float(L.m[1][1]), float(L.m[2][1])};
    a.vz = {float(L.m[0][2]), float(L.m[1][2]), float(L.m[2][2])};
    a.p = {float(t.x), float(t.y), float(t.z)};
    return a;
  }
  static Affine3d fromFloat(const Affine3f& a) {
    Affine3d r;
    const Vec3f c[3] = {a.vx, a.vy, a.vz};
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) r.L.m[i][j] = c[j][i];
    r.t = toD(a.p);
    return r;
  }
};
inline Affine3d lerp(const Affine3d& a, const Affine3d& b, double f) {
  Affine3d r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.L.m[i][j] = a.L.m[i][j] * (1.0 - f) + b.L.m[i][j] * f;
  r.t = lerp(a.t, b.t, f);
  return r;
}

// Moments for the least-squares fit of x ~ A p over point pairs (p, x):
// centred sums, so that the fit is well conditioned far from the origin.
struct FitMoments {
  double w = 0;
  Vec3d sp, sx;
  double spp[3][3] = {};  // sum p p^T
  double sxp[3][3] = {};  // sum x p^T
  void add(Vec3d p, Vec3d x, double weight = 1.0) {
    w += weight;
    sp = sp + p * weight;
    sx = sx + x * weight;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        spp[i][j] += weight * p[i] * p[j];
        sxp[i][j] += weight * x[i] * p[j];
      }
  }
  void add(const FitMoments& o) {
    w += o.w;
    sp = sp + o.sp;
    sx = sx + o.sx;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        spp[i][j] += o.spp[i][j];
        sxp[i][j] += o.sxp[i][j];
      }
  }
  // The least-squares affine map (ridge-regularized towards the identity in
  // directions the points do not constrain). False when there are no points.
  bool solve(Affine3d& out) const {
    if (!(w > 0)) return false;
    const Vec3d mp = sp * (1.0 / w), mx = sx * (1.0 / w);
    Mat3d C, X;  // covariance of p, cross-covariance x p^T
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        C.m[i][j] = spp[i][j] - w * mp[i] * mp[j];
        X.m[i][j] = sxp[i][j] - w * mx[i] * mp[j];
      }
    const double tr = C.m[0][0] + C.m[1][1] + C.m[2][2];
    const double lambda = 1e-9 * tr + 1e-300;
    for (int i = 0; i < 3; ++i) {
      C.m[i][i] += lambda;
      X.m[i][i] += lambda;  // pulls unconstrained directions to identity
    }
    Mat3d Ci;
    if (!C.inverse(Ci)) {
      out.L = Mat3d{};
      out.t = mx - mp;
      return true;
    }
    out.L = X * Ci;
    out.t = mx - out.L * mp;
    return true;
  }
};

// Eigenvectors (columns of `vecs`) of a symmetric 3x3 matrix, by Jacobi
// rotations, sorted by decreasing eigenvalue.
inline void symmetricEigen(Mat3d a, Mat3d& vecs, Vec3d& vals) {
  Mat3d v;
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = std::fabs(a.m[0][1]) + std::fabs(a.m[0][2]) + std::fabs(a.m[1][2]);
    if (off < 1e-300) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (std::fabs(a.m[p][q]) < 1e-300) continue;
        const double theta = (a.m[q][q] - a.m[p][p]) / (2.0 * a.m[p][q]);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k) {  // a = J^T a J
          const double akp = a.m[k][p], akq = a.m[k][q];
          a.m[k][p] = c * akp - s * akq;
          a.m[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {
          const double apk = a.m[p][k], aqk = a.m[q][k];
          a.m[p][k] = c * apk - s * aqk;
          a.m[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = v.m[k][p], vkq = v.m[k][q];
          v.m[k][p] = c * vkp - s * vkq;
          v.m[k][q] = s * vkp + c * vkq;
        }
      }
  }
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int i, int j) { return a.m[i][i] > a.m[j][j]; });
  for (int c = 0; c < 3; ++c) {
    vals[c] = a.m[order[c]][order[c]];
    for (int r = 0; r < 3; ++r) vecs.m[r][c] = v.m[r][order[c]];
  }
}

}  // namespace mbrt::detail
