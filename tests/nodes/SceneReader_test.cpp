// SPDX-License-Identifier: MIT
// The guard in front of Coin's reader: every construct known to crash, hang or exhaust Coin 4.0
// is refused with file, line and reason before Coin sees it (without the guard each of these
// inputs crashes or hangs the test process), and every scene we ship passes it.
#include <Inventor/actions/SoGetBoundingBoxAction.h>
#include <Inventor/nodes/SoSeparator.h>
#include <catch2/catch.hpp>
#include <cstdio>
#include <dirent.h>
#include <fstream>
#include <sstream>
#include <vector>
#include <unistd.h>

#include "NodesTestUtil.h"
#include "bsdeform/SceneGuard.h"
#include "bsdeform/SceneReader.h"

using namespace bsdeform;

namespace {
const std::string kHeader = "#Inventor V2.1 ascii\n";

SceneCheck check(const std::string& text) {
  testutil::Coin::get();
  return checkSceneText(text.data(), text.size(), "t.iv");
}

// Reads through the guard; on success the root is unref'ed again.
bool reads(const std::string& text, std::string& error) {
  testutil::Coin::get();
  SoSeparator* root = readSceneText(text.data(), text.size(), "t.iv", error);
  if (!root) return false;
  root->ref();
  root->unref();
  return true;
}

// `depth` nodes inside each other: depth - 1 Separators around a Cube.
std::string nested(int depth) {
  std::string s = kHeader;
  for (int i = 1; i < depth; ++i) s += "Separator {\n";
  s += "Cube {}\n";
  for (int i = 1; i < depth; ++i) s += "}\n";
  return s;
}

std::string tempDir() {
  char tmpl[] = "/tmp/bsdeform-reader-XXXXXX";
  REQUIRE(mkdtemp(tmpl));
  return tmpl;
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  REQUIRE(f.good());
}
}  // namespace

TEST_CASE("SceneReader: every scene we ship passes the guard and reads", "[nodes]") {
  testutil::Coin::get();
  DIR* d = opendir(BSDEFORM_SCENES_DIR);
  REQUIRE(d);
  int n = 0;
  while (dirent* e = readdir(d)) {
    const std::string name = e->d_name;
    if (name.size() < 4 || name.substr(name.size() - 3) != ".iv") continue;
    std::string error;
    SoSeparator* root = readSceneFile(std::string(BSDEFORM_SCENES_DIR) + "/" + name, error);
    INFO(name << ": " << error);
    CHECK(root);
    if (root) {
      root->ref();
      root->unref();
    }
    ++n;
  }
  closedir(d);
  CHECK(n >= 15);
}

TEST_CASE("SceneReader: a word longer than Coin's name table chunk is refused", "[nodes]") {
  testutil::Coin::get();
  // SbName copies into 65,504-byte chunks (namemap.cpp): 65,503 characters overflow.
  const std::string longName(65600, 'a');
  for (const std::string& text : {kHeader + "DEF " + longName + " Cube {}\n", kHeader + "\n\n" + longName + " {}\n",
                                  kHeader + "Cube { width " + longName + " }\n"}) {
    const SceneCheck c = check(text);
    CHECK_FALSE(c.ok);
    CHECK(c.file == "t.iv");
    CHECK(c.reason.find("65600 characters") != std::string::npos);
  }
  CHECK(check(kHeader + "\n\n" + longName + " {}\n").line == 4);
  // a long but safe name reads
  std::string error;
  CHECK(reads(kHeader + "DEF " + std::string(5000, 'b') + " Cube {}\n", error));
  // a string that may become an SbName is bounded too
  const SceneCheck s = check(kHeader + "Info { string \"" + std::string(70000, 'x') + "\" }\n");
  CHECK_FALSE(s.ok);
  CHECK(s.reason.find("quoted string of 70000") != std::string::npos);
}

TEST_CASE("SceneReader: 'fields [ ]' naming a field a known type lacks is refused", "[nodes]") {
  for (const char* type : {"Cube", "Separator", "SoBSplineDeformSurface", "SoForceField"}) {
    const SceneCheck c = check(kHeader + "Separator {\n  " + type + " { fields [ SFFloat bogus ] }\n}\n");
    INFO(type);
    CHECK_FALSE(c.ok);
    CHECK(c.line == 3);
    CHECK(c.reason.find("declares 'bogus'") != std::string::npos);
  }
  // what Coin writes for extension types (the fields they have) reads
  std::string error;
  CHECK(reads(kHeader + "SoBSplineDeformSurface { fields [ SFInt32 numUControlPoints, SFDouble w10 ] w10 0.5 }\n"
                        "Cube { fields [ SFFloat width ] width 2 }\n",
              error));
  INFO(error);
  CHECK(reads(kHeader + "MyUnknownThing { fields [ SFFloat width, MFVec3f points ] width 2 points [ 0 0 0, 1 1 1 ] }\n",
              error));
  // the same unknown type declared twice with different fields
  CHECK(reads(kHeader + "Other { fields [ SFFloat a ] a 1 }\nOther { fields [ SFVec3f a ] a 1 2 3 }\n", error));
  CHECK_FALSE(check(kHeader + "Cube { fields [ SFFloat width\n").ok);
}

TEST_CASE("SceneReader: a node or engine connected to itself is refused", "[nodes]") {
  const SceneCheck self = check(kHeader + "DEF E ElapsedTime {\n timeIn 0 = USE E.timeOut\n}\n");
  CHECK_FALSE(self.ok);
  CHECK(self.line == 3);
  CHECK(self.reason.find("USE E inside the definition of E") != std::string::npos);
  // a cycle through a second engine
  CHECK_FALSE(check(kHeader + "DEF A Calculator { a 0 = DEF B Calculator { a 0 = USE A.oa }.oa }\n").ok);
  // a group inside itself
  CHECK_FALSE(check(kHeader + "DEF G Separator { Cube {} USE G }\n").ok);
  // connections to finished engines and USE of finished nodes are fine
  std::string error;
  CHECK(reads(kHeader +
                  "DEF T ElapsedTime {}\nDEF C Calculator { a 0 = USE T.timeOut expression \"oa = a\" }\n"
                  "Translation { translation 0 0 0 = USE C.oA }\nDEF S Separator { Cube {} }\nUSE S\n",
              error));
  INFO(error);
  // a later DEF of the same name inside the body is a different object
  CHECK(check(kHeader + "DEF A Calculator { a 0 = DEF A Calculator { a 1 }.oa }\n").ok);
}

TEST_CASE("SceneReader: nesting is bounded below what overflows the stack", "[nodes]") {
  testutil::Coin::get();
  const SceneLimits limits;
  const SceneCheck deep = check(nested(12000));
  CHECK_FALSE(deep.ok);
  CHECK(deep.line == limits.maxNesting + 1 + 1);  // header line, then one Separator per line
  CHECK(deep.reason.find("nested 1001 deep") != std::string::npos);
  // the deepest scene allowed reads, gets a bounding box and writes back
  const std::string text = nested(limits.maxNesting);
  std::string error;
  SoSeparator* root = readSceneText(text.data(), text.size(), "deep.iv", error);
  REQUIRE(root);
  root->ref();
  SoGetBoundingBoxAction bb(SbViewportRegion(100, 100));
  bb.apply(root);
  CHECK(bb.getBoundingBox().getSize()[0] == Approx(2.0));
  const std::string back = sceneToText(root);
  CHECK(back.find("Cube") != std::string::npos);
  root->unref();
  // the limit is configurable
  SceneLimits shallow;
  shallow.maxNesting = 3;
  CHECK_FALSE(checkSceneText(text.data(), text.size(), "deep.iv", std::string(), shallow).ok);
}

TEST_CASE("SceneReader: an engine field holds engines only", "[nodes]") {
  const std::string surface = "DEF S SoBSplineDeformSurface {\n";
  for (const char* bad : {"forces [ 5 ]", "forces [ @ ]", "forces 5", "forces [ \"x\" ]", "forces [ Cube {} ]",
                          "forces [ DEF F Cube {} ]", "forces [ USE Nowhere ]"}) {
    const SceneCheck c = check(kHeader + surface + "  " + bad + "\n}\n");
    INFO(bad);
    CHECK_FALSE(c.ok);
    CHECK(c.line == 3);
    CHECK(c.reason.find("forces") != std::string::npos);
  }
  const SceneCheck node = check(kHeader + "DEF C Cube {}\n" + surface + " forces [ USE C ]\n}\n");
  CHECK_FALSE(node.ok);
  CHECK(node.reason.find("USE C is not an engine") != std::string::npos);
  std::string error;
  CHECK(reads(kHeader + "DEF F SoForceField { type UNIFORM force 0 0 1 }\n" + surface +
                  " forces [ DEF G SoForceField { type POINT }, USE F ]\n}\nSoBSplineDeformSurface { forces USE G }\n"
                  "SoBSplineDeformSurface { forces [] }\n",
              error));
  INFO(error);
}

TEST_CASE("SceneReader: engine fields declared by an unknown type hold engines only", "[nodes]") {
  // Coin reads `fields [ MFEngine forces ]` of an unknown type and then loops on `forces [ 5 ]`
  // exactly as for our own node's field.
  const SceneCheck c = check(kHeader + "Separator { Probe { fields [ MFEngine forces ]\n forces [ 5 ] } }\n");
  CHECK_FALSE(c.ok);
  CHECK(c.line == 3);
  CHECK(c.reason.find("forces") != std::string::npos);
  // an SFNode declared the same way is read as a node field; later instances keep the declaration
  CHECK_FALSE(check(kHeader + "Probe { fields [ SFNode n, SFFloat f ] n 5 }\n").ok);
  CHECK_FALSE(check(kHeader + "Probe { fields [ SoSFEngine e ] }\nProbe { e 5 }\n").ok);
  // ordinary declared fields and node values of the declared kind read as Coin reads them
  std::string error;
  const bool ok = reads(kHeader + "Probe { fields [ SFFloat f, SFNode n, MFNode m ] f 2 n Cube {} m [ Sphere {}, Cone {} ] }\n", error);
  INFO(error);
  CHECK(ok);
}

TEST_CASE("SceneReader: a type that is no node or engine is refused where a node is read", "[nodes]") {
  // A field or event type used as a node: Coin 4.0 casts it to SoBase and writes through it.
  for (const char* type : {"SFTrigger", "SoSFTrigger", "MFVec3d", "SoMouseButtonEvent"}) {
    const SceneCheck c = check(kHeader + "Separator {\n " + type + " { x } }\n");
    INFO(type);
    CHECK_FALSE(c.ok);
    CHECK(c.line == 3);
    CHECK(c.reason.find("neither a node nor an engine") != std::string::npos);
  }
  // An engine at the top level without a DEF name: Coin creates it, skips it and leaks it.
  const SceneCheck top = check(kHeader + "Cube {}\nSoForceField { }\n");
  CHECK_FALSE(top.ok);
  CHECK(top.line == 3);
  CHECK(top.reason.find("top level") != std::string::npos);
  // engines stay allowed where they can be used: DEF'ed at the top level, connections, engine fields
  std::string error;
  CHECK(reads(kHeader + "DEF E ElapsedTime { }\nSeparator { Translation { translation 0 0 0 = USE E.timeOut } }\n", error));
  CHECK(reads(kHeader + "Separator { Translation { translation 0 0 0 = ElapsedTime { } . timeOut } }\n", error));
  CHECK(reads(kHeader + "Separator { DEF T Transform { } Rotor { speed 0 = DEF E ElapsedTime { } . timeOut } }\n", error));
  INFO(error);
}

TEST_CASE("SceneReader: a NUL byte is refused, not looped on", "[nodes]") {
  const std::string text = kHeader + "Separator {\n Cube { wid" + std::string(1, '\0') + "th 1 } }\n";
  const SceneCheck c = check(text);
  CHECK_FALSE(c.ok);
  CHECK(c.line == 3);
  CHECK(c.reason.find("NUL") != std::string::npos);
}

TEST_CASE("SceneReader: File includes are checked too, and may not include themselves", "[nodes]") {
  testutil::Coin::get();
  const std::string dir = tempDir();
  writeFile(dir + "/part.iv", kHeader + "Separator {\n Cube {}\n}\n");
  writeFile(dir + "/bad.iv", kHeader + "\nSoBSplineDeformSurface { forces [ 5 ] }\n");
  writeFile(dir + "/loop.iv", kHeader + "File { name \"loop.iv\" }\n");
  writeFile(dir + "/main.iv", kHeader + "File { name \"part.iv\" }\n");
  writeFile(dir + "/main_bad.iv", kHeader + "Separator { File { name \"bad.iv\" } }\n");
  std::string error;
  SoSeparator* root = readSceneFile(dir + "/main.iv", error);
  INFO(error);
  REQUIRE(root);
  root->ref();
  SoGetBoundingBoxAction bb(SbViewportRegion(100, 100));
  bb.apply(root);
  CHECK(bb.getBoundingBox().getSize()[0] == Approx(2.0));
  root->unref();
  CHECK_FALSE(readSceneFile(dir + "/main_bad.iv", error));
  CHECK(error.find("bad.iv:3:") != std::string::npos);
  CHECK_FALSE(readSceneFile(dir + "/loop.iv", error));
  CHECK(error.find("includes itself") != std::string::npos);
  // nesting counts across includes
  writeFile(dir + "/deep_part.iv", nested(600));
  writeFile(dir + "/deep_main.iv", nested(500).replace(nested(500).find("Cube {}"), 7, "File { name \"deep_part.iv\" }"));
  CHECK_FALSE(readSceneFile(dir + "/deep_main.iv", error));
  CHECK(error.find("deep_part.iv:") != std::string::npos);
  for (const char* f : {"part.iv", "bad.iv", "loop.iv", "main.iv", "main_bad.iv", "deep_part.iv", "deep_main.iv"})
    std::remove((dir + "/" + f).c_str());
  rmdir(dir.c_str());
}

TEST_CASE("SceneReader: file problems are named with the system's reason", "[nodes]") {
  testutil::Coin::get();
  std::string error;
  CHECK_FALSE(readSceneFile("/nonexistent/x.iv", error));
  CHECK(error == "/nonexistent/x.iv: No such file or directory");
  CHECK_FALSE(readSceneFile("/tmp", error));
  CHECK(error.find("is a directory") != std::string::npos);
  // binary and compressed files are not scanned, so not read
  CHECK_FALSE(check("#Inventor V2.1 binary\n\x01\x02").ok);
  CHECK_FALSE(check(std::string("\x1f\x8b\x08\x00", 4)).ok);
  // malformed text Coin itself would refuse gets a position
  const SceneCheck unclosed = check(kHeader + "Info { string \"abc\n}\n");
  CHECK_FALSE(unclosed.ok);
  CHECK(unclosed.line == 2);
  CHECK_FALSE(check(kHeader + "Cube {}\n}\n").ok);
  // Coin's own read errors come back in the message
  CHECK_FALSE(reads(kHeader + "Cube { width }\n", error));
  CHECK(error.find("t.iv: ") == 0);
}

// One entry per function of bsdeform/SceneGuard.h (one per hazard of docs/reliability.md): the
// file on disk is refused by readSceneFile with "FILE:LINE: problem", and the function itself
// passes the harmless neighbour of its hazard.
TEST_CASE("SceneReader: each guard function refuses its hazard with the file, the line and the problem", "[nodes]") {
  testutil::Coin::get();
  struct Hazard {
    const char* guard;
    std::string text;
    int line;
    const char* problem;
  };
  const std::vector<Hazard> hazards = {
      {"longName", kHeader + "DEF " + std::string(65600, 'n') + " Cube {}\n", 2, "a name of 65600 characters"},
      {"undeclaredField", kHeader + "Cube { fields [ SFFloat bogus ] }\n", 2, "declares 'bogus', which Cube does not have"},
      {"selfReference", kHeader + "DEF E ElapsedTime {\n timeIn 0 = USE E.timeOut\n}\n", 3,
       "USE E inside the definition of E itself"},
      {"deepNesting", nested(1001), 1002, "nodes nested 1001 deep"},
      {"wrongItemInField", kHeader + "SoBSplineDeformSurface {\n forces [ 5 ] }\n", 3,
       "field 'forces' holds engines; '5' is not an engine type"},
      {"itemFieldOfUnknownType", kHeader + "Probe { fields [ MFEngine forces ]\n forces [ 5 ] }\n", 3,
       "field 'forces' holds engines"},
      {"notANodeOrEngine", kHeader + "Separator { SFTrigger { x } }\n", 2, "'SFTrigger' is a Coin type that is neither"},
      {"unnamedTopLevelEngine", kHeader + "SoForceField { }\n", 2, "an engine without a DEF name"},
      {"nulByte", kHeader + "Cube { wid" + std::string(1, '\0') + "th 1 }\n", 2, "a NUL byte"},
      {"binaryOrCompressed", "#Inventor V2.1 binary\n\x01\x02", 1, "binary Inventor files are not read"},
  };
  const std::string dir = tempDir();
  const std::string path = dir + "/hazard.iv";
  for (const Hazard& h : hazards) {
    INFO(h.guard);
    writeFile(path, h.text);
    std::string error;
    CHECK_FALSE(readSceneFile(path, error));
    CHECK(error.rfind(path + ":" + std::to_string(h.line) + ": ", 0) == 0);
    CHECK(error.find(h.problem) != std::string::npos);
  }
  // the includes: a file including itself, an included file above the size limit
  writeFile(path, kHeader + "File { name \"hazard.iv\" }\n");
  std::string error;
  CHECK_FALSE(readSceneFile(path, error));
  CHECK(error.rfind(path + ":2: File includes 'hazard.iv', which includes itself", 0) == 0);
  writeFile(dir + "/big.iv", kHeader + "Cube {}\n" + std::string(200, '#') + "\n");
  writeFile(path, kHeader + "Separator {\n File { name \"big.iv\" } }\n");
  SceneLimits small;
  small.maxFileBytes = 100;
  CHECK_FALSE(readSceneFile(path, error, small));
  CHECK(error.rfind(path + ":3: File 'big.iv' has 230 bytes (at most 100)", 0) == 0);
  CHECK_FALSE(readSceneFile(dir + "/big.iv", error, small));
  CHECK(error == dir + "/big.iv: 230 bytes (a scene file may have at most 100)");
  std::remove(path.c_str());
  std::remove((dir + "/big.iv").c_str());
  rmdir(dir.c_str());

  // the harmless neighbours pass each function
  using namespace bsdeform::guard;
  const SceneLimits limits;
  CHECK(longName(65000, NameKind::Word, limits).empty());
  CHECK_FALSE(longName(65001, NameKind::QuotedString, limits).empty());
  CHECK(undeclaredField("Cube", fieldKinds(typeFromName("Cube")), "width", false).empty());
  CHECK(undeclaredField("Cube", fieldKinds(typeFromName("Cube")), "SFFloat", true).empty());
  CHECK_FALSE(undeclaredField("Cube", fieldKinds(typeFromName("Cube")), "exposedField", true).empty());
  CHECK(selfReference("E", false).empty());
  CHECK(deepNesting(1000, limits).empty());
  ItemValue engine;
  engine.form = ItemValue::Type;
  engine.text = "SoForceField";
  engine.type = typeFromName(engine.text);
  CHECK(wrongItemInField(FieldKind::Engine, "forces", engine).empty());
  CHECK_FALSE(wrongItemInField(FieldKind::Node, "children", engine).empty());
  CHECK(itemFieldOfUnknownType("MFEngine") == FieldKind::Engine);
  CHECK(itemFieldOfUnknownType("SFNode") == FieldKind::Node);
  CHECK(itemFieldOfUnknownType("SFFloat") == FieldKind::Other);
  CHECK(notANodeOrEngine(typeFromName("Cube"), "Cube").empty());
  CHECK(notANodeOrEngine(SoType::badType(), "Unknown").empty());
  CHECK(unnamedTopLevelEngine(typeFromName("SoForceField"), "SoForceField", true, true).empty());
  CHECK(unnamedTopLevelEngine(typeFromName("SoForceField"), "SoForceField", false, false).empty());
  CHECK(nulByte('a').empty());
  CHECK(binaryOrCompressed(kHeader.data(), kHeader.size()).empty());
  CHECK_FALSE(binaryOrCompressed("\x1f\x8b", 2).empty());
  CHECK_FALSE(largeFile(100, small));
  CHECK(largeFile(101, small));
  CHECK(includesItself("a.iv", "/x/a.iv", {"/x/b.iv"}).empty());
}

// Issue 37, item 0: `USE A,` is how people write a list of references and how Coin's writer
// lays one out; Coin's reader alone takes "A," as the name ("Unknown reference").
namespace {
const std::string kTwoObstacles = kHeader + R"(Separator {
  DEF A Cube { }
  DEF B Sphere { }
  SoBSplineDeformSurface {
    on FALSE
    forces [ DEF Contact SoForceField { type COLLISION obstacles [ USE A, USE B ] } ]
  }
}
)";
}  // namespace

TEST_CASE("SceneReader: obstacles [ USE A, USE B ] as a person writes it reads as two obstacles", "[nodes]") {
  SoSeparator* root = testutil::read(kTwoObstacles);
  INFO((testutil::Coin::get().messages.empty() ? std::string() : testutil::Coin::get().messages.back()));
  REQUIRE(root);
  auto* contact = testutil::named<SoForceField>("Contact");
  REQUIRE(contact);
  REQUIRE(contact->obstacles.getNum() == 2);
  CHECK(contact->obstacles[0] == testutil::named<SoNode>("A"));
  CHECK(contact->obstacles[1] == testutil::named<SoNode>("B"));
  root->unref();
}

TEST_CASE("SceneReader: a comma after a USE name is separated only where it ends a reference", "[nodes]") {
  testutil::Coin::get();
  std::string out;
  // no reference with a comma: nothing to do
  const std::string plain = "Separator { DEF A Cube { } Group { } }";
  CHECK(separateUseCommas(plain.data(), plain.size(), out) == 0);
  // a list without spaces, across lines; the lines stay where they were
  const std::string list = "DEF A Cube { } DEF B Cube { }\nG { f [ USE A,\n USE B,USE A ] }";
  REQUIRE(separateUseCommas(list.data(), list.size(), out) == 2);
  CHECK(out == "DEF A Cube { } DEF B Cube { }\nG { f [ USE A ,\n USE B ,USE A ] }");
  // in a comment or a string it is not a reference
  const std::string quoted = "# USE A,\nInfo { string \"USE A, USE B\" }";
  CHECK(separateUseCommas(quoted.data(), quoted.size(), out) == 0);
  // a name DEF'ed with the comma is that name
  const std::string odd = "DEF A, Cube { } Group { children [ USE A, ] }";
  CHECK(separateUseCommas(odd.data(), odd.size(), out) == 0);
}
