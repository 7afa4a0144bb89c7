// SPDX-License-Identifier: MIT
#include <Inventor/SoDB.h>
#include <Inventor/SoInput.h>
#include <Inventor/SoOutput.h>
#include <Inventor/actions/SoWriteAction.h>
#include <Inventor/fields/SoMFDouble.h>
#include <Inventor/fields/SoMFVec3d.h>
#include <Inventor/fields/SoSFDouble.h>
#include <Inventor/fields/SoSFVec2d.h>
#include <Inventor/fields/SoSFVec3d.h>
#include <Inventor/lists/SoFieldList.h>
#include <Inventor/nodes/SoSubNode.h>
#include <algorithm>
#include <catch2/catch.hpp>
#include <charconv>
#include <clocale>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <limits>
#include <random>

#include "NodesTestUtil.h"
#include "../support/Skip.h"
#include "bsdeform/SceneText.h"

using namespace bsdeform;

namespace {
double readWithCoin(const std::string& text) {
  SoInput in;
  in.setBuffer(text.c_str(), text.size());
  double d = NAN;
  REQUIRE(in.read(d));
  return d;
}
}  // namespace

TEST_CASE("SceneText: the emulated reader computes what Coin's reader computes", "[nodes]") {
  testutil::Coin::get();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> mant(1.0, 10.0);
  std::uniform_int_distribution<int> ex(-20, 8);
  int mismatches = 0, inexact = 0;
  for (int i = 0; i < 4000; ++i) {
    const double x = (i % 2 ? -1 : 1) * mant(rng) * std::pow(10.0, ex(rng));
    char buf[40];
    std::snprintf(buf, sizeof buf, i % 3 ? "%.15g" : "%.16g", x);
    double emulated = 0.0;
    REQUIRE(coinReadReal(buf, emulated));
    const double coin = readWithCoin(buf);
    mismatches += emulated != coin;
    inexact += coin != std::strtod(buf, nullptr);
  }
  CHECK(mismatches == 0);
  CHECK(inexact > 100);  // Coin's reader really is inexact, so the check above means something
}

TEST_CASE("SceneText: every double written is read back by Coin to its 15-digit value", "[nodes]") {
  testutil::Coin::get();
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> mant(1.0, 10.0);
  std::uniform_int_distribution<int> ex(-25, 12);
  const double hard[] = {0.000983542385712959, 0.05, 0.3, 1e-5, 123456.789, 0.0, -0.0625};
  auto check = [](double x) {
    const std::string text = coinDoubleText(x);
    INFO(x << " written as " << text);
    CHECK(snap15(readWithCoin(text)) == snap15(x));
  };
  for (double x : hard) check(x);
  for (int i = 0; i < 4000; ++i) check(mant(rng) * std::pow(10.0, ex(rng)));
  // readable where possible: short decimals stay as they are
  CHECK(coinDoubleText(0.1) == "0.1");
  CHECK(coinDoubleText(2.5) == "2.5");
  CHECK(coinDoubleText(0.000983542385712959) == "983542385712959e-18");
}

TEST_CASE("SceneText: a scene streams in pieces of at most a megabyte, and a failing sink stops it", "[nodes]") {
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE "
                                     "numUControlPoints 160 numVControlPoints 160 "
                                     "forces SoForceField { type UNIFORM force 0 0 5 } } }");
  REQUIRE(root);
  testutil::find<SoBSplineDeformSurface>(root)->stepSimulation(2);
  std::vector<std::size_t> pieces;
  std::string streamed;
  CHECK(writeSceneText(root, [&](const char* data, std::size_t size) {
    pieces.push_back(size);
    streamed.append(data, size);
    return true;
  }));
  CHECK(streamed.size() > 3u << 20);  // three nets of 166^2 points
  CHECK(pieces.size() >= 3);
  CHECK(*std::max_element(pieces.begin(), pieces.end()) <= std::size_t(1) << 20);
  CHECK(streamed == testutil::write(root));
  // the sink fails on the second piece: writing stops there and says so
  int calls = 0;
  CHECK_FALSE(writeSceneText(root, [&](const char*, std::size_t) { return ++calls < 2; }));
  CHECK(calls == 2);
  root->unref();
}

// ---------------------------------------------------------------------------------------------
// The former writer (before issue 11), kept here as the reference: the number text and the
// scene text of today's writer must be byte-identical to what it wrote. Its strtod is the "C"
// locale's (the test process does not call setlocale); it read wrongly under a decimal-comma
// locale, which the writer of today does not (see the locale test below).
namespace reference {

double snap15(double x) {
  if (!std::isfinite(x)) return x;
  char buf[40];
  const auto r = std::to_chars(buf, buf + sizeof buf - 1, x, std::chars_format::general, 15);
  *r.ptr = '\0';
  return std::strtod(buf, nullptr);
}

std::string coinDoubleText(double x) {
  char buf[48];
  if (!std::isfinite(x)) {
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
  }
  auto text = std::to_chars(buf, buf + sizeof buf - 1, x, std::chars_format::general, 15);
  *text.ptr = '\0';
  const double target = std::strtod(buf, nullptr);
  double read = 0.0;
  if (bsdeform::coinReadReal(buf, read) && snap15(read) == target) return buf;
  auto sci = std::to_chars(buf, buf + sizeof buf - 1, target, std::chars_format::scientific, 14);
  *sci.ptr = '\0';
  const char* e = std::strchr(buf, 'e');
  std::string mantissa;
  for (const char* p = buf; p < e; ++p)
    if (*p != '.') mantissa += *p;
  int exponent = std::atoi(e + 1) - 14;
  while (mantissa.size() > 1 && mantissa.back() == '0') mantissa.pop_back(), ++exponent;
  std::string out = mantissa + (exponent ? "e" + std::to_string(exponent) : std::string());
  if (bsdeform::coinReadReal(out.c_str(), read) && snap15(read) == target) return out;
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

class Output : public SoOutput {
 public:
  void write(const double d) override {
    if (isBinary()) return SoOutput::write(d);
    SoOutput::write(coinDoubleText(d).c_str());
  }
  using SoOutput::write;
};

std::string sceneText(SoNode* root) {
  Output out;
  out.setBuffer(std::malloc(1024), 1024, std::realloc);
  SoWriteAction wa(&out);
  wa.apply(root);
  void* buf = nullptr;
  size_t size = 0;
  out.getBuffer(buf, size);
  std::string text(static_cast<const char*>(buf), size);
  std::free(buf);
  return text;
}

}  // namespace reference

namespace {

// Doubles a writer can get wrong: both zeros, subnormals, the ends of the range, powers of ten
// and their neighbours (the 15-digit grid changes there), short decimals, values next to a
// halfway point of the 15-digit rounding (where the shortest form of x and x itself round
// differently) and their neighbours.
std::vector<double> edgeValues() {
  std::vector<double> v = {0.0, -0.0, 0.1, 0.2, 0.3, -0.3, 0.05, 1.0, -1.0, 2.5, 1e-5, 1e-4, 1e15, 1e16, 123456.789,
                           0.000983542385712959, 1e-300, -1e-300, 1e300, -1e300,
                           std::numeric_limits<double>::min(), std::numeric_limits<double>::max(),
                           -std::numeric_limits<double>::max(), std::numeric_limits<double>::denorm_min(),
                           -std::numeric_limits<double>::denorm_min(), 4.9406564584124654e-324 * 12345,
                           std::nextafter(std::numeric_limits<double>::min(), 0.0), 2.2250738585072014e-308 * 0.5,
                           1e-310, 9.99999999999999e-5, 9.999999999999995e-5, 9.9999999999999949e-5,
                           9.9999999999999951e-5, 999999999999999.5, 99999999999999.95, 0.9999999999999995,
                           0.99999999999999949, 0.99999999999999951, 100000000000000.5, 1000000000000000.5,
                           0.1000000000000005, 0.12345678901234549, 0.12345678901234551, 1.0000000000000049,
                           1.0000000000000051, 5e-324, 1.7976931348623157e308, 0.5, 0.25, 1.0 / 3.0, 2.0 / 3.0,
                           3.141592653589793, 6.02214076e23, 1.602176634e-19, 299792458.0, 4503599627370496.5,
                           9007199254740993.0, 123456789012345678.0, 0.000123456789012345, 1.23456789012345e-5};
  // decimal halfway points of the 15-digit rounding, read correctly, and their neighbours
  std::mt19937_64 rng(17);
  std::uniform_int_distribution<long long> mant(100000000000000LL, 999999999999999LL);
  std::uniform_int_distribution<int> ex(-320, 300), exMid(-25, 1);  // all doubles; 1e-10 .. 1e16
  for (int i = 0; i < 6000; ++i) {
    const std::string s = std::to_string(mant(rng)) + (i % 3 == 0 ? "5" : i % 3 == 1 ? "49999" : "50001") + "e" +
                          std::to_string(i % 2 ? ex(rng) : exMid(rng));
    const double x = std::strtod(s.c_str(), nullptr);
    for (double y : {x, std::nextafter(x, 0.0), std::nextafter(x, INFINITY)}) v.push_back(i % 2 ? -y : y);
  }
  // the ends of the range that is rounded by arithmetic (1e-7 .. 1e15), and its steps
  for (double p : {1e-7, 1e-8, 1e14, 1e15, 99999999999999.5, 100000000000000.5, 999999999999999.4}) {
    double y = p;
    for (int i = 0; i < 40; ++i) y = std::nextafter(y, 0.0), v.push_back(y);
    y = p;
    for (int i = 0; i < 40; ++i) y = std::nextafter(y, INFINITY), v.push_back(y);
  }
  for (int e = -323; e <= 308; ++e) {
    const double p = std::strtod(("1e" + std::to_string(e)).c_str(), nullptr);
    for (double y : {p, std::nextafter(p, 0.0), std::nextafter(p, INFINITY), p * 3, p * 0.7}) v.push_back(y);
  }
  return v;
}

// Random doubles: every bit pattern (all exponents, subnormals, no NaN or infinity) and values as
// a simulation makes them (O(1), full precision, and their 15-digit snaps).
std::vector<double> randomValues(int count) {
  std::vector<double> v;
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> unit(-2.0, 2.0);
  while (int(v.size()) < count) {
    std::uint64_t bits = rng();
    double x;
    std::memcpy(&x, &bits, sizeof x);
    if (std::isfinite(x)) v.push_back(x);
    const double y = unit(rng) * std::pow(10.0, double(int(rng() % 9)) - 6.0);
    v.push_back(y);
    v.push_back(reference::snap15(y));
  }
  return v;
}

// The edge values and `randomCount` random ones, cut to whole points (triples) for a control net.
std::vector<double> netValues(int randomCount) {
  std::vector<double> values = edgeValues();
  const std::vector<double> random = randomValues(randomCount);
  values.insert(values.end(), random.begin(), random.end());
  values.resize(values.size() / 3 * 3);
  return values;
}

// A node with double fields of every shape, for writing arbitrary values.
class SceneTextProbe : public SoNode {
  SO_NODE_HEADER(SceneTextProbe);

 public:
  static void initClass() {
    if (getClassTypeId() == SoType::badType()) SO_NODE_INIT_CLASS(SceneTextProbe, SoNode, "Node");
  }
  SceneTextProbe() {
    SO_NODE_CONSTRUCTOR(SceneTextProbe);
    SO_NODE_ADD_FIELD(vectors, (SbVec3d(0, 0, 0)));
    SO_NODE_ADD_FIELD(numbers, (0.0));
    SO_NODE_ADD_FIELD(number, (0.0));
  }
  SoMFVec3d vectors;
  SoMFDouble numbers;
  SoSFDouble number;

 protected:
  ~SceneTextProbe() override = default;
};
SO_NODE_SOURCE(SceneTextProbe);

// A scene with the probe (values as given) inside a group, next to a stepped surface.
SoSeparator* probeScene(const std::vector<double>& values) {
  testutil::Coin::get();
  SceneTextProbe::initClass();
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { Separator { DEF S SoBSplineDeformSurface { "
                                     "on FALSE numUControlPoints 12 numVControlPoints 9 uDegree 2 damping 0.7 forces [ "
                                     "SoForceField { type REGION force 0 0.3 1 magnitude 60 regionMin 0.3 0.2 regionMax "
                                     "0.7 0.9 }, SoForceField { type POINT point 0.13 0.71 force 0 0 -0.3 } ] } } }");
  REQUIRE(root);
  testutil::find<SoBSplineDeformSurface>(root)->stepSimulation(3);
  auto* probe = new SceneTextProbe;
  auto* group = new SoSeparator;
  group->addChild(probe);
  root->addChild(group);
  probe->numbers.setValues(0, int(values.size()), values.data());
  probe->vectors.setNum(int(values.size() / 3));
  for (int i = 0; i < int(values.size() / 3); ++i)
    probe->vectors.set1Value(i, values[3 * i], values[3 * i + 1], values[3 * i + 2]);
  probe->number.setValue(values.empty() ? 0.0 : values.back());
  return root;
}

}  // namespace

TEST_CASE("SceneText: snap15 and coinDoubleText equal the former definitions value by value", "[nodes]") {
  testutil::Coin::get();
  std::vector<double> values = edgeValues();
  const std::vector<double> random = randomValues(200000);
  values.insert(values.end(), random.begin(), random.end());
  values.push_back(INFINITY);
  values.push_back(-INFINITY);
  values.push_back(std::nan(""));
  values.push_back(-std::nan(""));
  long textMismatches = 0, snapMismatches = 0;
  for (double x : values) {
    const std::string text = coinDoubleText(x), expected = reference::coinDoubleText(x);
    const double snap = snap15(x), expectedSnap = reference::snap15(x);
    const bool sameSnap = std::isnan(x) ? std::isnan(snap)
                                        : std::memcmp(&snap, &expectedSnap, sizeof snap) == 0;  // -0 too
    if (text != expected || !sameSnap) {
      if (textMismatches + snapMismatches < 10)
        UNSCOPED_INFO("x = " << std::setprecision(17) << x << ": text '" << text << "' expected '"
                                                 << expected << "', snap " << snap << " expected " << expectedSnap);
    }
    textMismatches += text != expected;
    snapMismatches += !sameSnap;
  }
  CHECK(values.size() > 200000u);
  CHECK(textMismatches == 0);
  CHECK(snapMismatches == 0);
}

TEST_CASE("SceneText: scene text is byte-identical to the former writer's", "[nodes]") {
  const std::vector<double> values = netValues(30000);
  SoSeparator* root = probeScene(values);
  const std::string text = testutil::write(root), expected = reference::sceneText(root);
  CHECK(text.size() > 1000000u);
  CHECK(text.find("SceneTextProbe") != std::string::npos);
  CHECK(text.find("controlNet") != std::string::npos);
  CHECK(text == expected);
  if (text != expected) {
    const auto where = std::mismatch(text.begin(), text.end(), expected.begin(), expected.end());
    const std::size_t at = std::size_t(where.first - text.begin());
    INFO("first difference at byte " << at << ": '" << text.substr(at > 40 ? at - 40 : 0, 80) << "' expected '"
                                     << expected.substr(at > 40 ? at - 40 : 0, 80) << "'");
    CHECK(false);
  }
  root->unref();
}

namespace {
// Switches the whole process to `name` (LC_ALL) for its lifetime; back to "C" after.
struct LocaleScope {
  bool active;
  explicit LocaleScope(const char* name) : active(std::setlocale(LC_ALL, name) != nullptr) {}
  ~LocaleScope() { std::setlocale(LC_ALL, "C"); }
};
}  // namespace

TEST_CASE("SceneText: text and snaps do not depend on the process locale (decimal comma)", "[nodes]") {
  const std::vector<double> values = netValues(20000);
  SoSeparator* root = probeScene(values);
  const std::string inC = testutil::write(root);
  SoSeparator* surface = probeScene({});  // the surface alone: a scene Coin reads back
  const std::string surfaceInC = testutil::write(surface);
  std::vector<std::string> textsInC;
  std::vector<double> snapsInC;
  for (double x : values) textsInC.push_back(coinDoubleText(x)), snapsInC.push_back(snap15(x));
  {
    // Qt programs (the viewer, bsdeform-run) call setlocale(LC_ALL, "") at start: a user's
    // LANG=de_DE.UTF-8 is the process locale there.
    const std::string locale = testsupport::testLocale();
    LocaleScope de(locale.c_str());
    if (!de.active) {
      BSDEFORM_TEST_SKIP("the locale " + locale + " is not installed (scripts/common.sh generates it with " +
                         "localedef); the locale independence of scene text was not checked");
      root->unref();
      surface->unref();
      return;
    }
    REQUIRE(std::string(std::localeconv()->decimal_point) == ",");
    CHECK(std::strtod("0.5", nullptr) == 0.0);  // the C library reads with a comma now
    CHECK(testutil::write(root) == inC);
    long differences = 0;
    for (size_t i = 0; i < values.size(); ++i)
      differences += coinDoubleText(values[i]) != textsInC[i] || !(snap15(values[i]) == snapsInC[i]);
    CHECK(differences == 0);
    // reading snaps every double (SoBSplineDeformSurface::readInstance): the same state back
    SoSeparator* back = testutil::read(surfaceInC);
    REQUIRE(back);
    CHECK(testutil::write(back) == surfaceInC);
    back->unref();
  }
  root->unref();
  surface->unref();
}

TEST_CASE("SceneText: a list of references written reads back, by our reader and by Coin's own", "[nodes]") {
  // Issue 37, item 0: Coin lays out `obstacles` as `USE A,` newline `USE B ]`, which its own
  // reader refuses ("Unknown reference "A,""): the saved scene could not be opened again.
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { DEF A Cube { } DEF B Sphere { }\n"
                                     "SoBSplineDeformSurface { on FALSE forces [ SoForceField { type COLLISION "
                                     "obstacles [ USE A , USE B ] } ] } }\n");
  REQUIRE(root);
  const std::string text = testutil::write(root);
  root->unref();
  INFO(text);
  CHECK(text.find("USE A,") == std::string::npos);
  auto obstaclesOf = [](SoSeparator* r) {
    auto* field = testutil::find<SoBSplineDeformSurface>(r);
    REQUIRE(field);
    auto* ff = static_cast<SoForceField*>(static_cast<SoEngine*>(field->forces[0]));
    return std::vector<std::string>{ff->obstacles.getNum() > 0 ? ff->obstacles[0]->getName().getString() : "",
                                    ff->obstacles.getNum() > 1 ? ff->obstacles[1]->getName().getString() : "",
                                    std::to_string(ff->obstacles.getNum())};
  };
  SoSeparator* ours = testutil::read(text);
  REQUIRE(ours);
  CHECK(obstaclesOf(ours) == std::vector<std::string>{"A", "B", "2"});
  ours->unref();
  // Coin's reader without our guard, as any Coin program reads the file
  SoInput in;
  in.setBuffer(text.data(), text.size());
  SoSeparator* coins = SoDB::readAll(&in);
  REQUIRE(coins);
  coins->ref();
  CHECK(obstaclesOf(coins) == std::vector<std::string>{"A", "B", "2"});
  coins->unref();
}

TEST_CASE("SceneText: every double field of both nodes reads as written, found from the field data", "[nodes]") {
  // Issue 37, item 4: Coin's reader is a few ulps off (poissonRatio 0.243 read as
  // 0.24300000000000002) and the snapping after it listed fields by hand, missing the SHELL ones.
  testutil::Coin::get();
  std::string surface, force;
  auto* s0 = new SoBSplineDeformSurface;
  s0->ref();
  auto* f0 = new SoForceField;
  f0->ref();
  auto fieldsText = [](SoFieldContainer* c, std::string& text) {
    SoFieldList fields;
    const int n = c->getFields(fields);
    int listed = 0;
    for (int i = 0; i < n; ++i) {
      SbName name;
      c->getFieldName(fields[i], name);
      const SoType t = fields[i]->getTypeId();
      if (t == SoSFDouble::getClassTypeId()) text += std::string(" ") + name.getString() + " 0.243";
      else if (t == SoSFVec3d::getClassTypeId()) text += std::string(" ") + name.getString() + " 0.243 0.7 0.1";
      else if (t == SoSFVec2d::getClassTypeId()) text += std::string(" ") + name.getString() + " 0.243 0.7";
      else continue;
      ++listed;
    }
    return listed;
  };
  const int surfaceDoubles = fieldsText(s0, surface), forceDoubles = fieldsText(f0, force);
  CHECK(surfaceDoubles >= 16);  // the weights, the SHELL material, time step, shape sizes...
  CHECK(forceDoubles >= 10);
  SoSeparator* root = testutil::read("#Inventor V2.1 ascii\nSeparator { DEF Read SoBSplineDeformSurface {" + surface +
                                     " forces [ DEF ReadForce SoForceField {" + force + " } ] } }\n");
  REQUIRE(root);
  for (SoFieldContainer* c : {static_cast<SoFieldContainer*>(testutil::named<SoBSplineDeformSurface>("Read")),
                              static_cast<SoFieldContainer*>(testutil::named<SoForceField>("ReadForce"))}) {
    REQUIRE(c);
    SoFieldList fields;
    const int n = c->getFields(fields);
    for (int i = 0; i < n; ++i) {
      SbName name;
      c->getFieldName(fields[i], name);
      INFO(name.getString());
      const SoType t = fields[i]->getTypeId();
      if (t == SoSFDouble::getClassTypeId()) {
        CHECK(static_cast<SoSFDouble*>(fields[i])->getValue() == 0.243);
      } else if (t == SoSFVec3d::getClassTypeId()) {
        CHECK(static_cast<SoSFVec3d*>(fields[i])->getValue() == SbVec3d(0.243, 0.7, 0.1));
      } else if (t == SoSFVec2d::getClassTypeId()) {
        CHECK(static_cast<SoSFVec2d*>(fields[i])->getValue() == SbVec2d(0.243, 0.7));
      }
    }
  }
  root->unref();
  s0->unref();
  f0->unref();
}
