// SPDX-License-Identifier: MIT
#pragma once
#include <Inventor/SoDB.h>
#include <Inventor/SoInput.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/nodes/SoSeparator.h>

#include <string>
#include <vector>

#include "bsdeform/CoinMessageCapture.h"
#include "bsdeform/NodesInit.h"
#include "bsdeform/SceneReader.h"
#include "bsdeform/SceneText.h"
#include "bsdeform/contact/Contact.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace testutil {

/// Initialises Coin and our nodes once and collects Coin warnings and errors.
class Coin {
  static bool init() {
    bsdeform::disableDynamicNodeLoading();
    bsdeform::initNodes();
    return true;
  }
  Coin() = default;
  bool m_initialised = init();             // first: SoDB::init() sets Coin's default handlers
  bsdeform::CoinMessageCapture m_capture;  // for the whole test run

 public:
  static Coin& get() {
    static Coin c;
    return c;
  }
  std::vector<std::string>& messages = m_capture.messages;
};

/// Reads a scene from a string (null on failure). The result is ref'ed.
inline SoSeparator* read(const std::string& text) {
  Coin::get();
  std::string error;  // the guarded reader our programs use; Coin's errors also reach `messages`
  SoSeparator* root = bsdeform::readSceneText(text.data(), text.size(), "test-scene", error);
  if (root) root->ref();
  else Coin::get().messages.push_back(error);
  return root;
}

inline std::string write(SoNode* root) { return bsdeform::sceneToText(root); }

/// The last object DEF'ed with `name` (engines included).
template <typename T>
T* named(const char* name) {
  return static_cast<T*>(SoBase::getNamedBase(SbName(name), T::getClassTypeId()));
}

template <typename T>
T* find(SoNode* root) {
  SoSearchAction sa;
  sa.setType(T::getClassTypeId());
  sa.setInterest(SoSearchAction::FIRST);
  sa.apply(root);
  return sa.getPath() ? static_cast<T*>(sa.getPath()->getTail()) : nullptr;
}

// Total load of the COLLISION forces of `s` that list or name `other` (all points move,
// so the sum over the control points is the integral of the density).
inline Eigen::Vector3d contactLoadFrom(SoBSplineDeformSurface* s, SoNode* other) {
  const bsdeform::Simulation& sim = s->simulation();
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int i = 0; i < s->forces.getNum(); ++i) {
    auto* ff = static_cast<SoForceField*>(static_cast<SoEngine*>(s->forces[i]));
    const bool named = ff->obstacleNames.find(SbString(other->getName().getString())) >= 0;
    if (ff->type.getValue() != SoForceField::COLLISION || (ff->obstacles.find(other) < 0 && !named)) continue;
    for (const auto& f : sim.forces()) {
      auto* c = dynamic_cast<const bsdeform::CollisionForce*>(f.get());
      if (!c) continue;
      // the force of this field (the test gives each COLLISION field its own stiffness)
      bsdeform::ControlNet load = bsdeform::ControlNet::Zero(sim.space().numMoving(), 3);
      const bsdeform::LoadContext ctx{sim.space(), sim.current(), sim.previous(), sim.subStepSize(), sim.time()};
      if (c->parameters().stiffness != ff->stiffness.getValue()) continue;
      c->addLoad(ctx, load);
      // a load in the surface's coordinates is A^T times the world force
      total += Eigen::Vector3d(c->world().linear.transpose().inverse() * load.colwise().sum().transpose());
    }
  }
  return total;
}

}  // namespace testutil
