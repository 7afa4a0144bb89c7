// SPDX-License-Identifier: MIT
#include "bsdeform/NodesInit.h"

#include <Inventor/SoDB.h>

#include <cstdlib>

#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {

void initNodes() {
  SoDB::init();  // returns at once when already initialised
  SoForceField::initClass();
  SoBSplineDeformSurface::initClass();
}

void disableDynamicNodeLoading() { setenv("COIN_NO_SOTYPE_DYNLOAD", "1", 1); }

}  // namespace bsdeform
