// SPDX-License-Identifier: MIT
// A plain Coin program: it links only Coin and includes none of bsdeform's headers. It reads
// a scene and prints the types and the bounding box it finds, then lets half a second of
// Coin's realTime pass, as any Coin viewer's clock does, and prints the surface's step count
// (read by field name): the surface animates with no code of ours. With the directory of
// libbsdeform_nodes on LD_LIBRARY_PATH, Coin's dynamic node loading finds our classes.
#include <Inventor/SbViewportRegion.h>
#include <Inventor/SoDB.h>
#include <Inventor/SoInput.h>
#include <Inventor/actions/SoGetBoundingBoxAction.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/fields/SoSFTime.h>
#include <Inventor/sensors/SoSensorManager.h>
#include <Inventor/nodes/SoSeparator.h>
#include <Inventor/nodes/SoShape.h>

#include <cstdio>

int main(int argc, char** argv) {
  if (argc < 2) return 2;
  SoDB::init();
  SoInput in;
  if (!in.openFile(argv[1])) return 3;
  SoSeparator* root = SoDB::readAll(&in);
  if (!root) {
    std::printf("read failed\n");
    return 1;
  }
  root->ref();
  const SoType t = SoType::fromName("SoBSplineDeformSurface");
  std::printf("type %s known: %d, shape: %d\n", "SoBSplineDeformSurface", int(!t.isBad()),
              int(!t.isBad() && t.isDerivedFrom(SoShape::getClassTypeId())));
  SoGetBoundingBoxAction bba(SbViewportRegion(100, 100));
  bba.apply(root);
  const SbBox3f b = bba.getBoundingBox();
  std::printf("bbox %.3f %.3f %.3f %.3f %.3f %.3f\n", b.getMin()[0], b.getMin()[1], b.getMin()[2], b.getMax()[0],
              b.getMax()[1], b.getMax()[2]);
  SoSearchAction search;
  search.setType(t);
  search.apply(root);
  if (search.getPath()) {
    SoFieldContainer* surface = search.getPath()->getTail();
    auto* realTime = static_cast<SoSFTime*>(SoDB::getGlobalField("realTime"));
    const SbTime start = realTime->getValue();
    for (int frame = 1; frame <= 30; ++frame) {  // 30 frames of 1/60 s
      realTime->setValue(start + SbTime(frame / 60.0));
      SoDB::getSensorManager()->processDelayQueue(FALSE);
    }
    SbString steps;
    surface->getField("stepCount")->get(steps);
    std::printf("after 0.5 s of realTime: stepCount %s\n", steps.getString());
  }
  root->unref();
  return 0;
}
