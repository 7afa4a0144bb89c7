// SPDX-License-Identifier: MIT
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <stdexcept>
#include <thread>

#include "../support/ThreadSettings.h"
#include "bsdeform/contact/TriangleTree.h"

using namespace bsdeform;
using Eigen::Vector3d;
using Eigen::Vector3i;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Brute force, written differently from the tree's narrow phase (closestPointOnTriangle works
// with Voronoi regions): the projection on the plane when it falls inside, else the nearest of
// the three edge segments.
Vector3d closestOnSegment(const Vector3d& p, const Vector3d& x, const Vector3d& y) {
  const Vector3d d = y - x;
  const double t = std::clamp((p - x).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return x + t * d;
}

Vector3d closestOnTriangleBrute(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  const Vector3d n = (b - a).cross(c - a);
  const Vector3d proj = p - (p - a).dot(n) / n.squaredNorm() * n;
  if ((b - a).cross(proj - a).dot(n) >= 0 && (c - b).cross(proj - b).dot(n) >= 0 && (a - c).cross(proj - c).dot(n) >= 0)
    return proj;
  Vector3d best = closestOnSegment(p, a, b);
  for (const Vector3d& q : {closestOnSegment(p, b, c), closestOnSegment(p, c, a)})
    if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
  return best;
}

struct Brute {
  Vector3d point;
  double distance = kInf;
};

Brute bruteForce(const TriangleMesh& mesh, const Vector3d& p) {
  Brute r;
  for (const Vector3i& t : mesh.triangles) {
    const Vector3d q = closestOnTriangleBrute(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
    const double d = (q - p).norm();
    if (d < r.distance) r = {q, d};
  }
  return r;
}

// Orients every triangle of a mesh that is star-shaped around the origin so it is
// counter-clockwise seen from outside.
void orientOutward(TriangleMesh& mesh) {
  for (Vector3i& t : mesh.triangles) {
    const Vector3d& a = mesh.vertices[t[0]];
    const Vector3d n = (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a);
    if (n.dot(a + mesh.vertices[t[1]] + mesh.vertices[t[2]]) < 0) std::swap(t[1], t[2]);
  }
}

// Cube [-1, 1]^3, 12 triangles; the diagonals are chosen so that some corners have one triangle
// of one face and two of another (the angle weighting must not care, a plain average would).
TriangleMesh cube() {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  const int quads[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  for (int f = 0; f < 6; ++f) {
    const int* q = quads[f];
    if (f != 5) {
      m.triangles.emplace_back(q[0], q[1], q[2]);
      m.triangles.emplace_back(q[0], q[2], q[3]);
    } else {
      m.triangles.emplace_back(q[0], q[1], q[3]);
      m.triangles.emplace_back(q[1], q[2], q[3]);
    }
  }
  orientOutward(m);
  return m;
}

// Regular tetrahedron: face normals at -1/3 to each other, so a face normal of the triangle
// found gives the wrong side for some points near an edge or a vertex.
TriangleMesh tetrahedron() {
  TriangleMesh m;
  m.vertices = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  m.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
  orientOutward(m);
  return m;
}

TriangleMesh icosphere(int subdivisions) {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh m;
  for (int s1 : {-1, 1})
    for (int s2 : {-1, 1}) {
      m.vertices.emplace_back(0, s1, s2 * phi);
      m.vertices.emplace_back(s1, s2 * phi, 0);
      m.vertices.emplace_back(s2 * phi, 0, s1);
    }
  for (int i = 0; i < 12; ++i)  // the faces: triples at edge length 2
    for (int j = i + 1; j < 12; ++j)
      for (int k = j + 1; k < 12; ++k) {
        auto edge = [&](int a, int b) { return std::abs((m.vertices[a] - m.vertices[b]).norm() - 2.0) < 1e-9; };
        if (edge(i, j) && edge(j, k) && edge(i, k)) m.triangles.emplace_back(i, j, k);
      }
  for (auto& v : m.vertices) v.normalize();
  orientOutward(m);
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.vertices.push_back((m.vertices[a] + m.vertices[b]).normalized());
      return mid[key] = int(m.vertices.size()) - 1;
    };
    std::vector<Vector3i> next;
    for (const Vector3i& t : m.triangles) {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      next.emplace_back(t[0], ab, ca);
      next.emplace_back(t[1], bc, ab);
      next.emplace_back(t[2], ca, bc);
      next.emplace_back(ab, bc, ca);
    }
    m.triangles = next;
  }
  return m;
}

// Torus R = 1, r = 0.4, counter-clockwise seen from outside (du x dv points out): not convex.
TriangleMesh torus(int nu, int nv) {
  TriangleMesh m;
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * pi * i / nu, v = 2 * pi * j / nv;
      m.vertices.emplace_back((1 + 0.4 * std::cos(v)) * std::cos(u), (1 + 0.4 * std::cos(v)) * std::sin(u),
                              0.4 * std::sin(v));
    }
  auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      m.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      m.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return m;
}

// Triangles with random corners in the unit cube: intersecting, of every size and shape.
TriangleMesh randomSoup(int vertices, int triangles, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> pick(0, vertices - 1);
  TriangleMesh m;
  for (int i = 0; i < vertices; ++i) m.vertices.emplace_back(u(rng), u(rng), u(rng));
  while (int(m.triangles.size()) < triangles) {
    const Vector3i t(pick(rng), pick(rng), pick(rng));
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) m.triangles.push_back(t);
  }
  return m;
}

// Small triangles (sides up to `size`) scattered in the unit cube.
TriangleMesh randomSmallTriangles(int triangles, double size, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0), e(-size, size);
  TriangleMesh m;
  for (int t = 0; t < triangles; ++t) {
    const Vector3d c(u(rng), u(rng), u(rng));
    for (int k = 0; k < 3; ++k) m.vertices.push_back(c + Vector3d(e(rng), e(rng), e(rng)));
    m.triangles.emplace_back(3 * t, 3 * t + 1, 3 * t + 2);
  }
  return m;
}

Vector3d randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  return Vector3d(g(rng), g(rng), g(rng)).normalized();
}

// Inside a convex mesh: behind every face plane.
bool insideConvex(const TriangleMesh& m, const Vector3d& p) {
  for (const Vector3i& t : m.triangles) {
    const Vector3d& a = m.vertices[t[0]];
    if ((m.vertices[t[1]] - a).cross(m.vertices[t[2]] - a).dot(p - a) >= 0) return false;
  }
  return true;
}

// Inside any closed mesh: parity of the crossings of a ray in a fixed generic direction.
bool insideByParity(const TriangleMesh& m, const Vector3d& p) {
  const Vector3d dir = Vector3d(0.5377, 0.3313, 0.7746).normalized();
  int crossings = 0;
  for (const Vector3i& t : m.triangles) {
    const Vector3d a = m.vertices[t[0]], e1 = m.vertices[t[1]] - a, e2 = m.vertices[t[2]] - a;
    const Vector3d h = dir.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-300) continue;
    const Vector3d s = p - a;
    const double u = s.dot(h) / det;
    const Vector3d q = s.cross(e1);
    const double v = dir.dot(q) / det;
    const double dist = e2.dot(q) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && dist > 0) ++crossings;
  }
  return crossings % 2 == 1;
}

// The kind of feature a hit point lies on, found geometrically from the hit triangle.
enum class Feature { Face, Edge, Vertex };
Feature featureOf(const TriangleMesh& m, const ClosestHit& hit, double tol) {
  const Vector3i& t = m.triangles[hit.triangle];
  for (int k = 0; k < 3; ++k)
    if ((hit.point - m.vertices[t[k]]).norm() <= tol) return Feature::Vertex;
  for (int k = 0; k < 3; ++k)
    if ((hit.point - closestOnSegment(hit.point, m.vertices[t[k]], m.vertices[t[(k + 1) % 3]])).norm() <= tol)
      return Feature::Edge;
  return Feature::Face;
}

Vector3d faceNormal(const TriangleMesh& m, int triangle) {
  const Vector3i& t = m.triangles[triangle];
  return (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).normalized();
}

bool sameHit(const ClosestHit& a, const ClosestHit& b) {
  return a.point == b.point && a.normal == b.normal && a.distance == b.distance &&
         a.signedDistance == b.signedDistance && a.triangle == b.triangle;
}

}  // namespace

TEST_CASE("TriangleTree: closest point and distance equal brute force on random meshes", "[core]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  TriangleMesh noisySphere = icosphere(3);
  for (Vector3d& v : noisySphere.vertices) v = Vector3d(0.5, 0.5, 0.5) + v * (0.4 + 0.05 * u(rng));
  for (const TriangleMesh& mesh : {randomSoup(300, 500, rng), noisySphere}) {
    const TriangleTree tree(mesh);
    REQUIRE(tree.droppedTriangles() == 0);
    int wrongHit = 0, wrongDistance = 0, wrongPoint = 0, hits = 0;
    for (int i = 0; i < 3000; ++i) {
      const Vector3d q(u(rng), u(rng), u(rng));
      const Brute b = bruteForce(mesh, q);
      const double maxDistance = i % 2 ? kInf : 0.05;
      ClosestHit h;
      const bool found = tree.closest(q, maxDistance, h);
      if (found != (b.distance <= maxDistance)) {
        ++wrongHit;
        continue;
      }
      if (!found) continue;
      ++hits;
      if (std::abs(h.distance - b.distance) > 1e-12) ++wrongDistance;
      if ((h.point - b.point).norm() > 1e-10 || std::abs((h.point - q).norm() - h.distance) > 1e-12) ++wrongPoint;
    }
    INFO(mesh.triangles.size() << " triangles");
    CHECK(hits > 1500);
    CHECK(wrongHit == 0);
    CHECK(wrongDistance == 0);
    CHECK(wrongPoint == 0);
  }
}

TEST_CASE("TriangleTree: its Embree device leaves the kernels their threads, and a tree built on them answers the "
          "same bits",
          "[core]") {
  // Embree's TBB tasking holds the process's TBB parallelism to its devices' thread count while
  // they live: a device of one thread had kept every runParts() kernel on one thread in any
  // scene with an obstacle. Now the device takes the kernels' count.
  ThreadSettingsGuard guard;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  TriangleMesh sphere = icosphere(5);  // 20 480 triangles: large enough for a parallel build
  for (Vector3d& v : sphere.vertices) v = Vector3d(0.5, 0.5, 0.5) + 0.4 * v;
  bsdeform::setKernelThreads(2);
  const int available = bsdeform::effectiveKernelThreads();  // 2, or 1 on a machine of one CPU
  bsdeform::setKernelThreads(1);
  const TriangleTree one(sphere);
  bsdeform::setKernelThreads(2);
  const TriangleTree two(sphere);
  CHECK(bsdeform::effectiveKernelThreads() == available);
  // the same answers, bit for bit, also on the edges and vertices (ties between triangles)
  std::vector<Vector3d> queries;
  for (int i = 0; i < 2000; ++i) queries.emplace_back(u(rng), u(rng), u(rng));
  const Vector3d centre(0.5, 0.5, 0.5);
  for (const Vector3d& v : sphere.vertices) queries.push_back(centre + 1.3 * (v - centre));
  int differ = 0;
  for (const Vector3d& q : queries) {
    ClosestHit a, b;
    REQUIRE(one.closest(q, kInf, a));
    REQUIRE(two.closest(q, kInf, b));
    differ += !(a.point == b.point && a.normal == b.normal && a.distance == b.distance);
  }
  CHECK(differ == 0);
}

TEST_CASE("TriangleTree: maxDistance is respected to the last digits", "[core]") {
  std::mt19937 rng(11);
  const TriangleMesh mesh = torus(40, 20);
  const TriangleTree tree(mesh);
  int missedJustInside = 0, foundJustOutside = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vector3d q = 1.6 * Vector3d(std::uniform_real_distribution<double>(-1, 1)(rng),
                                      std::uniform_real_distribution<double>(-1, 1)(rng),
                                      std::uniform_real_distribution<double>(-0.5, 0.5)(rng));
    const double d = bruteForce(mesh, q).distance;
    ClosestHit h;
    if (!tree.closest(q, d * (1 + 1e-9), h)) ++missedJustInside;
    if (tree.closest(q, d * (1 - 1e-9), h)) ++foundJustOutside;
  }
  // Faces parallel to the hierarchy's boxes, where the box distance is the triangle distance:
  // the float boxes must not cull a triangle whose double distance is within maxDistance.
  std::uniform_real_distribution<double> height(0.01, 0.9), along(0.1, 0.4);
  for (double level : {0.1, 0.3, 0.7, 1.3}) {
    TriangleMesh grid;  // 40 x 40 squares of side 1/40
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; j <= 40; ++j) grid.vertices.emplace_back(i / 40.0, j / 40.0, level);
    for (int i = 0; i < 40; ++i)
      for (int j = 0; j < 40; ++j) {
        grid.triangles.emplace_back(i * 41 + j, (i + 1) * 41 + j, (i + 1) * 41 + j + 1);
        grid.triangles.emplace_back(i * 41 + j, (i + 1) * 41 + j + 1, i * 41 + j + 1);
      }
    const TriangleTree flat(grid);
    for (int i = 0; i < 500; ++i) {
      const Vector3d q(along(rng), 0.5 + along(rng), level + 0.1 * height(rng));
      const double d = q.z() - level;
      ClosestHit h;
      if (!flat.closest(q, d * (1 + 1e-9), h)) ++missedJustInside;
      if (flat.closest(q, d * (1 - 1e-9), h)) ++foundJustOutside;
    }
  }
  CHECK(missedJustInside == 0);
  CHECK(foundJustOutside == 0);

  ClosestHit h;
  const Vector3d onSurface = mesh.vertices[5];
  CHECK(tree.closest(onSurface, 0.0, h));  // distance 0 is within 0
  CHECK(h.distance == 0.0);
  CHECK_FALSE(tree.closest(Vector3d(0, 0, 3), 1.0, h));
  CHECK_FALSE(tree.closest(Vector3d(0, 0, 3), -1.0, h));
  CHECK_FALSE(tree.closest(Vector3d(0, 0, 3), std::nan(""), h));
  CHECK_FALSE(tree.closest(Vector3d(std::nan(""), 0, 0), kInf, h));
  CHECK(tree.closest(Vector3d(0, 0, 3), kInf, h));
  CHECK(h.distance == Approx(bruteForce(mesh, Vector3d(0, 0, 3)).distance).epsilon(1e-12));

  const TriangleTree empty(TriangleMesh{});
  CHECK(empty.triangleCount() == 0);
  CHECK_FALSE(empty.closest(Vector3d::Zero(), kInf, h));
}

TEST_CASE("TriangleTree: a hint changes the cost of a query, never its answer", "[core]") {
  // Hints as CollisionForce gives them (the answer for a nearby point), wrong ones (any
  // triangle) and invalid ones (out of range), with finite and infinite search radii: the
  // closest point, normal and distances are those of the query without a hint, and the hint
  // comes back as the triangle found (-1 when none).
  std::mt19937 rng(5);
  const TriangleMesh mesh = torus(60, 30);
  const TriangleTree tree(mesh);
  std::uniform_real_distribution<double> u(-1.6, 1.6), small(-0.02, 0.02);
  std::uniform_int_distribution<int> anyTriangle(0, tree.triangleCount() - 1);
  int differ = 0, hintNotAnswer = 0, found = 0, missing = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vector3d q(u(rng), u(rng), 0.3 * u(rng));
    const double maxDistance = i % 3 == 0 ? kInf : 0.15;
    ClosestHit plain;
    const bool hasPlain = tree.closest(q, maxDistance, plain);
    ClosestHit nearby;
    int previous = -1;
    tree.closest(q + Vector3d(small(rng), small(rng), small(rng)), kInf, nearby, previous);
    for (int hint : {previous, anyTriangle(rng), tree.triangleCount() + 3, -7}) {
      ClosestHit h;
      int io = hint;
      const bool has = tree.closest(q, maxDistance, h, io);
      if (has != hasPlain) {
        ++missing;
        continue;
      }
      if (!has) {
        if (io != -1) ++hintNotAnswer;
        continue;
      }
      ++found;
      if (io != h.triangle) ++hintNotAnswer;
      // equal distance; the point and normal too unless two triangles tie exactly
      if (h.distance != plain.distance || h.signedDistance != plain.signedDistance) ++differ;
      if (h.triangle == plain.triangle && !sameHit(h, plain)) ++differ;
    }
  }
  CHECK(found > 4000);
  CHECK(missing == 0);
  CHECK(differ == 0);
  CHECK(hintNotAnswer == 0);
}

TEST_CASE("TriangleTree: inside and outside of a closed icosphere, at faces, edges and vertices", "[core]") {
  const TriangleMesh mesh = icosphere(2);
  const TriangleTree tree(mesh);
  std::mt19937 rng(3);
  int wrong = 0, tested = 0;
  // Random directions at several depths, against the exact test for a convex polyhedron.
  for (double offset : {-0.3, -0.02, -1e-4, 1e-4, 0.02, 0.3})
    for (int i = 0; i < 500; ++i) {
      const Vector3d q = (1 + offset) * randomUnit(rng);
      ClosestHit h;
      REQUIRE(tree.closest(q, 1.0, h));
      ++tested;
      if ((h.signedDistance < 0) != insideConvex(mesh, q) || std::abs(h.signedDistance) != h.distance) ++wrong;
    }
  // Outside in every vertex's normal cone (closest point: the vertex) and every edge's (the edge).
  int atVertex = 0, atEdge = 0;
  for (const Vector3d& v : mesh.vertices) {
    ClosestHit h;
    REQUIRE(tree.closest(v + 0.01 * v.normalized(), 1.0, h));
    atVertex += (h.point - v).norm() < 1e-12;
    wrong += !(h.signedDistance > 0);
  }
  for (int t = 0; t < int(mesh.triangles.size()); ++t)
    for (int k = 0; k < 3; ++k) {
      const Vector3d a = mesh.vertices[mesh.triangles[t][k]], b = mesh.vertices[mesh.triangles[t][(k + 1) % 3]];
      // the neighbour across this edge
      for (int s = 0; s < int(mesh.triangles.size()); ++s) {
        if (s == t) continue;
        const Vector3i& o = mesh.triangles[s];
        const int shared = (mesh.vertices[o[0]] == a || mesh.vertices[o[0]] == b) +
                           (mesh.vertices[o[1]] == a || mesh.vertices[o[1]] == b) +
                           (mesh.vertices[o[2]] == a || mesh.vertices[o[2]] == b);
        if (shared != 2) continue;
        const Vector3d q = 0.5 * (a + b) + 0.01 * (faceNormal(mesh, t) + faceNormal(mesh, s)).normalized();
        ClosestHit h;
        REQUIRE(tree.closest(q, 1.0, h));
        atEdge += (h.point - 0.5 * (a + b)).norm() < 1e-12;
        wrong += !(h.signedDistance > 0);
      }
    }
  CHECK(tested == 3000);
  CHECK(atVertex == int(mesh.vertices.size()));
  CHECK(atEdge == 3 * int(mesh.triangles.size()));
  CHECK(wrong == 0);
}

TEST_CASE("TriangleTree: a cube's corners and edges have the angle-weighted pseudo-normals", "[core]") {
  const TriangleMesh mesh = cube();
  const TriangleTree tree(mesh);
  int unevenCorners = 0;  // corners with 4 or 5 triangles: one or two from different faces
  for (int v = 0; v < 8; ++v) {
    int n = 0;
    for (const Vector3i& t : mesh.triangles) n += (t.array() == v).any();
    unevenCorners += n == 4 || n == 5;
  }
  REQUIRE(unevenCorners > 0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> positive(0.05, 1.0);
  int wrongSign = 0, notAtCorner = 0, wrongNormal = 0;
  for (const Vector3d& c : mesh.vertices) {
    // Outside in the corner's octant: the corner is closest; its pseudo-normal is the diagonal
    // whether the corner has one or two triangles of each face.
    for (int i = 0; i < 50; ++i) {
      const Vector3d q = c + 0.05 * c.cwiseProduct(Vector3d(positive(rng), positive(rng), positive(rng)));
      ClosestHit h;
      REQUIRE(tree.closest(q, 1.0, h));
      notAtCorner += h.point != c;
      wrongNormal += (h.normal - c / std::sqrt(3.0)).norm() > 1e-12;
      wrongSign += !(h.signedDistance > 0);
    }
    // Inside near the corner.
    for (int i = 0; i < 50; ++i) {
      const Vector3d q = c - 0.05 * c.cwiseProduct(Vector3d(positive(rng), positive(rng), positive(rng)));
      ClosestHit h;
      REQUIRE(tree.closest(q, 1.0, h));
      wrongSign += !(h.signedDistance < 0);
    }
  }
  // Outside near the 12 edges, in the edge's quarter: normal (n1 + n2) / sqrt 2.
  int edges = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int s1 : {-1, 1})
      for (int s2 : {-1, 1}) {
        Vector3d n1 = Vector3d::Zero(), n2 = Vector3d::Zero();
        n1[(axis + 1) % 3] = s1;
        n2[(axis + 2) % 3] = s2;
        for (int i = 0; i < 20; ++i) {
          Vector3d onEdge = n1 + n2;
          onEdge[axis] = std::uniform_real_distribution<double>(-0.9, 0.9)(rng);
          const Vector3d q = onEdge + 0.03 * (positive(rng) * n1 + positive(rng) * n2);
          ClosestHit h;
          REQUIRE(tree.closest(q, 1.0, h));
          wrongNormal += (h.normal - (n1 + n2) / std::sqrt(2.0)).norm() > 1e-12;
          wrongSign += !(h.signedDistance > 0);
          notAtCorner += (h.point - onEdge).norm() > 1e-12;  // closest point: on the edge
          ++edges;
        }
      }
  // Random points in and around the cube.
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int i = 0; i < 3000; ++i) {
    const Vector3d q(u(rng), u(rng), u(rng));
    ClosestHit h;
    REQUIRE(tree.closest(q, 10.0, h));
    const bool inside = q.cwiseAbs().maxCoeff() < 1.0;
    wrongSign += (h.signedDistance < 0) != inside;
  }
  CHECK(edges == 240);
  CHECK(notAtCorner == 0);
  CHECK(wrongNormal == 0);
  CHECK(wrongSign == 0);
}

TEST_CASE("TriangleTree: signs at sharp edges and vertices where a face normal would fail", "[core]") {
  const TriangleMesh mesh = tetrahedron();
  const TriangleTree tree(mesh);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> w(0.0, 1.0);
  int wrong = 0, faceNormalWrong = 0, queries = 0;
  auto check = [&](const Vector3d& q) {
    ClosestHit h;
    REQUIRE(tree.closest(q, 10.0, h));
    ++queries;
    const bool inside = insideConvex(mesh, q);
    wrong += (h.signedDistance < 0) != inside;
    faceNormalWrong += ((q - h.point).dot(faceNormal(mesh, h.triangle)) < 0) != inside;
  };
  for (int t = 0; t < 4; ++t)
    for (int s = t + 1; s < 4; ++s) {  // every pair of faces shares an edge
      const Vector3d n1 = faceNormal(mesh, t), n2 = faceNormal(mesh, s);
      std::vector<int> common;
      for (int a : {0, 1, 2})
        for (int b : {0, 1, 2})
          if (mesh.triangles[t][a] == mesh.triangles[s][b]) common.push_back(mesh.triangles[t][a]);
      REQUIRE(common.size() == 2);
      for (int i = 0; i < 100; ++i) {
        const double x = w(rng);
        const Vector3d onEdge = x * mesh.vertices[common[0]] + (1 - x) * mesh.vertices[common[1]];
        check(onEdge + 0.05 * (w(rng) * n1 + w(rng) * n2));
      }
    }
  for (int v = 0; v < 4; ++v) {
    Vector3d n[3];
    int k = 0;
    for (int t = 0; t < 4; ++t)
      if ((mesh.triangles[t].array() == v).any()) n[k++] = faceNormal(mesh, t);
    for (int i = 0; i < 100; ++i) check(mesh.vertices[v] + 0.05 * (w(rng) * n[0] + w(rng) * n[1] + w(rng) * n[2]));
  }
  CHECK(queries == 1000);
  CHECK(wrong == 0);
  CHECK(faceNormalWrong > 50);  // these points do tell a pseudo-normal from a face normal
}

TEST_CASE("TriangleTree: inside and outside of non-convex meshes match ray parity", "[core]") {
  // A torus (saddle vertices on the inner side) and an icosphere with dents and spikes (vertices
  // concave seen from outside, where inside points have a vertex or an edge as closest feature).
  TriangleMesh bumpy = icosphere(2);
  for (size_t v = 0; v < bumpy.vertices.size(); ++v) bumpy.vertices[v] *= v % 7 == 0 ? 0.8 : v % 11 == 0 ? 1.2 : 1.0;
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> unit(0.0, 1.0), offset(-0.04, 0.04), jitter(-0.002, 0.002);
  std::map<std::pair<bool, Feature>, int> seen;
  int wrong = 0, tested = 0;
  for (const TriangleMesh& mesh : {torus(24, 12), bumpy}) {
    const TriangleTree tree(mesh);
    auto check = [&](const Vector3d& q) {
      ClosestHit h;
      if (!tree.closest(q, 0.05, h)) return;
      ++tested;
      const bool inside = insideByParity(mesh, q);
      wrong += (h.signedDistance < 0) != inside;
      ++seen[{inside, featureOf(mesh, h, 1e-12)}];
    };
    std::uniform_int_distribution<int> pick(0, int(mesh.triangles.size()) - 1);
    for (int i = 0; i < 3000; ++i) {  // near a random point of a random triangle
      const int t = pick(rng);
      double a = unit(rng), b = unit(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const Vector3i& f = mesh.triangles[t];
      const Vector3d p = mesh.vertices[f[0]] + a * (mesh.vertices[f[1]] - mesh.vertices[f[0]]) +
                         b * (mesh.vertices[f[2]] - mesh.vertices[f[0]]);
      check(p + offset(rng) * faceNormal(mesh, t));
    }
    for (const Vector3d& v : mesh.vertices)  // just off every vertex, along the direction from the origin
      for (double offset : {-0.02, -0.005, 0.005, 0.02})
        check(v + offset * v.normalized() + Vector3d(jitter(rng), jitter(rng), jitter(rng)));
  }
  CHECK(tested > 6000);
  CHECK(wrong == 0);
  // Both sides were probed at faces, edges and vertices.
  for (bool inside : {false, true})
    for (Feature f : {Feature::Face, Feature::Edge, Feature::Vertex}) {
      INFO("inside " << inside << ", feature " << int(f) << " (0 face, 1 edge, 2 vertex)");
      CHECK(seen[{inside, f}] >= 10);
    }
}

TEST_CASE("TriangleTree: degenerate, non-finite and badly indexed triangles are dropped and counted", "[core]") {
  TriangleMesh mesh = cube();  // 8 vertices, 12 triangles, size 2 sqrt 3
  const double nan = std::nan("");
  mesh.vertices.emplace_back(nan, 0, 0);                       // 8
  mesh.vertices.emplace_back(0, kInf, 0);                      // 9
  mesh.vertices.emplace_back(0.5, 0.5, 0.5);                   // 10
  mesh.vertices.emplace_back(0.5 + 1e-7, 0.5 + 2e-7, 0.5);     // 11
  mesh.vertices.emplace_back(0.5 + 2e-7, 0.5 + 4e-7, 0.5);     // 12: collinear with 10, 11
  mesh.vertices.emplace_back(0.5, 0.5 + 1e-7, 0.5 + 1e-7);     // 13: 10, 11, 13 tiny (area ~1e-14)
  mesh.vertices.emplace_back(0.5, 0.5 + 2e-3, 0.5);            // 14: 10, 11, 14 thin but kept
  const std::vector<Vector3i> bad = {{0, 1, 8}, {2, 9, 3}, {0, 1, 15}, {-1, 2, 3}, {10, 11, 12}, {10, 10, 11},
                                     {10, 11, 13}};
  const Vector3i thin(10, 14, 11);
  const auto cubeTriangles = mesh.triangles;
  for (const Vector3i& t : bad) mesh.triangles.push_back(t);
  mesh.triangles.push_back(thin);
  const TriangleTree tree(mesh);
  CHECK(tree.droppedTriangles() == int(bad.size()));
  CHECK(tree.triangleCount() == 13);
  REQUIRE(tree.mesh().triangles.size() == 13);
  for (int t = 0; t < 12; ++t) CHECK(tree.mesh().triangles[t] == cubeTriangles[t]);
  CHECK(tree.mesh().triangles[12] == thin);
  CHECK(tree.mesh().vertices.size() == mesh.vertices.size());

  // Answers come from the kept triangles only and are finite.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  const TriangleMesh kept{mesh.vertices, tree.mesh().triangles};
  int badAnswers = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vector3d q(u(rng), u(rng), u(rng));
    ClosestHit h;
    REQUIRE(tree.closest(q, kInf, h));
    if (!h.point.allFinite() || !h.normal.allFinite() || std::abs(h.distance - bruteForce(kept, q).distance) > 1e-12)
      ++badAnswers;
  }
  CHECK(badAnswers == 0);

  // Nothing left: every query misses.
  TriangleMesh allBad;
  allBad.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {nan, 1, 0}};
  allBad.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}};
  const TriangleTree none(allBad);
  ClosestHit h;
  CHECK(none.droppedTriangles() == 3);
  CHECK(none.triangleCount() == 0);
  CHECK_FALSE(none.closest(Vector3d::Zero(), kInf, h));
}

TEST_CASE("TriangleTree: a triangle soup signs like the indexed mesh", "[core]") {
  // Coin's SoCallbackAction gives three vertices of their own per triangle.
  const TriangleMesh indexed = cube();
  TriangleMesh soup;
  for (const Vector3i& t : indexed.triangles) {
    const int base = int(soup.vertices.size());
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(indexed.vertices[t[k]]);
    soup.triangles.emplace_back(base, base + 1, base + 2);
  }
  const TriangleTree a(indexed), b(soup);
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> u(-1.3, 1.3);
  int differ = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vector3d q(u(rng), u(rng), u(rng));
    ClosestHit ha, hb;
    REQUIRE(a.closest(q, kInf, ha));
    REQUIRE(b.closest(q, kInf, hb));
    differ += (ha.point - hb.point).norm() > 1e-12 || (ha.normal - hb.normal).norm() > 1e-12 ||
              ha.signedDistance != hb.signedDistance;
  }
  CHECK(differ == 0);
}

TEST_CASE("TriangleTree: update() answers as a tree built on the moved mesh", "[core]") {
  std::mt19937 rng(23);
  std::normal_distribution<double> g(0.0, 0.02);
  std::uniform_real_distribution<double> u(-1.6, 1.6);
  TriangleMesh mesh = torus(30, 15);
  TriangleTree tree(mesh);
  std::vector<Vector3d> queries;
  for (int i = 0; i < 3000; ++i) queries.emplace_back(u(rng), u(rng), 0.4 * u(rng));
  std::vector<ClosestHit> before(queries.size());
  for (size_t i = 0; i < queries.size(); ++i) REQUIRE(tree.closest(queries[i], kInf, before[i]));

  auto compare = [&](const TriangleTree& updated, const TriangleTree& fresh, int& changed) {
    int differ = 0;
    changed = 0;
    for (size_t i = 0; i < queries.size(); ++i) {
      ClosestHit a, b;
      const bool fa = updated.closest(queries[i], 0.3, a), fb = fresh.closest(queries[i], 0.3, b);
      if (fa != fb) {
        ++differ;
        continue;
      }
      if (!fa) continue;
      // The triangle may differ where two are equally close (a shared edge or vertex).
      differ += (a.point - b.point).norm() > 1e-12 || (a.normal - b.normal).norm() > 1e-12 ||
                std::abs(a.signedDistance - b.signedDistance) > 1e-12;
      changed += (a.point - before[i].point).norm() > 1e-6;
    }
    return differ;
  };

  // 1. Every vertex moves (a wobble and a shift): refit.
  for (Vector3d& v : mesh.vertices) v += Vector3d(g(rng), g(rng), g(rng)) + Vector3d(0.1, -0.05, 0.02);
  tree.update(mesh.vertices);
  {
    const TriangleTree fresh(mesh);
    int changed = 0;
    CHECK(compare(tree, fresh, changed) == 0);
    CHECK(changed > 1000);  // the update did move the answers
    CHECK(tree.droppedTriangles() == 0);
  }
  // 2. A vertex collapses onto its neighbour (two triangles degenerate) and another becomes
  // NaN: the kept set changes, as in a tree built from scratch.
  mesh.vertices[7] = mesh.vertices[8];
  mesh.vertices[100] = Vector3d(std::nan(""), 0, 0);
  tree.update(mesh.vertices);
  {
    const TriangleTree fresh(mesh);
    int changed = 0;
    CHECK(tree.droppedTriangles() == fresh.droppedTriangles());
    CHECK(tree.droppedTriangles() == 2 + 6);
    CHECK(tree.triangleCount() == fresh.triangleCount());
    CHECK(compare(tree, fresh, changed) == 0);
  }
  CHECK_THROWS_AS(tree.update(std::vector<Vector3d>(3, Vector3d::Zero())), std::invalid_argument);
}

TEST_CASE("TriangleTree: concurrent queries from two threads give the serial answers", "[core]") {
  std::mt19937 rng(29);
  const TriangleMesh mesh = randomSmallTriangles(4000, 0.05, rng);
  const TriangleTree tree(mesh);
  std::uniform_real_distribution<double> u(-0.1, 1.1);
  std::vector<Vector3d> queries;
  for (int i = 0; i < 20000; ++i) queries.emplace_back(u(rng), u(rng), u(rng));
  auto run = [&](std::vector<ClosestHit>& out, std::vector<char>& found) {
    out.assign(queries.size(), ClosestHit());
    found.assign(queries.size(), 0);
    for (size_t i = 0; i < queries.size(); ++i) found[i] = tree.closest(queries[i], 0.02, out[i]);
  };
  std::vector<ClosestHit> serial, a, b;
  std::vector<char> fs, fa, fb;
  run(serial, fs);
  std::thread ta([&] { run(a, fa); }), tb([&] { run(b, fb); });
  ta.join();
  tb.join();
  int hits = 0, differ = 0;
  for (size_t i = 0; i < queries.size(); ++i) {
    hits += fs[i];
    differ += fa[i] != fs[i] || fb[i] != fs[i] || (fs[i] && (!sameHit(a[i], serial[i]) || !sameHit(b[i], serial[i])));
  }
  CHECK(hits > 2000);
  CHECK(hits < 19000);
  CHECK(differ == 0);
}
