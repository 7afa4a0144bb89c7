// SPDX-License-Identifier: MIT
// Closest-point queries on obstacle meshes (issue 9, item 4): the candidate libraries on the
// contact workload, single thread.
//   ClosestBuild/<index>/<mesh>/<triangles>   building the hierarchy from a mesh
//   ClosestUpdate/<index>/<mesh>/<triangles>  all vertices moved (1 % of the size), then refit or rebuild
//   ClosestQuery/<index>/<mesh>/<triangles>   36864 (192^2) queries placed like a cloth lying on the
//                                             mesh: half within maxDistance = 0.02 size, half farther
// Meshes: a closed torus (R = 1, r = 0.4, size 2.8) and a bumpy height field over the unit
// square (size 1), about 1k, 10k and 100k triangles.
// Indices: Embree (default MEDIUM build, update = rebuild), EmbreeRefit (dynamic LOW scene,
// REFIT geometry, update = refit), TriangleTree (bsdeform's class: EmbreeRefit plus the
// pseudo-normals and the sign), CGAL (AABB_tree, hint at maxDistance: no KD-tree), CGALkd
// (AABB_tree + KD-tree hint, accelerate_distance_queries), CGALsphere (do_intersect with the
// maxDistance sphere, then the KD-tree hinted query). CGAL has no refit: its update rebuilds.
// The CGAL rows need -DBSDEFORM_BENCH_CGAL=ON (bench/CMakeLists.txt).
// Every query benchmark first checks its answers against the Embree index, which is checked
// against brute force on a subset.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <string>

#include "closest_index.h"

namespace {

using bsdeform::TriangleMesh;
using closestbench::ClosestIndex;
using closestbench::Hit;
using Eigen::Vector3d;
using Eigen::Vector3i;

constexpr double kPi = 3.14159265358979323846;
constexpr int kClothSide = 192;  // 36864 query points
constexpr double kMaxDistanceOfSize = 0.02;

enum class MeshKind { Torus, HeightField };

struct Scenario {
  TriangleMesh mesh;
  double size = 1.0;
  std::vector<Vector3d> queries;
  std::vector<Vector3d> movedA, movedB;  // two deformed states for update()
  double maxDistance() const { return kMaxDistanceOfSize * size; }
};

// The first half of the cloth's rows rest on the surface (offset 0.1..0.9 maxDistance along the
// normal), the other half hover above it (2..6 maxDistance), in grid order like the quadrature
// points of one surface.
double clothOffset(int row, std::mt19937& rng, double maxDistance) {
  std::uniform_real_distribution<double> resting(0.1, 0.9), hovering(2.0, 6.0);
  return (row < kClothSide / 2 ? resting(rng) : hovering(rng)) * maxDistance;
}

void addDeformations(Scenario& s) {
  const double a = 0.01 * s.size, w = 2.0 * 2.0 * kPi / s.size;
  for (const Vector3d& v : s.mesh.vertices) {
    s.movedA.push_back(v + a * Vector3d(std::sin(w * v.y()), std::sin(w * v.z()), std::sin(w * v.x())));
    s.movedB.push_back(v + a * Vector3d(std::cos(w * v.z()), std::cos(w * v.x()), std::cos(w * v.y())));
  }
}

Scenario torus(int triangles) {
  // 2 nu nv triangles with nu = 2 nv.
  const int nv = std::max(3, int(std::lround(std::sqrt(triangles / 4.0)))), nu = 2 * nv;
  const double R = 1.0, r = 0.4;
  Scenario s;
  s.size = 2.0 * (R + r);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2.0 * kPi * i / nu, v = 2.0 * kPi * j / nv;
      s.mesh.vertices.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
                                   r * std::sin(v));
    }
  auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {  // counter-clockwise seen from outside (du x dv points out)
      s.mesh.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      s.mesh.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  // The cloth covers the top of half the ring: u in [0, pi], v in [0, pi].
  std::mt19937 rng(1);
  for (int a = 0; a < kClothSide; ++a)
    for (int b = 0; b < kClothSide; ++b) {
      const double u = kPi * (a + 0.5) / kClothSide, v = kPi * (b + 0.5) / kClothSide;
      const Vector3d n(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
      const Vector3d p((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
      s.queries.push_back(p + clothOffset(a, rng, s.maxDistance()) * n);
    }
  addDeformations(s);
  return s;
}

double bumps(double x, double y) { return 0.04 * std::sin(6.0 * kPi * x) * std::sin(6.0 * kPi * y); }

Scenario heightField(int triangles) {
  const int n = std::max(2, int(std::lround(std::sqrt(triangles / 2.0))));  // n^2 cells
  Scenario s;
  s.size = 1.0;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = double(i) / n, y = double(j) / n;
      s.mesh.vertices.emplace_back(x, y, bumps(x, y));
    }
  auto id = [&](int i, int j) { return i * (n + 1) + j; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {  // counter-clockwise seen from +z
      s.mesh.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      s.mesh.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  std::mt19937 rng(2);
  for (int a = 0; a < kClothSide; ++a)
    for (int b = 0; b < kClothSide; ++b) {
      const double x = 0.02 + 0.96 * (a + 0.5) / kClothSide, y = 0.02 + 0.96 * (b + 0.5) / kClothSide;
      s.queries.emplace_back(x, y, bumps(x, y) + clothOffset(a, rng, s.maxDistance()));
    }
  addDeformations(s);
  return s;
}

const Scenario& scenario(MeshKind kind, int triangles) {
  static std::map<std::pair<int, int>, Scenario> cache;
  const auto key = std::make_pair(int(kind), triangles);
  auto it = cache.find(key);
  if (it == cache.end())
    it = cache.emplace(key, kind == MeshKind::Torus ? torus(triangles) : heightField(triangles)).first;
  return it->second;
}

// The shipped class (Embree, refit on update, plus the pseudo-normals and the sign).
class TreeIndex final : public ClosestIndex {
 public:
  void build(const TriangleMesh& mesh) override { m_tree = std::make_unique<bsdeform::TriangleTree>(mesh); }
  void update(const std::vector<Vector3d>& vertices) override { m_tree->update(vertices); }
  bool closest(const Vector3d& q, double maxDistance, Hit& hit) const override {
    bsdeform::ClosestHit h;
    if (!m_tree->closest(q, maxDistance, h)) return false;
    hit.point = h.point;
    hit.distance = h.distance;
    hit.triangle = h.triangle;
    return true;
  }

 private:
  std::unique_ptr<bsdeform::TriangleTree> m_tree;
};

using Factory = std::function<std::unique_ptr<ClosestIndex>()>;

void setMeshCounters(benchmark::State& state, const Scenario& s) {
  state.counters["triangles"] = double(s.mesh.triangles.size());
}

void runBuild(benchmark::State& state, MeshKind kind, int triangles, const Factory& make) {
  const Scenario& s = scenario(kind, triangles);
  std::unique_ptr<ClosestIndex> index = make();
  for (auto _ : state) index->build(s.mesh);
  setMeshCounters(state, s);
}

void runUpdate(benchmark::State& state, MeshKind kind, int triangles, const Factory& make) {
  const Scenario& s = scenario(kind, triangles);
  std::unique_ptr<ClosestIndex> index = make();
  index->build(s.mesh);
  bool flip = false;
  for (auto _ : state) {
    index->update(flip ? s.movedA : s.movedB);
    flip = !flip;
  }
  setMeshCounters(state, s);
}

// Brute force over all triangles, for the check of the reference index.
bool bruteForce(const Scenario& s, const Vector3d& q, double maxDistance, double& distance) {
  distance = std::numeric_limits<double>::infinity();
  for (const Vector3i& t : s.mesh.triangles) {
    const auto& v = s.mesh.vertices;
    distance = std::min(distance, (q - bsdeform::closestPointOnTriangle(q, v[t[0]], v[t[1]], v[t[2]]).point).norm());
  }
  return distance <= maxDistance;
}

// Compares `index` with the Embree reference (itself checked by brute force on every 97th
// query): hit or not, and the distance to 1e-12 of the size. Returns the number of mismatches.
int mismatches(const Scenario& s, const ClosestIndex& index) {
  static std::map<const Scenario*, std::vector<std::pair<bool, double>>> reference;
  const double maxDistance = s.maxDistance(), tol = 1e-12 * s.size;
  auto it = reference.find(&s);
  int bad = 0;
  if (it == reference.end()) {
    auto embree = closestbench::makeEmbreeIndex(false);
    embree->build(s.mesh);
    std::vector<std::pair<bool, double>> answers;
    for (size_t i = 0; i < s.queries.size(); ++i) {
      Hit h;
      const bool found = embree->closest(s.queries[i], maxDistance, h);
      answers.emplace_back(found, found ? h.distance : 0.0);
      double d;
      if (i % 97 != 0) continue;
      if (bruteForce(s, s.queries[i], maxDistance, d) != found || (found && std::abs(d - h.distance) > tol)) ++bad;
    }
    if (bad) return bad;
    it = reference.emplace(&s, std::move(answers)).first;
  }
  for (size_t i = 0; i < s.queries.size(); ++i) {
    Hit h;
    const bool found = index.closest(s.queries[i], maxDistance, h);
    if (found != it->second[i].first || (found && std::abs(h.distance - it->second[i].second) > tol)) ++bad;
  }
  return bad;
}

void runQuery(benchmark::State& state, MeshKind kind, int triangles, const Factory& make) {
  const Scenario& s = scenario(kind, triangles);
  std::unique_ptr<ClosestIndex> index = make();
  index->build(s.mesh);
  if (const int bad = mismatches(s, *index)) {
    state.SkipWithError(("answers differ from the reference: " + std::to_string(bad)).c_str());
    return;
  }
  const double maxDistance = s.maxDistance();
  long hits = 0;
  for (auto _ : state) {
    hits = 0;
    Hit h;
    for (const Vector3d& q : s.queries) hits += index->closest(q, maxDistance, h);
    benchmark::DoNotOptimize(hits);
  }
  setMeshCounters(state, s);
  state.counters["hit fraction"] = double(hits) / double(s.queries.size());
  state.counters["queries/s"] =
      benchmark::Counter(double(s.queries.size()), benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

int main(int argc, char** argv) {
  using closestbench::CgalQuery;
  const std::vector<std::pair<std::string, MeshKind>> meshes = {{"torus", MeshKind::Torus},
                                                                {"heightfield", MeshKind::HeightField}};
  struct Candidate {
    std::string name;
    Factory make;
    bool build, update, query;
  };
  std::vector<Candidate> candidates = {
      {"Embree", [] { return closestbench::makeEmbreeIndex(false); }, true, true, true},
      {"EmbreeRefit", [] { return closestbench::makeEmbreeIndex(true); }, true, true, true},
      {"TriangleTree", [] { return std::make_unique<TreeIndex>(); }, true, true, true},
  };
  if (closestbench::haveCgal()) {
    candidates.push_back({"CGAL", [] { return closestbench::makeCgalIndex(CgalQuery::SphereHint); }, true, true, true});
    candidates.push_back({"CGALkd", [] { return closestbench::makeCgalIndex(CgalQuery::KdHint); }, true, true, true});
    candidates.push_back(
        {"CGALsphere", [] { return closestbench::makeCgalIndex(CgalQuery::SphereTest); }, false, false, true});
  }
  for (const char* what : {"ClosestBuild", "ClosestUpdate", "ClosestQuery"})
    for (const auto& [meshName, kind] : meshes)
      for (int triangles : {1000, 10000, 100000})
        for (const Candidate& c : candidates) {
          const std::string name = std::string(what) + "/" + c.name + "/" + meshName + "/" + std::to_string(triangles);
          const std::string w = what;
          auto* run = w == "ClosestBuild" ? (c.build ? runBuild : nullptr)
                      : w == "ClosestUpdate" ? (c.update ? runUpdate : nullptr)
                                             : (c.query ? runQuery : nullptr);
          if (run)
            benchmark::RegisterBenchmark(name.c_str(), run, kind, triangles, c.make)->Unit(benchmark::kMillisecond);
        }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
