// SPDX-License-Identifier: MIT
#include "bsdeform/spline/Tessellation.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace bsdeform {

int tessellationSegments(float complexity, int spans) {
  const float c = std::max(0.0f, std::min(1.0f, complexity));
  const double perSpan = spans * (0.5 + 2.0 * c);
  const int wanted = static_cast<int>(std::lround(std::max(perSpan, 64.0 * c)));
  const int cap = static_cast<int>(64 + 448 * c);
  return std::max(4, std::min(wanted, cap));
}

void tessellate(const SplineSpace& sp, const ControlNet& net, int segU, int segV, SurfaceGrid& g) {
  assert(segU >= 1 && segV >= 1 && net.rows() == sp.netSize());
  const int cols = sp.netCols(), n1 = sp.degreeU(), n2 = sp.degreeV();
  const int nvU = segU + 1, nvV = segV + 1;
  g.vertices.resize(size_t(nvU) * nvV * 3);
  g.normals.resize(g.vertices.size());
  g.texCoords.resize(size_t(nvU) * nvV * 2);
  // v-direction bases are the same for every row of vertices
  std::vector<LocalBasis>& bv = g.scratch.basesV;
  bv.resize(size_t(nvV));
  for (int j = 0; j < nvV; ++j) sp.basisV().evaluate(double(j) / segV, 1, bv[j]);
  std::vector<double>& c0 = g.scratch.rowSum;
  std::vector<double>& c1 = g.scratch.rowDerivative;
  c0.resize(size_t(cols) * 3);
  c1.resize(size_t(cols) * 3);
  std::vector<char>& degenerate = g.scratch.degenerate;
  degenerate.resize(size_t(nvU) * nvV);
  std::vector<double>& rawNormal = g.scratch.rawNormal;
  rawNormal.resize(size_t(nvU) * nvV * 3);
  LocalBasis bu;
  double scale = 0.0;
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int i = 0; i < nvU; ++i) {
    const double u = double(i) / segU;
    sp.basisU().evaluate(u, 1, bu);
    std::fill(c0.begin(), c0.end(), 0.0);
    std::fill(c1.begin(), c1.end(), 0.0);
    for (int a = 0; a < bu.count; ++a) {
      const double* row = net.data() + size_t(bu.first + a + n1) * cols * 3;
      const double b0 = bu.d[0][a], b1 = bu.d[1][a];
      for (int m = 0; m < cols * 3; ++m) {
        c0[m] += b0 * row[m];
        c1[m] += b1 * row[m];
      }
    }
    for (int j = 0; j < nvV; ++j) {
      double p[3] = {0, 0, 0}, du[3] = {0, 0, 0}, dv[3] = {0, 0, 0};
      const LocalBasis& b = bv[j];
      for (int k = 0; k < b.count; ++k) {
        const size_t m = size_t(b.first + k + n2) * 3;
        for (int c = 0; c < 3; ++c) {
          p[c] += b.d[0][k] * c0[m + c];
          du[c] += b.d[0][k] * c1[m + c];
          dv[c] += b.d[1][k] * c0[m + c];
        }
      }
      const size_t vi = size_t(i) * nvV + j;
      double* n = &rawNormal[vi * 3];
      n[0] = du[1] * dv[2] - du[2] * dv[1];
      n[1] = du[2] * dv[0] - du[0] * dv[2];
      n[2] = du[0] * dv[1] - du[1] * dv[0];
      scale = std::max(scale, std::sqrt(du[0] * du[0] + du[1] * du[1] + du[2] * du[2]) *
                                  std::sqrt(dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]));
      for (int c = 0; c < 3; ++c) {
        const float x = float(p[c]);
        g.vertices[vi * 3 + c] = x;
        lo[c] = std::min(lo[c], x);
        hi[c] = std::max(hi[c], x);
      }
      g.texCoords[vi * 2] = float(u);
      g.texCoords[vi * 2 + 1] = float(double(j) / segV);
    }
  }
  // Normals; a vanishing du x dv (relative to the largest |du||dv|) takes the mean normal of
  // the nearest row in v with a regular normal.
  auto length = [&](size_t vi) { return std::sqrt(rawNormal[vi * 3] * rawNormal[vi * 3] + rawNormal[vi * 3 + 1] * rawNormal[vi * 3 + 1] +
                                                  rawNormal[vi * 3 + 2] * rawNormal[vi * 3 + 2]); };
  const double tiny = 1e-9 * scale;
  for (size_t vi = 0; vi < degenerate.size(); ++vi) degenerate[vi] = !(length(vi) > tiny);
  for (int i = 0; i < nvU; ++i)
    for (int j = 0; j < nvV; ++j) {
      const size_t vi = size_t(i) * nvV + j;
      double n[3] = {rawNormal[vi * 3], rawNormal[vi * 3 + 1], rawNormal[vi * 3 + 2]};
      if (degenerate[vi]) {
        n[0] = n[1] = n[2] = 0.0;
        for (int step = 1; step < nvV && n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0; ++step)
          for (int jj : {j - step, j + step}) {
            if (jj < 0 || jj >= nvV) continue;
            for (int ii = 0; ii < nvU; ++ii) {
              const size_t w = size_t(ii) * nvV + jj;
              if (degenerate[w]) continue;
              const double len = length(w);
              for (int c = 0; c < 3; ++c) n[c] += rawNormal[w * 3 + c] / len;
            }
            if (n[0] != 0.0 || n[1] != 0.0 || n[2] != 0.0) break;
          }
      }
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      for (int c = 0; c < 3; ++c) g.normals[vi * 3 + c] = float(len > 0 ? n[c] / len : (c == 2 ? 1.0 : 0.0));
    }
  if (g.segU != segU || g.segV != segV || g.indices.empty()) {
    g.indices.clear();
    g.indices.reserve(size_t(segU) * segV * 6);
    for (int i = 0; i < segU; ++i)
      for (int j = 0; j < segV; ++j) {
        const unsigned a = unsigned(i * nvV + j), b = unsigned((i + 1) * nvV + j);
        g.indices.insert(g.indices.end(), {a, b, b + 1, a, b + 1, a + 1});
      }
  }
  g.segU = segU;
  g.segV = segV;
  for (int c = 0; c < 3; ++c) {
    g.boundsMin[c] = lo[c];
    g.boundsMax[c] = hi[c];
  }
}

Eigen::Vector2d closestParameter(const SplineSpace& space, const ControlNet& net, const SurfaceGrid& grid,
                                 const Eigen::Vector3d& target) {
  size_t best = 0;
  double bestDist = INFINITY;
  for (size_t i = 0; i + 2 < grid.vertices.size(); i += 3) {
    const double d = (Eigen::Vector3d(grid.vertices[i], grid.vertices[i + 1], grid.vertices[i + 2]) - target).squaredNorm();
    if (d < bestDist) bestDist = d, best = i / 3;
  }
  double uu = grid.texCoords.empty() ? 0.5 : grid.texCoords[best * 2];
  double vv = grid.texCoords.empty() ? 0.5 : grid.texCoords[best * 2 + 1];
  auto keep = [](double x, bool periodic) { return periodic ? x - std::floor(x) : std::clamp(x, 0.0, 1.0); };
  for (int iter = 0; iter < 12; ++iter) {
    const SurfacePoint sp = space.evaluate(net, uu, vv, 1);
    const Eigen::Vector3d r = sp.position - target;
    const double a = sp.du.dot(sp.du), b = sp.du.dot(sp.dv), c = sp.dv.dot(sp.dv);
    const double g1 = sp.du.dot(r), g2 = sp.dv.dot(r), det = a * c - b * b;
    if (!(det > 1e-300)) break;
    const double du = -(c * g1 - b * g2) / det, dv = -(a * g2 - b * g1) / det;
    uu = keep(uu + du, space.periodicU());
    vv = keep(vv + dv, space.periodicV());
    if (std::abs(du) + std::abs(dv) < 1e-10) break;
  }
  return Eigen::Vector2d(uu, vv);
}

}  // namespace bsdeform
