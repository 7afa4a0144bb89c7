// SPDX-License-Identifier: MIT
// bsdeform-render SCENE.iv OUT.png [STEPS] [WIDTH HEIGHT]
// Reads a scene, advances every SoBSplineDeformSurface by STEPS steps (default 0), and renders
// it headlessly (EGL, no X needed) to a PNG.
#include <Inventor/SoDB.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/nodes/SoSeparator.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "bsdeform/NodesInit.h"
#include "bsdeform/OffscreenRenderer.h"
#include "bsdeform/SceneReader.h"
#include "bsdeform/dynamics/Simulation.h"
#include "bsdeform/SoBSplineDeformSurface.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s SCENE.iv OUT.png [STEPS] [WIDTH HEIGHT]\n", argv[0]);
    return 2;
  }
  const int steps = argc > 3 ? std::atoi(argv[3]) : 0;
  const int width = argc > 5 ? std::atoi(argv[4]) : 640, height = argc > 5 ? std::atoi(argv[5]) : 480;
  bsdeform::disableDynamicNodeLoading();
  bsdeform::initNodes();
  std::string readError;
  SoSeparator* root = bsdeform::readSceneFile(argv[1], readError);  // guarded, see docs/reliability.md
  if (!root) {
    std::fprintf(stderr, "bsdeform-render: %s\n", readError.c_str());
    return 2;
  }
  root->ref();
  SoSearchAction sa;
  sa.setType(SoBSplineDeformSurface::getClassTypeId());
  sa.setInterest(SoSearchAction::ALL);
  sa.apply(root);
  int status = 0;
  for (int i = 0; i < sa.getPaths().getLength(); ++i) {
    auto* s = static_cast<SoBSplineDeformSurface*>(sa.getPaths()[i]->getTail());
    if (!s->stepSimulation(steps)) status = 3;
    std::printf("surface %d: t = %g, norm (eq. 15) = %.6g\n", i, s->simulation().time(), s->simulation().deformationNorm());
  }
  bsdeform::Image image;
  std::string error;
  if (!bsdeform::renderOffscreen(root, width, height, image, error) || !bsdeform::writePng(image, argv[2], error)) {
    std::fprintf(stderr, "bsdeform-render: %s\n", error.c_str());
    root->unref();
    return 1;
  }
  std::printf("wrote %s (%d x %d)\n", argv[2], width, height);
  root->unref();
  return status;
}
