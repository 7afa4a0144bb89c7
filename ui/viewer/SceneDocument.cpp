// SPDX-License-Identifier: MIT
#include "SceneDocument.h"

#include <Inventor/SoDB.h>
#include <Inventor/SoPrimitiveVertex.h>
#include <Inventor/SbViewportRegion.h>
#include <Inventor/actions/SoCallbackAction.h>
#include <Inventor/actions/SoGetMatrixAction.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/nodes/SoSeparator.h>

#include <QFile>
#include <QFileInfo>
#include <QTextStream>
#include <cstdint>
#include <cstring>
#include <unordered_map>

#include "AtomicFile.h"
#include "bsdeform/SceneReader.h"
#include "bsdeform/SceneText.h"
#include "bsdeform/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {


SceneDocument::SceneDocument() = default;

SceneDocument::~SceneDocument() = default;

void SceneDocument::adopt(SoSeparator* root, const QString& path) {
  m_root.reset(root);
  m_path = path;
  scan();
}

void SceneDocument::rescan() {
  if (m_root) scan();
}

void SceneDocument::scan() {
  m_surfaces.clear();
  m_forceFields.clear();
  for (SoBSplineDeformSurface* s : sceneSurfaces(m_root.get())) {
    s->setScene(m_root.get());  // COLLISION forces find their obstacles here
    m_surfaces << s;
    for (int k = 0; k < s->forces.getNum(); ++k) {
      SoEngine* e = s->forces[k];
      if (e && e->isOfType(SoForceField::getClassTypeId()) && !m_forceFields.contains(static_cast<SoForceField*>(e)))
        m_forceFields << static_cast<SoForceField*>(e);
    }
  }
}

bool SceneDocument::load(const QString& path, QString& error) {
  if (!QFileInfo(path).isFile()) {
    error = QStringLiteral("%1: no such file").arg(path);
    return false;
  }
  std::string why;  // the guarded reader (docs/reliability.md)
  SoSeparator* root = readSceneFile(QFile::encodeName(path).toStdString(), why);
  if (!root) {
    error = QStringLiteral("%1 could not be read:\n%2").arg(path, QString::fromStdString(why));
    return false;
  }
  adopt(root, path);
  return true;
}

bool SceneDocument::loadFromText(const QByteArray& text, const QString& name, QString& error) {
  std::string why;
  SoSeparator* root = readSceneText(text.constData(), std::size_t(text.size()), name.toStdString(), why);
  if (!root) {
    error = QStringLiteral("%1 could not be read:\n%2").arg(name, QString::fromStdString(why));
    return false;
  }
  adopt(root, QString());
  return true;
}

QByteArray SceneDocument::toText() const {
  if (!m_root) return QByteArray();
  return QByteArray::fromStdString(sceneToText(m_root.get()));
}

bool SceneDocument::writeTo(const TextSink& sink) const {
  if (!m_root) return false;
  return writeSceneText(m_root.get(), sink);
}

bool SceneDocument::save(const QString& path, QString& error) const {
  // streamed into the temporary file: the text is never held in memory
  return saveFileAtomically(
      path,
      [this](QIODevice& device) {
        return writeTo([&device](const char* data, std::size_t size) { return device.write(data, qint64(size)) == qint64(size); });
      },
      error);
}

QString SceneDocument::nameOf(SoBSplineDeformSurface* s) const {
  const SbName n = s->getName();
  return n.getLength() ? QString::fromUtf8(n.getString()) : QStringLiteral("Surface %1").arg(m_surfaces.indexOf(s) + 1);
}

QString SceneDocument::nameOf(SoForceField* f) const {
  const SbName n = f->getName();
  return n.getLength() ? QString::fromUtf8(n.getString()) : QStringLiteral("Force %1").arg(m_forceFields.indexOf(f) + 1);
}

namespace {
// The triangles a surface draws, with shared vertices: generatePrimitives gives each grid point
// to every triangle around it with bit-identical position, normal and (u, v), so equal vertices
// are one (a periodic seam keeps two vertices with different (u, v), as a UV seam should).
struct Mesh {
  QVector<SbVec3f> p, n;
  QVector<SbVec2f> uv;
  QVector<int> triangles;  // three vertex indices each
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
    const int i = p.size();
    index.emplace(key, i);
    p << pos;
    n << normal;
    uv << t;
    return i;
  }
};

void collectTriangle(void* data, SoCallbackAction* action, const SoPrimitiveVertex* a, const SoPrimitiveVertex* b,
                     const SoPrimitiveVertex* c) {
  auto* mesh = static_cast<Mesh*>(data);
  const SbMatrix& m = action->getModelMatrix();
  SbMatrix normalMatrix = m.inverse().transpose();
  for (const SoPrimitiveVertex* v : {a, b, c}) {
    SbVec3f p, n;
    m.multVecMatrix(v->getPoint(), p);
    normalMatrix.multDirMatrix(v->getNormal(), n);
    n.normalize();
    mesh->triangles << mesh->vertex(p, n, SbVec2f(v->getTextureCoords()[0], v->getTextureCoords()[1]));
  }
}
}  // namespace

SoPath* SceneDocument::pathTo(SoBSplineDeformSurface* surface, QString& error) const {
  if (!m_root || !m_surfaces.contains(surface)) {
    error = QStringLiteral("no surface to export");
    return nullptr;
  }
  SoSearchAction sa;
  sa.setNode(surface);
  sa.apply(m_root.get());
  if (!sa.getPath()) {
    error = QStringLiteral("the surface is not in the scene");
    return nullptr;
  }
  SoPath* path = sa.getPath()->copy();
  path->ref();
  return path;
}

SoPath* SceneDocument::exportPath(SoBSplineDeformSurface* surface, const QString& path, const QString& what,
                                  const QStringList& extensions, QString& error) const {
  const QString ext = QFileInfo(path).suffix().toLower();
  if (!extensions.contains(ext)) {
    error = QStringLiteral("%1: unknown %2 format '%3' (use .%4)").arg(path, what, ext, extensions.join(QStringLiteral(" or .")));
    return nullptr;
  }
  return pathTo(surface, error);
}

bool SceneDocument::exportMesh(SoBSplineDeformSurface* surface, const QString& path, QString& error) const {
  SoPath* found = exportPath(surface, path, QStringLiteral("mesh"), {QStringLiteral("obj"), QStringLiteral("stl")}, error);
  if (!found) return false;
  const QString ext = QFileInfo(path).suffix().toLower();
  Mesh mesh;
  SoCallbackAction ca;
  ca.addTriangleCallback(SoBSplineDeformSurface::getClassTypeId(), collectTriangle, &mesh);
  ca.apply(found);
  found->unref();
  auto writeObj = [&](QIODevice& f) {
    QTextStream out(&f);
    out.setRealNumberPrecision(9);
    out << "# " << nameOf(surface) << ", exported by bsdeform-viewer (world coordinates): " << mesh.p.size() << " vertices, "
        << mesh.triangles.size() / 3 << " triangles\n";
    out << "o " << QString(nameOf(surface)).replace(QLatin1Char(' '), QLatin1Char('_')) << '\n';
    for (const SbVec3f& p : mesh.p) out << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (const SbVec2f& t : mesh.uv) out << "vt " << t[0] << ' ' << t[1] << '\n';
    for (const SbVec3f& n : mesh.n) out << "vn " << n[0] << ' ' << n[1] << ' ' << n[2] << '\n';
    for (int i = 0; i + 2 < mesh.triangles.size(); i += 3) {
      out << 'f';
      for (int k = 0; k < 3; ++k) {
        const int v = mesh.triangles[i + k] + 1;  // a vertex's position, (u, v) and normal share its index
        out << ' ' << v << '/' << v << '/' << v;
      }
      out << '\n';
    }
    out.flush();
    return out.status() == QTextStream::Ok;
  };
  auto writeStl = [&](QIODevice& f) {
    QByteArray header(80, ' ');
    const QByteArray title = "bsdeform-viewer " + nameOf(surface).toUtf8();
    std::memcpy(header.data(), title.constData(), size_t(std::min(80, title.size())));
    bool ok = f.write(header) == header.size();
    const quint32 count = quint32(mesh.triangles.size() / 3);
    ok &= f.write(reinterpret_cast<const char*>(&count), 4) == 4;  // STL is little-endian, as is this machine
    for (int i = 0; ok && i + 2 < mesh.triangles.size(); i += 3) {
      const SbVec3f& a = mesh.p[mesh.triangles[i]];
      const SbVec3f& b = mesh.p[mesh.triangles[i + 1]];
      const SbVec3f& c = mesh.p[mesh.triangles[i + 2]];
      SbVec3f n = (b - a).cross(c - a);
      n.normalize();
      float rec[12] = {n[0], n[1], n[2]};
      for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 3; ++d) rec[3 + 3 * k + d] = mesh.p[mesh.triangles[i + k]][d];
      ok &= f.write(reinterpret_cast<const char*>(rec), sizeof rec) == qint64(sizeof rec);
      const quint16 attr = 0;
      ok &= f.write(reinterpret_cast<const char*>(&attr), 2) == 2;
    }
    return ok;
  };
  if (ext == QLatin1String("obj")) return saveFileAtomically(path, writeObj, error);
  return saveFileAtomically(path, writeStl, error);
}

bool SceneDocument::exportControlNet(SoBSplineDeformSurface* surface, const QString& path, QString& error) const {
  SoPath* found = exportPath(surface, path, QStringLiteral("control net"), {QStringLiteral("xyz"), QStringLiteral("obj")}, error);
  if (!found) return false;
  const QString ext = QFileInfo(path).suffix().toLower();
  SoGetMatrixAction ma(SbViewportRegion(1, 1));
  ma.apply(found);
  found->unref();
  const SbMatrix m = ma.getMatrix();  // affine: the B-spline of the moved net is the moved surface
  const Simulation& sim = surface->simulation();
  const ControlNet& net = sim.current();
  const int rows = sim.space().netRows(), cols = sim.space().netCols();
  QVector<SbVec3f> points(int(net.rows()));
  for (int i = 0; i < int(net.rows()); ++i)
    m.multVecMatrix(SbVec3f(float(net(i, 0)), float(net(i, 1)), float(net(i, 2))), points[i]);
  const bool obj = ext == QLatin1String("obj");
  auto write = [&](QIODevice& f) {
    QTextStream out(&f);
    out.setRealNumberPrecision(9);
    out << "# control net of " << nameOf(surface) << " (world coordinates), exported by bsdeform-viewer: " << rows << " x "
        << cols << " points (u x v, degrees " << sim.parameters().degreeU << ", " << sim.parameters().degreeV
        << "), u-major: point (i, j) is number i * " << cols << " + j\n";
    for (const SbVec3f& p : points) out << (obj ? "v " : "") << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    if (obj) {  // the net's polylines: one along v for each i, one along u for each j
      for (int i = 0; i < rows; ++i) {
        out << 'l';
        for (int j = 0; j < cols; ++j) out << ' ' << i * cols + j + 1;
        out << '\n';
      }
      for (int j = 0; j < cols; ++j) {
        out << 'l';
        for (int i = 0; i < rows; ++i) out << ' ' << i * cols + j + 1;
        out << '\n';
      }
    }
    out.flush();
    return out.status() == QTextStream::Ok;
  };
  return saveFileAtomically(path, write, error);
}

}  // namespace bsdeform
