// SPDX-License-Identifier: MIT
#pragma once
/// @file SceneDocument.h
/// The scene the viewer shows: reading (with Coin's error message), writing with the simulation
/// state (atomically), the surfaces and force fields it contains, and mesh export.

#include <QString>
#include <QStringList>
#include <QVector>
#include <vector>

#include "bsdeform/NodeRef.h"
#include "bsdeform/SceneText.h"

class SoSeparator;
class SoBSplineDeformSurface;
class SoForceField;
class SoNode;
class SoPath;

namespace bsdeform {

class SceneDocument {
 public:
  SceneDocument();
  ~SceneDocument();
  SceneDocument(const SceneDocument&) = delete;
  SceneDocument& operator=(const SceneDocument&) = delete;

  /// Reads `path`. On failure returns false, sets `error` (Coin's reason with file and line) and
  /// keeps the current scene.
  bool load(const QString& path, QString& error);
  /// Reads a scene from memory (the default scene).
  bool loadFromText(const QByteArray& text, const QString& name, QString& error);
  /// Writes the scene with the current simulation state to `path` atomically (the viewer's
  /// Play and speed are its clock's, never in the file; saveFileAtomically: on failure the previous file is untouched and `error` gives the reason).
  bool save(const QString& path, QString& error) const;
  /// The scene as .iv text, with the current state.
  QByteArray toText() const;
  /// Streams that text into `sink`; false without a scene or when the sink failed.
  bool writeTo(const TextSink& sink) const;

  SoSeparator* root() const { return m_root.get(); }
  const QString& path() const { return m_path; }
  /// The file the scene belongs to (a restored recovery file belongs to the scene it came from).
  void setPath(const QString& path) { m_path = path; }
  const QVector<SoBSplineDeformSurface*>& surfaces() const { return m_surfaces; }
  const QVector<SoForceField*>& forceFields() const { return m_forceFields; }
  /// A display name: the DEF name, or "Surface 1", "Force 2", ...
  QString nameOf(SoBSplineDeformSurface* s) const;
  QString nameOf(SoForceField* f) const;
  /// Finds the surfaces and force fields again after the graph changed (a node inserted or
  /// removed); newly seen surfaces' `on` and `speed` count as authored.
  void rescan();
  /// Whether `f` makes no force from its values as they stand (COLLISION: taken as it is), tried
  /// again only after its values changed (its revision): the viewer asks every frame.
  bool forceFieldRefused(SoForceField* f) const;
  /// The surfaces' `on` and `speed` as the file or the field editor set them (written to file).

  /// Writes the triangles of `surface` as drawn (world coordinates, with every transform above
  /// it) as Wavefront OBJ or binary STL, chosen by the file extension (.obj / .stl), through
  /// bsdeform::writeMesh (nodes/bsdeform/MeshExport.h). Atomic.
  /// The OBJ is one connected mesh: one vertex per tessellation point (position, (u, v) texture
  /// coordinate and normal under one index), faces sharing them, so an s x s grid gives
  /// (s + 1)^2 vertices and 2 s^2 triangles (a periodic seam has its own column of vertices).
  bool exportMesh(SoBSplineDeformSurface* surface, const QString& path, QString& error) const;
  /// Writes the current control net of `surface` (all (N1 + 2 n1)(N2 + 2 n2) points, u-major,
  /// world coordinates) for a CAD tool: .xyz (one "x y z" line per point) or .obj (the points
  /// as vertices and the net's rows and columns as polylines). Atomic.
  bool exportControlNet(SoBSplineDeformSurface* surface, const QString& path, QString& error) const;

 private:
  void adopt(SoSeparator* root, const QString& path);
  void scan();
  /// A ref'ed copy of the path from the root to `surface` (nullptr with `error` if none).
  SoPath* pathTo(SoBSplineDeformSurface* surface, QString& error) const;
  /// pathTo() when `path` ends in one of `extensions` (lower case, no dot), else a message
  /// naming the file and the `what` format.
  SoPath* exportPath(SoBSplineDeformSurface* surface, const QString& path, const QString& what, const QStringList& extensions,
                     QString& error) const;

  NodeRef<SoSeparator> m_root;
  QString m_path;
  /// The comment lines that followed the file's `#Inventor` line when it was read: a save
  /// writes them again (Coin's writer drops every comment).
  QByteArray m_headerComment;
  QVector<SoBSplineDeformSurface*> m_surfaces;
  QVector<SoForceField*> m_forceFields;
  /// forceFieldRefused()'s answers by force field (held: a deleted one's address is not reused
  /// while it is here) with the revision they were found at; cleared with every new scene.
  struct KnownRefusal {
    NodeRef<SoForceField> field;
    int revision = 0;
    bool refused = false;
  };
  mutable std::vector<KnownRefusal> m_knownRefusals;
};

}  // namespace bsdeform
