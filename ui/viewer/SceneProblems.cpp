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
  QVector<SceneProblem> out;
  for (SoBSplineDeformSurface* s : doc.surfaces()) {
    s->simulation();  // the model built from the fields as read
    const SoBSplineDeformSurface::Problem& p = s->problem();
    if (p.kind == SoBSplineDeformSurface::Problem::NONE) continue;
    SceneProblem sp;
    sp.node = doc.nameOf(s);  // as the scene panel names it
    sp.field = QString::fromStdString(p.field);
    sp.value = fieldValueText(s, sp.field);
    sp.reason = QString::fromStdString(p.message);
    out << sp;
  }
  for (SoForceField* f : doc.forceFields()) {
    const QString reason = refusalOf(f);
    if (reason.isEmpty()) continue;
    bool told = false;  // a surface that holds it already said so
    for (const SceneProblem& q : out) told = told || q.reason.contains(reason);
    if (told) continue;
    SceneProblem sp;
    sp.node = doc.nameOf(f);
    sp.reason = reason;
    out << sp;
  }
  return out;
}

}  // namespace bsdeform
