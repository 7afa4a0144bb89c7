// SPDX-License-Identifier: MIT
#include "SceneProblems.h"

#include <Inventor/SbString.h>
#include <Inventor/fields/SoField.h>

#include "EditCommands.h"
#include "SceneDocument.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {

namespace {

QString nodeName(SoFieldContainer* node, const char* type, int place) {
  const SbName n = node->getName();
  return n.getLength() ? QString::fromUtf8(n.getString()) : QStringLiteral("%1 #%2").arg(QLatin1String(type)).arg(place + 1);
}

}  // namespace

QString SceneProblem::text() const {
  if (field.isEmpty()) return QStringLiteral("%1: %2").arg(node, reason);
  return QStringLiteral("%1: %2 = %3: %4").arg(node, field, value, reason);
}

QString fieldValueText(SoFieldContainer* owner, const QString& field) {
  SoField* f = owner ? owner->getField(SbName(field.toUtf8().constData())) : nullptr;
  if (!f) return QString();
  SbString text;
  f->get(text);
  return QString::fromUtf8(text.getString()).simplified();
}

QVector<SceneProblem> sceneProblems(const SceneDocument& doc) {
  QVector<SceneProblem> out;
  for (int i = 0; i < doc.surfaces().size(); ++i) {
    SoBSplineDeformSurface* s = doc.surfaces()[i];
    s->simulation();  // the model built from the fields as read
    const SoBSplineDeformSurface::Problem& p = s->problem();
    if (p.kind == SoBSplineDeformSurface::Problem::NONE) continue;
    SceneProblem sp;
    sp.node = nodeName(s, "SoBSplineDeformSurface", i);
    sp.field = QString::fromStdString(p.field);
    sp.value = fieldValueText(s, sp.field);
    sp.reason = QString::fromStdString(p.message);
    sp.refused = p.kind == SoBSplineDeformSurface::Problem::FIELD || p.kind == SoBSplineDeformSurface::Problem::FORCE_FIELD ||
                 p.kind == SoBSplineDeformSurface::Problem::STOPPED;
    out << sp;
  }
  for (int i = 0; i < doc.forceFields().size(); ++i) {
    SoForceField* f = doc.forceFields()[i];
    const QString reason = refusalOf(f);
    const QString name = nodeName(f, "SoForceField", i);
    if (reason.isEmpty()) continue;
    bool told = false;  // a surface that holds it already said so
    for (const SceneProblem& q : out) told = told || q.reason.contains(reason);
    if (told) continue;
    SceneProblem sp;
    sp.node = name;
    sp.reason = reason;
    out << sp;
  }
  return out;
}

}  // namespace bsdeform
