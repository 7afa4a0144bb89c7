// SPDX-License-Identifier: MIT
#include "EditCommands.h"

#include <Inventor/SoPath.h>
#include <Inventor/SbViewportRegion.h>
#include <Inventor/actions/SoGetBoundingBoxAction.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/fields/SoField.h>
#include <Inventor/nodes/SoGroup.h>
#include <Inventor/nodes/SoSeparator.h>
#include <Inventor/nodes/SoTranslation.h>

#include <QObject>
#include <algorithm>

#include "MaterialPresets.h"
#include "SceneDocument.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {

namespace {
SoField* copyOf(const SoField& f) {
  auto* copy = static_cast<SoField*>(f.getTypeId().createInstance());
  copy->copyFrom(f);
  return copy;
}

QString fieldName(SoFieldContainer* owner, SoField* field) {
  SbName name;
  owner->getFieldName(field, name);
  return QString::fromLatin1(name.getString());
}

QString enumName(const SoSFEnum& field) {
  for (int k = 0; k < field.getNumEnums(); ++k) {
    SbName name;
    if (field.getEnum(k, name) == field.getValue()) return QString::fromLatin1(name.getString());
  }
  return QString::number(field.getValue());
}
}  // namespace

QString refusalOf(SoFieldContainer* owner) {
  // a surface: a refused field (other problems, e.g. a force's, do not refuse the model)
  if (owner->isOfType(SoBSplineDeformSurface::getClassTypeId())) {
    const QVector<RefusedField> refused = refusedFieldsOf(owner);
    return refused.isEmpty() ? QString() : refused.front().reason;
  }
  if (owner->isOfType(SoForceField::getClassTypeId())) {
    auto* f = static_cast<SoForceField*>(owner);
    if (f->type.getValue() == SoForceField::COLLISION) return QString();
    std::string error;
    f->makeForce(SoForceField::SurfaceInfo(), error);
    return QString::fromStdString(error);
  }
  return QString();
}

QVector<RefusedField> refusedFieldsOf(SoFieldContainer* owner) {
  QVector<RefusedField> out;
  if (!owner) return out;
  if (owner->isOfType(SoBSplineDeformSurface::getClassTypeId())) {
    auto* s = static_cast<SoBSplineDeformSurface*>(owner);
    s->simulation();  // rebuilt from the fields now
    for (const SoBSplineDeformSurface::Problem& p : s->refusals())
      out.push_back({QString::fromStdString(p.field), QString::fromStdString(p.message)});
  } else if (owner->isOfType(SoForceField::getClassTypeId())) {
    auto* f = static_cast<SoForceField*>(owner);
    if (f->type.getValue() == SoForceField::COLLISION) return out;
    for (const SoForceField::Refusal& r : f->refusedFields())
      out.push_back({QString::fromStdString(r.field), QString::fromStdString(r.message)});
  }
  return out;
}

// ---------------------------------------------------------------------------------------------

SetFieldCommand::SetFieldCommand(EditContext& context, SoFieldContainer* owner, SoField* field, const SoField& before,
                                 bool beforeIsDefault, const SoField& after, bool alreadySet)
    : m_context(context),
      m_owner(owner),
      m_field(field),
      m_before(copyOf(before)),
      m_after(copyOf(after)),
      m_beforeIsDefault(beforeIsDefault),
      m_skipRedo(alreadySet) {
  m_owner->ref();
  setText(QObject::tr("Change %1").arg(fieldName(owner, field)));
}

SetFieldCommand::~SetFieldCommand() {
  delete m_before;
  delete m_after;
  m_owner->unref();
}

void SetFieldCommand::set(const SoField& value, bool isDefault) {
  m_field->copyFrom(value);
  m_field->setDefault(isDefault);
  m_context.fieldChanged(m_owner, m_field);
}

void SetFieldCommand::undo() { set(*m_before, m_beforeIsDefault); }

void SetFieldCommand::redo() {
  if (m_skipRedo) {
    m_skipRedo = false;
      m_context.fieldChanged(m_owner, m_field);
    return;
  }
  set(*m_after, false);
}

// ---------------------------------------------------------------------------------------------

void insertedForceDefaults(SoForceField* f, int type, SoBSplineDeformSurface* surface) {
  const Simulation& sim = surface->simulation();
  const SurfacePoint c = sim.evaluate(0.5, 0.5, 1);  // the centre and its normal
  const Eigen::Vector3d n = c.normal();
  Eigen::Vector3d lo = sim.current().colwise().minCoeff().transpose(), hi = sim.current().colwise().maxCoeff().transpose();
  const double size = std::max(1e-6, (hi - lo).norm());
  auto vec = [](const Eigen::Vector3d& v) { return SbVec3d(v.x(), v.y(), v.z()); };
  switch (type) {
    case SoForceField::GRAVITY:
      f->force = SbVec3d(0.0, 0.0, -9.81);
      f->magnitude = 1.0;
      break;
    case SoForceField::EXPRESSION:
      f->expression.set1Value(0, "0");
      f->expression.set1Value(1, "0");
      f->expression.set1Value(2, "sin(pi*u)*sin(pi*v)");
      break;
    case SoForceField::SPRING:
      f->point = SbVec2d(0.5, 0.5);
      f->anchor = vec(c.position);
      break;
    case SoForceField::PLANE_COLLISION:
      f->center = SbVec3d(c.position.x(), c.position.y(), lo.z() - 0.1 * size);
      f->normal = SbVec3d(0.0, 0.0, 1.0);
      break;
    case SoForceField::SPHERE_COLLISION:
      f->radius = 0.25 * size;
      f->center = vec(c.position - (0.25 * size + 0.05 * size) * (n.squaredNorm() > 0.0 ? n : Eigen::Vector3d::UnitZ()));
      break;
    default:
      break;  // UNIFORM, POINT, REGION: a unit load along +z (the node's); DRAG, PRESSURE, COLLISION
  }
}

InsertForceCommand::InsertForceCommand(EditContext& context, SoBSplineDeformSurface* surface, int type)
    : m_context(context), m_surface(surface), m_force(new SoForceField) {
  m_surface->ref();
  m_force->ref();
  m_force->type = type;
  insertedForceDefaults(m_force, type, surface);
  setText(QObject::tr("Add %1 force field").arg(enumName(m_force->type)));
}

InsertForceCommand::~InsertForceCommand() {
  m_force->unref();
  m_surface->unref();
}

void InsertForceCommand::redo() {
  m_surface->forces.set1Value(m_surface->forces.getNum(), m_force);
  m_context.doc.rescan();
  m_context.structureChanged(m_force);
}

void InsertForceCommand::undo() {
  const int i = m_surface->forces.find(m_force);
  if (i >= 0) m_surface->forces.deleteValues(i, 1);
  m_context.doc.rescan();
  m_context.structureChanged(m_surface);
}

// ---------------------------------------------------------------------------------------------

InsertSurfaceCommand::InsertSurfaceCommand(EditContext& context, SoGroup* root, const MaterialPreset* preset)
    : m_context(context), m_root(root), m_surface(new SoBSplineDeformSurface) {
  if (preset) applyMaterialPreset(m_surface, *preset);
  m_root->ref();
  auto* group = new SoSeparator;
  m_group = group;
  m_group->ref();
  // beside the scene's bounding box along x, a quarter of its width away
  SoGetBoundingBoxAction bb(SbViewportRegion(640, 480));
  bb.apply(root);
  const SbBox3f box = bb.getBoundingBox();
  if (!box.isEmpty()) {
    float dx, dy, dz;
    box.getSize(dx, dy, dz);
    auto* move = new SoTranslation;
    move->translation = SbVec3f(box.getMax()[0] + 0.25f * std::max(dx, 0.25f), box.getMin()[1], 0.0f);
    group->addChild(move);
  }
  group->addChild(m_surface);
  setText(preset ? QObject::tr("Add surface: %1").arg(QString::fromUtf8(preset->name)) : QObject::tr("Add surface"));
}

InsertSurfaceCommand::~InsertSurfaceCommand() {
  m_group->unref();
  m_root->unref();
}

void InsertSurfaceCommand::redo() {
  m_root->addChild(m_group);
  m_context.doc.rescan();
  m_context.structureChanged(m_surface);
}

void InsertSurfaceCommand::undo() {
  const int i = m_root->findChild(m_group);
  if (i >= 0) m_root->removeChild(i);
  m_context.doc.rescan();
  m_context.structureChanged(nullptr);
}

// ---------------------------------------------------------------------------------------------

DeleteCommand::DeleteCommand(EditContext& context, SoBSplineDeformSurface* surface)
    : m_context(context), m_target(surface), m_isSurface(true) {
  m_target->ref();
  SoSearchAction sa;
  sa.setNode(surface);
  sa.setInterest(SoSearchAction::ALL);
  sa.apply(context.doc.root());
  for (int i = 0; i < sa.getPaths().getLength(); ++i) {
    const SoPath* path = sa.getPaths()[i];  // no node kits here: the visible path is the whole path
    if (path->getLength() < 2) continue;
    SoNode* parent = path->getNodeFromTail(1);
    const int index = path->getIndexFromTail(0);
    bool known = false;
    for (const Place& p : m_places) known |= p.holder == parent && p.index == index;
    if (!known) m_places.push_back({parent, index});
  }
  for (Place& p : m_places) p.holder->ref();
  setText(QObject::tr("Delete %1").arg(context.doc.nameOf(surface)));
}

DeleteCommand::DeleteCommand(EditContext& context, SoForceField* force)
    : m_context(context), m_target(force), m_isSurface(false) {
  m_target->ref();
  for (SoBSplineDeformSurface* s : context.doc.surfaces())
    for (int k = 0; k < s->forces.getNum(); ++k)
      if (s->forces[k] == force) {
        s->ref();
        m_places.push_back({s, k});
      }
  setText(QObject::tr("Delete %1").arg(context.doc.nameOf(force)));
}

DeleteCommand::~DeleteCommand() {
  for (Place& p : m_places) p.holder->unref();
  m_target->unref();
}

void DeleteCommand::redo() {
  // last first: the recorded indices of a holder stay valid
  for (auto it = m_places.rbegin(); it != m_places.rend(); ++it) {
    if (m_isSurface)
      static_cast<SoGroup*>(it->holder)->removeChild(it->index);
    else
      static_cast<SoBSplineDeformSurface*>(it->holder)->forces.deleteValues(it->index, 1);
  }
  m_context.doc.rescan();
  m_context.structureChanged(nullptr);
}

void DeleteCommand::undo() {
  for (const Place& p : m_places) {
    if (m_isSurface) {
      static_cast<SoGroup*>(p.holder)->insertChild(static_cast<SoNode*>(m_target), p.index);
    } else {
      SoMFEngine& forces = static_cast<SoBSplineDeformSurface*>(p.holder)->forces;
      forces.insertSpace(p.index, 1);
      forces.set1Value(p.index, static_cast<SoEngine*>(m_target));
    }
  }
  m_context.doc.rescan();
  m_context.structureChanged(m_target);
}

// ---------------------------------------------------------------------------------------------

SolveStaticCommand::State SolveStaticCommand::capture(SoBSplineDeformSurface* node) {
  node->syncStateFields();
  return State{node, std::unique_ptr<SoField>(copyOf(node->controlNet)), std::unique_ptr<SoField>(copyOf(node->previousNet)),
               node->simulationTime.getValue(), int(node->stepCount.getValue())};
}

// The state fields of each surface, written as a file would hold them: the node rebuilds its
// state from them (its notify marks the state changed).
void SolveStaticCommand::restore(const std::vector<State>& states) {
  for (const State& s : states) {
    s.node->controlNet.copyFrom(*s.control);
    s.node->previousNet.copyFrom(*s.previous);
    s.node->simulationTime.setValue(s.time);
    s.node->stepCount.setValue(s.steps);
    s.node->simulation();  // rebuilt now, not at the next traversal
    m_context.fieldChanged(s.node, &s.node->controlNet);
  }
}

SolveStaticCommand::SolveStaticCommand(EditContext& context, const std::vector<SoBSplineDeformSurface*>& surfaces)
    : m_context(context) {
  setText(QObject::tr("Solve Static"));
  for (SoBSplineDeformSurface* s : surfaces) {
    s->ref();
    m_before.push_back(capture(s));
  }
  for (SoBSplineDeformSurface* s : surfaces) {
    StaticResult r;
    std::string error;
    const SbName name = s->getName();
    const QString label = name.getLength() ? QString::fromUtf8(name.getString()) : QObject::tr("surface");
    if (!s->solveStatic(&r, &error)) {
      m_error = label + QStringLiteral(": ") + QString::fromStdString(error);
      restore(m_before);
      return;
    }
    m_report += (m_report.isEmpty() ? QString() : QStringLiteral("; ")) +
                QObject::tr("%1: equilibrium by %2, relative residual %3")
                    .arg(label, QString::fromStdString(r.method))
                    .arg(r.residual, 0, 'g', 3);
  }
  for (SoBSplineDeformSurface* s : surfaces) {
    m_after.push_back(capture(s));
    m_context.fieldChanged(s, &s->controlNet);
  }
}

SolveStaticCommand::~SolveStaticCommand() {
  for (const State& s : m_before) s.node->unref();
}

void SolveStaticCommand::undo() { restore(m_before); }

void SolveStaticCommand::redo() {
  if (m_skipRedo) {  // solved in the constructor
    m_skipRedo = false;
    return;
  }
  restore(m_after);
}

}  // namespace bsdeform
