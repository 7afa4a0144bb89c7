// SPDX-License-Identifier: MIT
// The field table (bsdeform/FieldInfo.h): complete for both nodes, and the one source of the
// field reference in docs/nodes.md.
#include <Inventor/lists/SoFieldList.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "NodesTestUtil.h"
#include "bsdeform/FieldInfo.h"
#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace {

std::vector<std::string> fieldNames(SoFieldContainer* c) {
  SoFieldList fields;
  c->getFields(fields);
  std::vector<std::string> names;
  for (int i = 0; i < fields.getLength(); ++i) {
    SbName name;
    c->getFieldName(fields[i], name);
    names.emplace_back(name.getString());
  }
  return names;
}

std::vector<std::string> tableNames(const char* node) {
  std::vector<std::string> names;
  for (const bsdeform::FieldInfo& f : bsdeform::fieldInfos())
    if (std::string(f.node) == node) names.emplace_back(f.name);
  return names;
}

const char* const kBegin = "<!-- field-reference begin: generated from nodes/bsdeform/FieldInfo.cpp by tests/nodes/FieldInfo_test.cpp -->\n";
const char* const kEnd = "<!-- field-reference end -->\n";

}  // namespace

TEST_CASE("FieldInfo: one entry per field of both nodes, in the nodes' order, with a meaning", "[nodes]") {
  testutil::Coin::get();
  auto* s = new SoBSplineDeformSurface;
  s->ref();
  auto* f = new SoForceField;
  f->ref();
  CHECK(tableNames("SoBSplineDeformSurface") == fieldNames(s));
  CHECK(tableNames("SoForceField") == fieldNames(f));
  for (const bsdeform::FieldInfo& info : bsdeform::fieldInfos()) {
    INFO(info.node << "." << info.name);
    CHECK(std::string(info.meaning).size() > 10);
    CHECK(info.min <= info.max);
    // a force field's own switches are read by every type; every other field by at least one
    const bool always = std::string(info.name) == "type" || std::string(info.name) == "on";
    if (std::string(info.node) == "SoForceField") CHECK((info.usedBy == 0) == always);
  }
  // each force type reads type and on and some field that sets its size or place
  for (int t = SoForceField::UNIFORM; t <= SoForceField::COLLISION; ++t) {
    int used = 0;
    for (const bsdeform::FieldInfo& info : bsdeform::fieldInfos())
      if (std::string(info.node) == "SoForceField") used += bsdeform::forceFieldUses(t, info.name);
    CHECK(used >= 3);
  }
  CHECK(bsdeform::forceFieldUses(SoForceField::POINT, "point"));
  CHECK(!bsdeform::forceFieldUses(SoForceField::POINT, "regionMin"));
  CHECK(!bsdeform::forceFieldUses(SoForceField::DRAG, "force"));
  f->unref();
  s->unref();
}

TEST_CASE("FieldInfo: docs/nodes.md holds the generated field reference (BSDEFORM_UPDATE_DOCS=1 rewrites it)", "[nodes]") {
  testutil::Coin::get();
  const std::string path = BSDEFORM_DOCS_DIR "/nodes.md";
  std::ifstream in(path);
  REQUIRE(in);
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string doc = buffer.str();
  const std::size_t b = doc.find(kBegin), e = doc.find(kEnd);
  REQUIRE(b != std::string::npos);
  REQUIRE(e != std::string::npos);
  REQUIRE(b < e);
  const std::size_t from = b + std::string(kBegin).size();
  const std::string generated = bsdeform::fieldReferenceMarkdown();
  if (std::getenv("BSDEFORM_UPDATE_DOCS")) {
    doc.replace(from, e - from, generated);
    std::ofstream(path, std::ios::trunc) << doc;
    SUCCEED("rewrote " << path);
    return;
  }
  INFO("docs/nodes.md is out of date: run `BSDEFORM_UPDATE_DOCS=1 ctest -R FieldInfo` to regenerate it");
  CHECK(doc.substr(from, e - from) == generated);
  // the header line of each table is there
  CHECK(generated.find("| `w10` |") != std::string::npos);
  CHECK(generated.find("| `regionMin` |") != std::string::npos);
}
