// SPDX-License-Identifier: MIT
#include "bsdeform/AuthoredClock.h"

#include "bsdeform/SceneReader.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace bsdeform {

AuthoredClock::Values AuthoredClock::Values::of(SoBSplineDeformSurface* s) {
  return {s, bool(s->on.getValue()), bool(s->on.isDefault()), s->speed.getValue(), bool(s->speed.isDefault())};
}

namespace {
template <class Field, class Value>
void setQuietly(Field& field, Value value, bool isDefault) {
  const SbBool notify = field.enableNotify(FALSE);
  field.setValue(value);
  field.setDefault(isDefault);
  field.enableNotify(notify);
}
}  // namespace

void AuthoredClock::Values::apply() const {
  setQuietly(surface->on, SbBool(on), onDefault);
  setQuietly(surface->speed, speed, speedDefault);
}

AuthoredClock::AuthoredClock(SoNode* root) { capture(root); }

AuthoredClock::~AuthoredClock() { clear(); }

void AuthoredClock::clear() {
  for (Values& e : m_entries) e.surface->unref();
  m_entries.clear();
}

const AuthoredClock::Values* AuthoredClock::find(const SoBSplineDeformSurface* surface) const {
  for (const Values& e : m_entries)
    if (e.surface == surface) return &e;
  return nullptr;
}

void AuthoredClock::capture(SoNode* root) {
  for (SoBSplineDeformSurface* s : sceneSurfaces(root)) {
    if (find(s)) continue;
    s->ref();
    m_entries.push_back(Values::of(s));
  }
}

bool AuthoredClock::noteEdited(const SoField* field) {
  for (Values& e : m_entries) {
    if (field == &e.surface->on) {
      e.on = e.surface->on.getValue();
      e.onDefault = e.surface->on.isDefault();
      return true;
    }
    if (field == &e.surface->speed) {
      e.speed = e.surface->speed.getValue();
      e.speedDefault = e.surface->speed.isDefault();
      return true;
    }
  }
  return false;
}

bool AuthoredClock::authoredOn(SoBSplineDeformSurface* surface) const {
  const Values* e = find(surface);
  return e ? e->on : surface->on.getValue();
}

float AuthoredClock::authoredSpeed(SoBSplineDeformSurface* surface) const {
  const Values* e = find(surface);
  return e ? e->speed : surface->speed.getValue();
}

AuthoredClock::Scope::Scope(const AuthoredClock& clock) {
  m_runTime.reserve(clock.m_entries.size());
  for (const Values& e : clock.m_entries) {
    m_runTime.push_back(Values::of(e.surface));
    e.apply();
  }
}

AuthoredClock::Scope::~Scope() {
  for (const Values& v : m_runTime) v.apply();
}

}  // namespace bsdeform
