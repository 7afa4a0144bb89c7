// SPDX-License-Identifier: MIT
#include "SceneProblems.h"

#include <Inventor/SbString.h>
#include <Inventor/fields/SoField.h>

#include "EditCommands.h"
#include "SceneDocument.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {

QString SceneProblem::text() const {
  if (field.isEmpty()) return QStringLiteral("%1: %2").arg(node, reason);
  return QStringLiteral("%1: %2 = %3: %4").arg(node, field, value, reason);
}

namespace {

// The field's value in the text Coin writes ("9", "0 0 -1", "[ 1, 2 ]").
QString fieldValueText(SoFieldContainer* owner, const QString& field) {
  SoField* f = owner ? owner->getField(SbName(field.toUtf8().constData())) : nullptr;
  if (!f) return QString();
  SbString text;
  f->get(text);
  return QString::fromUtf8(text.getString()).simplified();
}

}  // namespace

QVector<SceneProblem> sceneProblems(const SceneDocument& doc) {
  QVector<SceneProblem> out, forces;
  for (SoForceField* f : doc.forceFields()) {
    for (const RefusedField& r : refusedFieldsOf(f)) {
      SceneProblem sp;
      sp.node = doc.nameOf(f);
      sp.field = r.field;
      sp.value = fieldValueText(f, sp.field);
      sp.reason = r.reason;
      forces << sp;
    }
  }
  for (SoBSplineDeformSurface* s : doc.surfaces()) {
    for (const RefusedField& r : refusedFieldsOf(s)) {  // the model built from the fields as read
      SceneProblem sp;
      sp.node = doc.nameOf(s);  // as the scene panel names it
      sp.field = r.field;
      sp.value = fieldValueText(s, sp.field);
      sp.reason = r.reason;
      out << sp;
    }
    // a problem that is not a refused field (an obstacle, a COLLISION force's values, a seam),
    // unless a force field's own entry tells it
    const SoBSplineDeformSurface::Problem& p = s->problem();
    if (p.kind == SoBSplineDeformSurface::Problem::NONE || p.kind == SoBSplineDeformSurface::Problem::FIELD) continue;
    const QString message = QString::fromStdString(p.message);
    bool told = false;
    for (const SceneProblem& q : forces) told = told || message.contains(q.reason);
    if (told) continue;
    SceneProblem sp;
    sp.node = p.kind == SoBSplineDeformSurface::Problem::FORCE_FIELD ? QString::fromStdString(p.node) : doc.nameOf(s);
    if (p.kind != SoBSplineDeformSurface::Problem::FORCE_FIELD) {
      sp.field = QString::fromStdString(p.field);
      sp.value = fieldValueText(s, sp.field);
    }
    sp.reason = message;
    out << sp;
  }
  return out << forces;
}

bool sceneRefused(const SceneDocument& doc) {
  for (SoBSplineDeformSurface* s : doc.surfaces()) {
    s->simulation();
    if (!s->refusals().empty()) return true;
  }
  // the force fields' values as they stand now (a surface remakes its forces only at its next
  // step, so its FORCE_FIELD problem may be older than a fix)
  for (SoForceField* f : doc.forceFields())
    if (doc.forceFieldRefused(f)) return true;
  return false;
}

QStringList refusedNodes(const SceneDocument& doc) {
  QStringList out;
  for (const SceneProblem& p : sceneProblems(doc))
    if (!out.contains(p.node)) out << p.node;
  return out;
}

}  // namespace bsdeform
