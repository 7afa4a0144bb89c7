// SPDX-License-Identifier: MIT
#include "SceneDocument.h"

#include <Inventor/SoDB.h>
#include <Inventor/SbViewportRegion.h>
#include <Inventor/actions/SoGetMatrixAction.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/nodes/SoSeparator.h>

#include <QFile>
#include <algorithm>
#include <cstring>
#include <QFileInfo>
#include <QTextStream>

#include "AtomicFile.h"
#include "bsdeform/MeshExport.h"
#include "bsdeform/SceneReader.h"
#include "bsdeform/SceneText.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {


SceneDocument::SceneDocument() = default;

SceneDocument::~SceneDocument() = default;

bool SceneDocument::forceFieldRefused(SoForceField* f) const {
  for (const KnownRefusal& k : m_knownRefusals)
    if (k.field.get() == f && k.revision == f->getRevision()) return k.refused;
  bool refused = false;
  if (f->type.getValue() != SoForceField::COLLISION) {
    std::string error;
    f->makeForce(SoForceField::SurfaceInfo(), error);
    refused = !error.empty();
  }
  auto known = std::find_if(m_knownRefusals.begin(), m_knownRefusals.end(), [f](const KnownRefusal& k) { return k.field.get() == f; });
  if (known == m_knownRefusals.end()) {
    m_knownRefusals.push_back(KnownRefusal{NodeRef<SoForceField>(f), 0, false});
    known = m_knownRefusals.end() - 1;
  }
  known->revision = f->getRevision();
  known->refused = refused;
  return refused;
}

void SceneDocument::adopt(SoSeparator* root, const QString& path) {
  m_knownRefusals.clear();
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

namespace {
// The comment block at the top of a scene file: the lines after the `#Inventor` line that are
// comments or blank, up to the first other line, without trailing blank lines.
QByteArray headerComment(const QString& path) {
  QFile f(path);
  if (!f.open(QIODevice::ReadOnly)) return QByteArray();
  QByteArray block;
  f.readLine(1 << 16);  // #Inventor V2.1 ascii
  while (!f.atEnd()) {
    const QByteArray line = f.readLine(1 << 16);
    const QByteArray t = line.trimmed();
    if (!t.isEmpty() && !t.startsWith('#')) break;
    block += line.endsWith('\n') ? line : line + '\n';
  }
  while (block.endsWith("\n\n")) block.chop(1);
  return block.trimmed().isEmpty() ? QByteArray() : block;
}
}  // namespace

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
  m_headerComment = headerComment(path);
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
  m_headerComment.clear();
  return true;
}

QByteArray SceneDocument::toText() const {
  QByteArray text;
  writeTo([&text](const char* data, std::size_t size) {
    text.append(data, int(size));
    return true;
  });
  return text;
}

bool SceneDocument::writeTo(const TextSink& sink) const {
  if (!m_root) return false;
  if (m_headerComment.isEmpty()) return writeSceneText(m_root.get(), sink);
  // the file's comment block goes right after the `#Inventor` line
  bool placed = false;
  return writeSceneText(m_root.get(), [&](const char* data, std::size_t size) {
    if (placed) return sink(data, size);
    const char* newline = static_cast<const char*>(std::memchr(data, '\n', size));
    if (!newline) return sink(data, size);
    const std::size_t head = std::size_t(newline - data) + 1;
    placed = true;
    return sink(data, head) && sink(m_headerComment.constData(), std::size_t(m_headerComment.size())) &&
           sink(data + head, size - head);
  });
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
  const SurfaceMesh mesh = surfaceMesh(found, nameOf(surface).toStdString());
  found->unref();
  std::string why;
  if (writeMesh({mesh}, QFile::encodeName(path).toStdString(), "bsdeform-viewer", why)) return true;
  error = QString::fromStdString(why);
  return false;
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
