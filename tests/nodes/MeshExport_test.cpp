// SPDX-License-Identifier: MIT
// Mesh export (bsdeform/MeshExport.h): the files hold exactly the triangles the surface draws,
// read back to the same vertices, and a failed write keeps the previous file.
#include <Inventor/nodes/SoSeparator.h>
#include <sys/resource.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <dirent.h>
#include <fstream>
#include <sstream>

#include "NodesTestUtil.h"
#include "bsdeform/MeshExport.h"
#include "bsdeform/SceneReader.h"
#include "bsdeform/SoBSplineDeformSurface.h"

using namespace bsdeform;

namespace {
// Two surfaces (default complexity: 32 x 32 segments, 33 x 33 grid points, 2048 triangles each),
// the second moved by a Translation that the export applies.
const char* kScene = R"IV(#Inventor V2.1 ascii
Separator {
  DEF Plate SoBSplineDeformSurface { on FALSE }
  Translation { translation 0 0 5 }
  SoBSplineDeformSurface { on FALSE }
}
)IV";
constexpr int kVertices = 33 * 33, kTriangles = 2 * 32 * 32;

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

std::string tempDir() {
  char tmpl[] = "/tmp/bsdeform-mesh-XXXXXX";
  REQUIRE(mkdtemp(tmpl));
  return tmpl;
}

int filesIn(const std::string& dir) {
  int n = 0;
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* e = readdir(d)) n += e->d_name[0] != '.';
    closedir(d);
  }
  return n;
}

std::vector<SurfaceMesh> meshesOf(SoNode* root) {
  std::vector<SurfaceMesh> meshes;
  int i = 0;
  for (SoBSplineDeformSurface* s : sceneSurfaces(root)) {
    SurfaceMesh m;
    std::string error;
    REQUIRE(surfaceMesh(root, s, "surface" + std::to_string(i++), m, error));
    meshes.push_back(m);
  }
  return meshes;
}
}  // namespace

TEST_CASE("MeshExport: OBJ and STL hold the triangles the surfaces draw and read back", "[nodes]") {
  SoSeparator* root = testutil::read(kScene);
  REQUIRE(root);
  const std::vector<SurfaceMesh> meshes = meshesOf(root);
  REQUIRE(meshes.size() == 2);
  for (const SurfaceMesh& m : meshes) {
    CHECK(m.points.size() == std::size_t(kVertices));  // shared vertices: one per grid point
    CHECK(m.normals.size() == m.points.size());
    CHECK(m.uv.size() == m.points.size());
    CHECK(m.triangles.size() == std::size_t(3 * kTriangles));
  }
  CHECK(meshes[1].points[0][2] == Approx(meshes[0].points[0][2] + 5.0f));  // world coordinates
  const std::string dir = tempDir();

  // OBJ: one object per surface, indices counting across the file, the same vertices back
  const std::string obj = dir + "/mesh.OBJ";
  std::string error;
  REQUIRE(writeMesh(meshes, obj, "bsdeform-test", error));
  std::istringstream in(slurp(obj));
  std::string line;
  std::getline(in, line);
  CHECK(line == "# surface0, surface1, exported by bsdeform-test (world coordinates): 2178 vertices, 4096 triangles");
  std::vector<std::string> objects;
  std::vector<SbVec3f> v;
  int vt = 0, vn = 0, faces = 0;
  std::size_t maxIndex = 0;
  while (std::getline(in, line)) {
    std::istringstream l(line);
    std::string tag;
    l >> tag;
    if (tag == "o") objects.push_back(line.substr(2));
    else if (tag == "v") {
      float x, y, z;
      l >> x >> y >> z;
      v.emplace_back(x, y, z);
    } else if (tag == "vt") ++vt;
    else if (tag == "vn") ++vn;
    else if (tag == "f") {
      ++faces;
      std::string corner;
      while (l >> corner) maxIndex = std::max(maxIndex, std::size_t(std::stoul(corner)));
    }
  }
  CHECK(objects == std::vector<std::string>{"surface0", "surface1"});
  CHECK(v.size() == std::size_t(2 * kVertices));
  CHECK(vt == 2 * kVertices);
  CHECK(vn == 2 * kVertices);
  CHECK(faces == 2 * kTriangles);
  CHECK(maxIndex == v.size());
  float worst = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const SurfaceMesh& m = meshes[i / kVertices];
    worst = std::max(worst, (v[i] - m.points[i % kVertices]).length());
  }
  CHECK(worst < 1e-6f);

  // STL: all triangles, their corners the mesh's
  const std::string stl = dir + "/mesh.stl";
  REQUIRE(writeMesh(meshes, stl, "bsdeform-test", error));
  const std::string bytes = slurp(stl);
  REQUIRE(bytes.size() == 84 + std::size_t(2 * kTriangles) * 50);
  CHECK(bytes.compare(0, 36, "bsdeform-test surface0, surface1    ") == 0);
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  CHECK(count == std::uint32_t(2 * kTriangles));
  float rec[12];
  std::memcpy(rec, bytes.data() + 84 + std::size_t(kTriangles) * 50, sizeof rec);  // the second surface's first
  const SbVec3f& corner = meshes[1].points[std::size_t(meshes[1].triangles[0])];
  CHECK(SbVec3f(rec[3], rec[4], rec[5]) == corner);
  CHECK(std::abs(SbVec3f(rec[0], rec[1], rec[2]).length() - 1.0f) < 1e-5f);
  std::remove(obj.c_str());
  std::remove(stl.c_str());
  rmdir(dir.c_str());
  root->unref();
}

TEST_CASE("MeshExport: a failed write keeps the previous file and names the file and the problem", "[nodes]") {
  SoSeparator* root = testutil::read(kScene);
  REQUIRE(root);
  const std::vector<SurfaceMesh> meshes = meshesOf(root);
  const std::string dir = tempDir();
  std::string error;
  // an unknown format, no surface, a folder that does not exist: nothing written
  CHECK_FALSE(writeMesh(meshes, dir + "/mesh.ply", "t", error));
  CHECK(error == dir + "/mesh.ply: unknown mesh format 'ply' (use .obj or .stl)");
  CHECK_FALSE(writeMesh({}, dir + "/mesh.obj", "t", error));
  CHECK(error == dir + "/mesh.obj: no surface to export");
  CHECK_FALSE(writeMesh(meshes, dir + "/missing/mesh.obj", "t", error));
  CHECK(error == "cannot write '" + dir + "/missing/mesh.obj': No such file or directory");
  CHECK(filesIn(dir) == 0);
  // the write fails part-way (a file size limit: works as root too): the old file stays
  for (const char* name : {"mesh.obj", "mesh.stl"}) {
    const std::string path = dir + "/" + name;
    std::ofstream(path) << "the user's file\n";
    rlimit old{};
    REQUIRE(getrlimit(RLIMIT_FSIZE, &old) == 0);
    const auto oldHandler = std::signal(SIGXFSZ, SIG_IGN);
    rlimit small = old;
    small.rlim_cur = 4096;
    REQUIRE(setrlimit(RLIMIT_FSIZE, &small) == 0);
    const bool written = writeMesh(meshes, path, "t", error);
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, oldHandler);
    INFO(error);
    CHECK_FALSE(written);
    CHECK(error == "cannot write '" + path + "': File too large");
    CHECK(slurp(path) == "the user's file\n");
    CHECK(filesIn(dir) == 1);  // no temporary file left
    std::remove(path.c_str());
  }
  rmdir(dir.c_str());
  root->unref();
}
