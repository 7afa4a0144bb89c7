// Reads a scene with our nodes, steps it and prints the deformation norm.
#include <Inventor/SoDB.h>
#include <Inventor/SoInput.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/nodes/SoSeparator.h>
#include <bsdeform/NodesInit.h>
#include <bsdeform/dynamics/Simulation.h>
#include <bsdeform/SoBSplineDeformSurface.h>

#include <cstdio>
#include <cstring>

int main() {
  bsdeform::disableDynamicNodeLoading();
  bsdeform::initNodes();
  const char* text = "#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE "
                     "forces SoForceField { type UNIFORM force 0 0 5 } } }";
  SoInput in;
  in.setBuffer(text, std::strlen(text));
  SoSeparator* root = SoDB::readAll(&in);
  if (!root) return 1;
  root->ref();
  SoSearchAction sa;
  sa.setType(SoBSplineDeformSurface::getClassTypeId());
  sa.apply(root);
  auto* s = static_cast<SoBSplineDeformSurface*>(sa.getPath()->getTail());
  s->stepSimulation(10);
  std::printf("consumer norm %.6f\n", s->simulation().deformationNorm());
  root->unref();
  return s->simulation().deformationNorm() > 0 ? 0 : 1;
}
