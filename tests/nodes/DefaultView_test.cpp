// SPDX-License-Identifier: MIT
#include <Inventor/SbViewportRegion.h>
#include <Inventor/nodes/SoCube.h>
#include <Inventor/nodes/SoPerspectiveCamera.h>
#include <Inventor/nodes/SoSeparator.h>
#include <Inventor/nodes/SoTranslation.h>
#include <catch2/catch.hpp>

#include "NodesTestUtil.h"
#include "bsdeform/DefaultView.h"
#include "bsdeform/OffscreenRenderer.h"

using namespace bsdeform;

namespace {
float distance(const SbVec3f& a, const SbVec3f& b) { return (a - b).length(); }
}  // namespace

TEST_CASE("DefaultView: every standard orientation looks along its direction with z (top: y) up", "[nodes]") {
  testutil::Coin::get();
  for (StandardView v : {StandardView::Default, StandardView::Front, StandardView::Top, StandardView::Side,
                         StandardView::Isometric}) {
    const SbRotation r = viewOrientation(v);
    SbVec3f look, up, right;
    r.multVec(SbVec3f(0, 0, -1), look);
    r.multVec(SbVec3f(0, 1, 0), up);
    r.multVec(SbVec3f(1, 0, 0), right);
    CHECK(distance(look, viewDirection(v)) < 1e-5f);
    const SbVec3f worldUp = v == StandardView::Top ? SbVec3f(0, 1, 0) : SbVec3f(0, 0, 1);
    // the screen's up is the world's up as far as the view allows: no roll
    CHECK(std::abs(right.dot(worldUp)) < 1e-5f);
    CHECK(up.dot(worldUp) > 0.0f);
  }
  // the default view is the runner's historical three-quarter view from the -y side
  CHECK(distance(viewDirection(StandardView::Default), SbVec3f(0.0f, 0.73f, -0.68f) / SbVec3f(0.0f, 0.73f, -0.68f).length()) < 1e-6f);
}

TEST_CASE("DefaultView: the framed unit square lies inside the view, centred, and fills 80 % of it", "[nodes]") {
  testutil::Coin::get();
  // a thin box standing for the plane surface S = (u, v, 0) on [0, 1]^2
  auto* root = new SoSeparator;
  root->ref();
  auto* camera = new SoPerspectiveCamera;
  root->addChild(camera);
  auto* move = new SoTranslation;
  move->translation.setValue(0.5f, 0.5f, 0.0f);
  root->addChild(move);
  auto* square = new SoCube;
  square->width = 1.0f;
  square->height = 1.0f;
  square->depth = 0.01f;
  root->addChild(square);
  const SbBox3f box(SbVec3f(0, 0, -0.005f), SbVec3f(1, 1, 0.005f));
  for (const SbVec2s size : {SbVec2s(800, 600), SbVec2s(400, 800)}) {
    const SbViewportRegion vp(size);
    frameView(camera, root, vp);
    const SbBox2f p = projectedBox(camera, box, vp);
    float x0, y0, x1, y1;
    p.getBounds(x0, y0, x1, y1);
    INFO("projected " << x0 << " " << y0 << " - " << x1 << " " << y1 << " at " << size[0] << "x" << size[1]);
    CHECK(x0 > 0.0f);
    CHECK(y0 > 0.0f);
    CHECK(x1 < 1.0f);
    CHECK(y1 < 1.0f);
    CHECK(std::max(x1 - x0, y1 - y0) == Approx(kFramedFraction).margin(0.02));
    CHECK(0.5f * (x0 + x1) == Approx(0.5f).margin(0.05));  // centred
    CHECK(0.5f * (y0 + y1) == Approx(0.5f).margin(0.05));
    // moved out of the view, the box projects beyond its edge
    const SbBox3f moved(box.getMin() + SbVec3f(3, 0, 0), box.getMax() + SbVec3f(3, 0, 0));
    CHECK(projectedBox(camera, moved, vp).getMax()[0] > 1.0f);
  }
  CHECK(findSceneCamera(root) == camera);
  CHECK(findSceneCamera(square) == nullptr);
  root->unref();
}

TEST_CASE("DefaultView: an open surface seen from below is lit like seen from above (two-sided lighting)", "[nodes]") {
  testutil::Coin::get();
  SoSeparator* scene = testutil::read(
      "#Inventor V2.1 ascii\nSeparator { Material { diffuseColor 0.8 0.5 0.2 } SoBSplineDeformSurface { } }");
  REQUIRE(scene);
  auto meanLit = [&](const SbVec3f& direction) {
    auto* root = new SoSeparator;
    root->ref();
    auto* camera = new SoPerspectiveCamera;
    root->addChild(camera);
    root->addChild(scene);
    camera->orientation = lookOrientation(direction, SbVec3f(0, 1, 0));
    frameScene(camera, root, SbViewportRegion(120, 90));
    bsdeform::Image img;
    std::string error;
    REQUIRE(bsdeform::renderOffscreen(root, 120, 90, img, error, SbColor(0, 0, 0)));
    root->unref();
    double sum = 0.0;
    long n = 0;
    for (size_t i = 0; i < img.rgb.size(); i += 3)
      if (img.rgb[i] | img.rgb[i + 1] | img.rgb[i + 2]) {
        sum += img.rgb[i];
        ++n;
      }
    REQUIRE(n > 1000);  // the surface covers a good part of the picture
    return sum / n;
  };
  const double above = meanLit(SbVec3f(0.1f, 0.2f, -1.0f)), below = meanLit(SbVec3f(0.1f, 0.2f, 1.0f));
  INFO("mean red of the surface from above " << above << ", from below " << below);
  CHECK(above > 100.0);
  CHECK(below > 0.8 * above);  // one-sided lighting leaves the underside at the ambient level
  scene->unref();
}
