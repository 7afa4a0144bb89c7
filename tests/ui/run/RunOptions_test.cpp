// SPDX-License-Identifier: MIT
// bsdeform-run's command line (ui/run/RunOptions): good values are read, a bad one is bad input
// with a message that names the option and the value.
#include <catch2/catch.hpp>

#include "RunOptions.h"

using bsdeform::run::Failure;
using bsdeform::run::RunOptions;

namespace {
Failure parse(QStringList args, RunOptions& o) {
  args.prepend(QStringLiteral("bsdeform-run"));
  return RunOptions::parse(args, o);
}
}  // namespace

TEST_CASE("RunOptions: defaults and good values", "[ui]") {
  RunOptions o;
  REQUIRE(parse({QStringLiteral("dir/drum.iv")}, o).ok());
  CHECK(o.scene == QStringLiteral("dir/drum.iv"));
  CHECK(o.steps == 100);
  CHECK(o.until < 0);
  CHECK(o.outDir == QStringLiteral("drum.out"));
  CHECK(o.width == 640);
  CHECK(o.height == 480);
  CHECK(o.recordEvery == 1);
  CHECK(o.videoFps == 25.0);
  CHECK(o.sweepChildArguments == QStringList{QStringLiteral("dir/drum.iv")});
  CHECK(o.exportMesh.isEmpty());

  const Failure f = parse(QStringLiteral("--until 2.5 --png-at 0.5,1 --png-every 3 --size 320x200 --set A.w10=1 "
                                         "--set B.magnitude=2 --record-every 4 --video v.mp4 --video-fps 50 -o out "
                                         "--overwrite --plot --export-mesh m/final.OBJ -q drum.iv")
                              .split(QLatin1Char(' ')),
                          o);
  REQUIRE(f.ok());
  CHECK(o.until == 2.5);
  CHECK(o.pngAt == QVector<double>({0.5, 1.0}));
  CHECK(o.pngEvery == 3);
  CHECK(o.width == 320);
  CHECK(o.height == 200);
  CHECK(o.sets == QStringList({QStringLiteral("A.w10=1"), QStringLiteral("B.magnitude=2")}));
  CHECK(o.recordEvery == 4);
  CHECK(o.video == QStringLiteral("v.mp4"));
  CHECK(o.videoFps == 50.0);
  CHECK(o.exportMesh == QStringLiteral("m/final.OBJ"));
  CHECK(o.outDir == QStringLiteral("out"));
  CHECK(o.overwrite);
  CHECK(o.plot);
  CHECK(o.quiet);
  CHECK(!o.resultOnly);
  // a sweep child runs the same simulation and writes nothing: no output or image options
  CHECK(o.sweepChildArguments == QStringLiteral("drum.iv --until 2.5 --set A.w10=1 --set B.magnitude=2").split(QLatin1Char(' ')));
}

TEST_CASE("RunOptions: --frame-names names frames by number (default) or by time", "[ui]") {
  RunOptions o;
  REQUIRE(parse({QStringLiteral("s.iv")}, o).ok());
  CHECK(!o.frameNamesTime);
  RunOptions t;
  REQUIRE(parse({QStringLiteral("--frame-names"), QStringLiteral("time"), QStringLiteral("s.iv")}, t).ok());
  CHECK(t.frameNamesTime);
  RunOptions f;
  REQUIRE(parse({QStringLiteral("--frame-names"), QStringLiteral("frame"), QStringLiteral("s.iv")}, f).ok());
  CHECK(!f.frameNamesTime);
}

TEST_CASE("RunOptions: a bad value names the option and the value", "[ui]") {
  const struct {
    const char* args;
    const char* message;
  } cases[] = {
      {"--steps -3 s.iv", "--steps '-3' is not a count >= 0"},
      {"--steps many s.iv", "--steps 'many' is not a count >= 0"},
      {"--until soon s.iv", "--until 'soon' is not a time >= 0"},
      {"--until inf s.iv", "--until 'inf' is not a time >= 0"},
      {"--steps 5 --until 1 s.iv", "give --steps or --until, not both"},
      {"--png-every -1 s.iv", "--png-every '-1' is not a count >= 0"},
      {"--png-at 1,-2 s.iv", "--png-at '1,-2' is not a list of times >= 0"},
      {"--size 0x10 s.iv", "--size '0x10' is not WxH within 1..8192"},
      {"--size 640 s.iv", "--size '640' is not WxH within 1..8192"},
      {"--size 9000x10 s.iv", "--size '9000x10' is not WxH within 1..8192"},
      {"--record-every 0 s.iv", "--record-every '0' is not a count >= 1"},
      {"--video-fps 0 s.iv", "--video-fps '0' is not a rate in (0, 1000]"},
      {"--video-fps 2000 s.iv", "--video-fps '2000' is not a rate in (0, 1000]"},
      {"--video v.mp4 --sweep A.w10=1,2 s.iv", "--video and --sweep: a sweep runs many simulations, record one with --set"},
      {"--export-mesh m.ply s.iv", "--export-mesh 'm.ply': unknown mesh format 'ply' (use .obj or .stl)"},
      {"--export-mesh mesh s.iv", "--export-mesh 'mesh': unknown mesh format '' (use .obj or .stl)"},
      {"--export-mesh m.stl --sweep A.w10=1,2 s.iv",
       "--export-mesh and --sweep: a sweep runs many simulations, export one with --set"},
      {"a.iv b.iv", "expected exactly one scene file (see --help)"},
      {"--frame-names seconds s.iv", "--frame-names 'seconds' is neither 'frame' nor 'time'"},
  };
  for (const auto& c : cases) {
    INFO(c.args);
    RunOptions o;
    const Failure f = parse(QString::fromLatin1(c.args).split(QLatin1Char(' ')), o);
    CHECK(f.code == bsdeform::run::kBadInput);
    CHECK(f.message == QString::fromLatin1(c.message));
  }
  RunOptions o;
  CHECK(parse({}, o).code == bsdeform::run::kBadInput);  // no scene at all
}

TEST_CASE("RunOptions: --keep-states names the state file, and is refused with --sweep and --static", "[ui]") {
  RunOptions o;
  REQUIRE(parse({QStringLiteral("drum.iv")}, o).ok());
  CHECK(o.keepStates.isEmpty());
  REQUIRE(parse(QStringLiteral("--keep-states run/drum.states --record-every 10 drum.iv").split(QLatin1Char(' ')), o).ok());
  CHECK(o.keepStates == QStringLiteral("run/drum.states"));
  CHECK(o.recordEvery == 10);
  CHECK_FALSE(o.sweepChildArguments.contains(QStringLiteral("--keep-states")));
  Failure f = parse(QStringLiteral("--keep-states s.states --sweep A.w10=1,2 drum.iv").split(QLatin1Char(' ')), o);
  CHECK(f.code == bsdeform::run::kBadInput);
  CHECK(f.message.contains(QStringLiteral("--keep-states and --sweep")));
  f = parse(QStringLiteral("--keep-states s.states --static drum.iv").split(QLatin1Char(' ')), o);
  CHECK(f.code == bsdeform::run::kBadInput);
  CHECK(f.message.contains(QStringLiteral("--static and --keep-states")));
}

TEST_CASE("RunOptions: --probe NAME=u,v, repeatable, bad names and values refused by name", "[ui]") {
  RunOptions o;
  REQUIRE(parse({QStringLiteral("--probe"), QStringLiteral("tip=1,0.5"), QStringLiteral("--probe"),
                 QStringLiteral("_c2=0, 1e-1"), QStringLiteral("s.iv")},
                o)
              .ok());
  REQUIRE(o.probes.size() == 2);
  CHECK(o.probes[0].name == QStringLiteral("tip"));
  CHECK(o.probes[0].u == 1.0);
  CHECK(o.probes[0].v == 0.5);
  CHECK(o.probes[1].name == QStringLiteral("_c2"));
  CHECK(o.probes[1].v == 0.1);
  REQUIRE(parse({QStringLiteral("--static"), QStringLiteral("--probe"), QStringLiteral("a=0,0"), QStringLiteral("s.iv")}, o).ok());
  CHECK(o.probes.size() == 1);
  for (const auto& [value, says] :
       {std::make_pair("tip", "--probe 'tip' is not NAME=u,v"), std::make_pair("9a=0,0", "--probe '9a=0,0' is not NAME=u,v"),
        std::make_pair("a-b=0,0", "--probe 'a-b=0,0' is not NAME=u,v"), std::make_pair("a=0,0,0", "is not NAME=u,v"),
        std::make_pair("a=-0.1,0", "u and v must be numbers in [0, 1], got '-0.1' and '0'"),
        std::make_pair("a=0,nan", "got '0' and 'nan'"), std::make_pair("a=,1", "got '' and '1'"),
        std::make_pair("reaction_umin=0,0", "would give the columns of the reactions"),
        std::make_pair("applied=0,0", "would give the columns of the reactions")}) {
    INFO(value);
    const Failure f = parse({QStringLiteral("--probe"), QString::fromUtf8(value), QStringLiteral("s.iv")}, o);
    CHECK(f.code == bsdeform::run::kBadInput);
    CHECK(f.message.contains(QString::fromUtf8(says)));
  }
  Failure f = parse({QStringLiteral("--probe"), QStringLiteral("a=0,0"), QStringLiteral("--probe"), QStringLiteral("a=1,1"),
                     QStringLiteral("s.iv")},
                    o);
  CHECK(f.message.contains(QStringLiteral("a probe named 'a' is given twice")));
  f = parse({QStringLiteral("--probe"), QStringLiteral("a=0,0"), QStringLiteral("--sweep"), QStringLiteral("S.w10=1,2"),
             QStringLiteral("s.iv")},
            o);
  CHECK(f.code == bsdeform::run::kBadInput);
  CHECK(f.message.contains(QStringLiteral("--probe and --sweep")));
}
