// SPDX-License-Identifier: MIT
#include "bsdeform/MeshExport.h"

#include <Inventor/SoPath.h>
#include <Inventor/SoPrimitiveVertex.h>
#include <Inventor/actions/SoCallbackAction.h>
#include <Inventor/actions/SoSearchAction.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <unordered_map>

#include "bsdeform/AtomicWrite.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

namespace {

struct MeshBuilder {
  SurfaceMesh& mesh;
  struct Key {
    float v[8];
    bool operator==(const Key& o) const { return std::memcmp(v, o.v, sizeof v) == 0; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::size_t h = 0;
      for (float x : k.v) {
        std::uint32_t bits;
        std::memcpy(&bits, &x, 4);
        h = h * 1000003u ^ bits;
      }
      return h;
    }
  };
  std::unordered_map<Key, int, KeyHash> index;

  int vertex(const SbVec3f& pos, const SbVec3f& normal, const SbVec2f& t) {
    const Key key{{pos[0], pos[1], pos[2], normal[0], normal[1], normal[2], t[0], t[1]}};
    const auto it = index.find(key);
    if (it != index.end()) return it->second;
    const int i = int(mesh.points.size());
    index.emplace(key, i);
    mesh.points.push_back(pos);
    mesh.normals.push_back(normal);
    mesh.uv.push_back(t);
    return i;
  }
};

void collectTriangle(void* data, SoCallbackAction* action, const SoPrimitiveVertex* a, const SoPrimitiveVertex* b,
                     const SoPrimitiveVertex* c) {
  auto* builder = static_cast<MeshBuilder*>(data);
  const SbMatrix& m = action->getModelMatrix();
  SbMatrix normalMatrix = m.inverse().transpose();
  for (const SoPrimitiveVertex* v : {a, b, c}) {
    SbVec3f p, n;
    m.multVecMatrix(v->getPoint(), p);
    normalMatrix.multDirMatrix(v->getNormal(), n);
    n.normalize();
    builder->mesh.triangles.push_back(builder->vertex(p, n, SbVec2f(v->getTextureCoords()[0], v->getTextureCoords()[1])));
  }
}

std::string joinedNames(const std::vector<SurfaceMesh>& meshes) {
  std::string names;
  for (const SurfaceMesh& m : meshes) names += (names.empty() ? "" : ", ") + m.name;
  return names;
}

std::string objText(const std::vector<SurfaceMesh>& meshes, const std::string& producer) {
  std::size_t vertices = 0, triangles = 0;
  for (const SurfaceMesh& m : meshes) vertices += m.points.size(), triangles += m.triangles.size() / 3;
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out.precision(9);
  out << "# " << joinedNames(meshes) << ", exported by " << producer << " (world coordinates): " << vertices
      << " vertices, " << triangles << " triangles\n";
  std::size_t offset = 1;  // OBJ indices count from 1 across the whole file
  for (const SurfaceMesh& m : meshes) {
    std::string object = m.name;
    std::replace(object.begin(), object.end(), ' ', '_');
    out << "o " << object << '\n';
    for (const SbVec3f& p : m.points) out << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (const SbVec2f& t : m.uv) out << "vt " << t[0] << ' ' << t[1] << '\n';
    for (const SbVec3f& n : m.normals) out << "vn " << n[0] << ' ' << n[1] << ' ' << n[2] << '\n';
    for (std::size_t i = 0; i + 2 < m.triangles.size(); i += 3) {
      out << 'f';
      for (int k = 0; k < 3; ++k) {
        const std::size_t v = std::size_t(m.triangles[i + k]) + offset;  // position, (u, v) and normal share it
        out << ' ' << v << '/' << v << '/' << v;
      }
      out << '\n';
    }
    offset += m.points.size();
  }
  return out.str();
}

// Binary STL: an 80-byte header, the triangle count, 50 bytes per triangle (little-endian, as
// is this machine).
std::string stlBytes(const std::vector<SurfaceMesh>& meshes, const std::string& producer) {
  std::uint32_t count = 0;
  for (const SurfaceMesh& m : meshes) count += std::uint32_t(m.triangles.size() / 3);
  std::string bytes(80, ' ');
  const std::string title = producer + " " + joinedNames(meshes);
  std::memcpy(&bytes[0], title.data(), std::min<std::size_t>(80, title.size()));
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  bytes.reserve(84 + std::size_t(count) * 50);
  for (const SurfaceMesh& m : meshes) {
    for (std::size_t i = 0; i + 2 < m.triangles.size(); i += 3) {
      const SbVec3f& a = m.points[std::size_t(m.triangles[i])];
      const SbVec3f& b = m.points[std::size_t(m.triangles[i + 1])];
      const SbVec3f& c = m.points[std::size_t(m.triangles[i + 2])];
      SbVec3f n = (b - a).cross(c - a);
      n.normalize();
      float rec[12] = {n[0], n[1], n[2]};
      for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 3; ++d) rec[3 + 3 * k + d] = m.points[std::size_t(m.triangles[i + k])][d];
      bytes.append(reinterpret_cast<const char*>(rec), sizeof rec);
      bytes.append(2, '\0');  // attribute byte count
    }
  }
  return bytes;
}

}  // namespace

SurfaceMesh surfaceMesh(SoPath* path, const std::string& name) {
  SurfaceMesh mesh;
  mesh.name = name;
  MeshBuilder builder{mesh, {}};
  SoCallbackAction ca;
  ca.addTriangleCallback(SoBSplineDeformSurface::getClassTypeId(), collectTriangle, &builder);
  ca.apply(path);
  return mesh;
}

bool surfaceMesh(SoNode* root, SoBSplineDeformSurface* surface, const std::string& name, SurfaceMesh& mesh,
                 std::string& error) {
  if (!root || !surface) {
    error = "no surface to export";
    return false;
  }
  SoSearchAction sa;
  sa.setNode(surface);
  sa.apply(root);
  if (!sa.getPath()) {
    error = "the surface is not in the scene";
    return false;
  }
  SoPath* path = sa.getPath()->copy();
  path->ref();
  mesh = surfaceMesh(path, name);
  path->unref();
  return true;
}

bool writeMesh(const std::vector<SurfaceMesh>& meshes, const std::string& path, const std::string& producer,
               std::string& error) {
  const std::size_t slash = path.rfind('/'), dot = path.rfind('.');
  std::string ext = dot == std::string::npos || (slash != std::string::npos && dot < slash) ? std::string() : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext != "obj" && ext != "stl") {
    error = path + ": unknown mesh format '" + ext + "' (use .obj or .stl)";
    return false;
  }
  if (meshes.empty()) {
    error = path + ": no surface to export";
    return false;
  }
  const std::string bytes = ext == "obj" ? objText(meshes, producer) : stlBytes(meshes, producer);
  return writeFileAtomically(path, bytes.data(), bytes.size(), error);
}

bool exportMesh(SoNode* root, const std::vector<SoBSplineDeformSurface*>& surfaces, const std::vector<std::string>& names,
                const std::string& path, const std::string& producer, std::string& error) {
  std::vector<SurfaceMesh> meshes(surfaces.size());
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    std::string why;
    if (!surfaceMesh(root, surfaces[i], i < names.size() ? names[i] : std::string(), meshes[i], why)) {
      error = path + ": " + why;
      return false;
    }
  }
  return writeMesh(meshes, path, producer, error);
}

}  // namespace bsdeform
