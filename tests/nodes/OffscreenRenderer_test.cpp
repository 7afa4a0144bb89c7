// SPDX-License-Identifier: MIT
#include <Inventor/SbViewportRegion.h>
#include <Inventor/actions/SoGetBoundingBoxAction.h>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <png.h>

#include "NodesTestUtil.h"
#include "bsdeform/OffscreenRenderer.h"

namespace {
const SbColor kBackground(0.0f, 0.0f, 0.0f);

bsdeform::Image render(SoNode* root, int w = 160, int h = 120) {
  bsdeform::Image img;
  std::string error;
  INFO(error);
  REQUIRE(bsdeform::renderOffscreen(root, w, h, img, error, kBackground));
  return img;
}

// Fraction of pixels that are not background, and of pixels where the colour is dominated by
// channel c (c = 0 red, 1 green, 2 blue).
double coverage(const bsdeform::Image& img) {
  size_t n = 0;
  for (size_t i = 0; i < img.rgb.size(); i += 3) n += (img.rgb[i] | img.rgb[i + 1] | img.rgb[i + 2]) != 0;
  return double(n) / (img.width * img.height);
}
double dominated(const bsdeform::Image& img, int c) {
  size_t n = 0;
  for (size_t i = 0; i < img.rgb.size(); i += 3) {
    const int v = img.rgb[i + c], o1 = img.rgb[i + (c + 1) % 3], o2 = img.rgb[i + (c + 2) % 3];
    n += v > 40 && v > 2 * o1 && v > 2 * o2;
  }
  return double(n) / (img.width * img.height);
}
}  // namespace

TEST_CASE("OffscreenRenderer: a deformed surface renders, is not blank and differs from the flat one", "[nodes]") {
  const char* scene = "#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { numUControlPoints 10 "
                      "numVControlPoints 10 on FALSE forces SoForceField { type REGION force 0.3 0 1 magnitude 80 } } }";
  SoSeparator* a = testutil::read(scene);
  SoSeparator* b = testutil::read(scene);
  REQUIRE((a && b));
  testutil::find<SoBSplineDeformSurface>(b)->stepSimulation(30);
  const bsdeform::Image flat = render(a), bent = render(b);
  CHECK(coverage(flat) > 0.2);
  CHECK(coverage(bent) > 0.2);
  size_t differing = 0;
  for (size_t i = 0; i < flat.rgb.size(); ++i) differing += std::abs(int(flat.rgb[i]) - int(bent.rgb[i])) > 8;
  CHECK(double(differing) / flat.rgb.size() > 0.05);
  // and it writes a PNG
  const std::string path = "offscreen_test.png";
  std::string error;
  REQUIRE(bsdeform::writePng(bent, path, error));
  std::ifstream f(path, std::ios::binary);
  char sig[8] = {};
  f.read(sig, 8);
  CHECK(std::string(sig + 1, 3) == "PNG");
  std::remove(path.c_str());
  CHECK_FALSE(bsdeform::writePng(bent, "/nonexistent-dir/x.png", error));
  CHECK(error.find("/nonexistent-dir/x.png") != std::string::npos);
  a->unref();
  b->unref();
}

TEST_CASE("OffscreenRenderer: SoMaterial, SoTexture2 and SoTransform compose with the surface", "[nodes]") {
  SoSeparator* green = testutil::read("#Inventor V2.1 ascii\nSeparator { Material { diffuseColor 0 1 0 } "
                                      "SoBSplineDeformSurface { on FALSE } }");
  REQUIRE(green);
  const bsdeform::Image g = render(green);
  CHECK(dominated(g, 1) > 0.2);
  CHECK(dominated(g, 0) < 0.01);
  // a 2 x 2 red/blue checker texture mapped by (u, v)
  SoSeparator* tex = testutil::read("#Inventor V2.1 ascii\nSeparator { Texture2 { image 2 2 3 0xff0000 0x0000ff "
                                    "0x0000ff 0xff0000 model DECAL } SoBSplineDeformSurface { on FALSE } }");
  REQUIRE(tex);
  const bsdeform::Image t = render(tex);
  CHECK(dominated(t, 0) > 0.02);
  CHECK(dominated(t, 2) > 0.02);
  // texel (0,0) is red and lies at small (u, v): bottom left (u to the right, v up); the
  // checker alternates, so each image quadrant is dominated by the expected colour
  auto redMinusBlue = [&](bool right, bool top) {
    long diff = 0;
    for (int y = top ? 0 : t.height / 2; y < (top ? t.height / 2 : t.height); ++y)
      for (int x = right ? t.width / 2 : 0; x < (right ? t.width : t.width / 2); ++x) {
        const unsigned char* p = &t.rgb[(size_t(y) * t.width + x) * 3];
        diff += long(p[0]) - long(p[2]);
      }
    return diff;
  };
  CHECK(redMinusBlue(false, false) > 0);
  CHECK(redMinusBlue(true, false) < 0);
  CHECK(redMinusBlue(false, true) < 0);
  CHECK(redMinusBlue(true, true) > 0);
  // transforms move the bounding box
  SoSeparator* moved = testutil::read("#Inventor V2.1 ascii\nSeparator { Transform { translation 2 0 0 scaleFactor 3 3 3 } "
                                      "SoBSplineDeformSurface { on FALSE } }");
  SoGetBoundingBoxAction bba(SbViewportRegion(100, 100));
  bba.apply(moved);
  CHECK(bba.getBoundingBox().getMin()[0] == Approx(2.0).margin(1e-5));
  CHECK(bba.getBoundingBox().getMax()[0] == Approx(5.0).margin(1e-5));
  green->unref();
  tex->unref();
  moved->unref();
}

TEST_CASE("OffscreenRenderer: a renderer kept across frames gives the pixels of a fresh one", "[nodes]") {
  // the runner keeps one renderer (one GL context, Coin's caches) for all frames of a run
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { Material { diffuseColor 0.9 0.5 0.2 } "
                                     "SoBSplineDeformSurface { numUControlPoints 12 numVControlPoints 12 on FALSE "
                                     "forces SoForceField { type REGION force 0.3 0 1 magnitude 80 } } }");
  REQUIRE(root);
  auto* surface = testutil::find<SoBSplineDeformSurface>(root);
  bsdeform::OffscreenRenderer kept;
  const int sizes[][2] = {{160, 120}, {160, 120}, {160, 120}, {96, 80}, {160, 120}};  // a new size: a new context
  bsdeform::Image previous;
  for (const auto& size : sizes) {
    surface->stepSimulation(10);
    bsdeform::Image fromKept, fromFresh;
    std::string error;
    REQUIRE(kept.render(root, size[0], size[1], fromKept, error));
    REQUIRE(bsdeform::renderOffscreen(root, size[0], size[1], fromFresh, error));
    CHECK(coverage(fromKept) > 0.2);
    CHECK(fromKept.width == size[0]);
    CHECK(fromKept.height == size[1]);
    INFO("frame " << &size - sizes);
    CHECK(fromKept.rgb == fromFresh.rgb);
    if (previous.width == size[0]) CHECK(previous.rgb != fromKept.rgb);  // the frames do change
    previous = fromKept;
  }
  root->unref();
}

TEST_CASE("OffscreenRenderer: the PNG decodes to the same pixels for every setting", "[nodes]") {
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE "
                                     "forces SoForceField { type REGION force 0.3 0 1 magnitude 80 } } }");
  REQUIRE(root);
  testutil::find<SoBSplineDeformSurface>(root)->stepSimulation(20);
  const bsdeform::Image img = render(root, 123, 77);  // rows not a multiple of 4 bytes
  root->unref();
  std::vector<bsdeform::PngSettings> settings{bsdeform::PngSettings()};
  for (int level : {0, 1, 6, 9})
    for (bool sub : {false, true}) settings.push_back(bsdeform::PngSettings{level, sub});
  for (const bsdeform::PngSettings& s : settings) {
    INFO("zlib level " << s.zlibLevel << (s.subFilterOnly ? ", SUB filter" : ", adaptive filters"));
    std::vector<unsigned char> png;
    REQUIRE(bsdeform::encodePng(img, png, s));
    png_image decoded;
    std::memset(&decoded, 0, sizeof decoded);
    decoded.version = PNG_IMAGE_VERSION;
    REQUIRE(png_image_begin_read_from_memory(&decoded, png.data(), png.size()));
    decoded.format = PNG_FORMAT_RGB;
    CHECK(decoded.width == png_uint_32(img.width));
    CHECK(decoded.height == png_uint_32(img.height));
    std::vector<unsigned char> pixels(PNG_IMAGE_SIZE(decoded));
    REQUIRE(png_image_finish_read(&decoded, nullptr, pixels.data(), 0, nullptr));
    CHECK(pixels == img.rgb);
  }
}
