// SPDX-License-Identifier: MIT
// Cost of writing a scene as .iv text (issue 11 item 2): bsdeform::writeSceneText, the writer of
// bsdeform-run's final.iv, Save As and autosave, streaming into a sink that only counts bytes.
//   WriteScene/<N>  an N x N bicubic surface after two steps of a region load: three nets of
//                   (N+6)^2 points (restNet empty for the plane: controlNet and previousNet),
//                   synchronised from the simulation and written
// Counters: bytes/s of text, values/s = doubles written per second.
#include <Inventor/SoDB.h>
#include <Inventor/SoInput.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/nodes/SoSeparator.h>
#include <benchmark/benchmark.h>

#include <string>

#include "bsdeform/NodesInit.h"
#include "bsdeform/SceneText.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace {

// The scene of the last size asked for: Google Benchmark calls a benchmark function several
// times (to size its iteration count), and building and stepping a 2048^2 model takes seconds.
SoSeparator* sceneOfSize(int N) {
  static int cachedN = -1;
  static SoSeparator* cached = nullptr;
  if (N == cachedN) return cached;
  if (cached) cached->unref();
  bsdeform::disableDynamicNodeLoading();
  bsdeform::initNodes();
  const std::string text = "#Inventor V2.1 ascii\nSeparator { SoBSplineDeformSurface { on FALSE damping 1 "
                           "numUControlPoints " + std::to_string(N) + " numVControlPoints " + std::to_string(N) +
                           " forces SoForceField { type REGION force 0 0 1 magnitude 60 regionMin 0.3 0.3 "
                           "regionMax 0.7 0.7 } } }";
  SoInput in;
  in.setBuffer(text.data(), text.size());
  cached = SoDB::readAll(&in);
  cached->ref();
  cachedN = N;
  SoSearchAction sa;
  sa.setType(SoBSplineDeformSurface::getClassTypeId());
  sa.apply(cached);
  static_cast<SoBSplineDeformSurface*>(sa.getPath()->getTail())->stepSimulation(2);
  return cached;
}

void WriteScene(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  SoSeparator* root = sceneOfSize(N);
  std::size_t bytes = 0;
  for (auto _ : state) {
    bytes = 0;
    const bool ok = bsdeform::writeSceneText(root, [&bytes](const char*, std::size_t size) {
      bytes += size;
      return true;
    });
    if (!ok) state.SkipWithError("writeSceneText failed");
  }
  const double values = 2.0 * 3.0 * (N + 6.0) * (N + 6.0);
  state.counters["MB"] = double(bytes) / 1e6;
  state.counters["bytes/s"] = benchmark::Counter(double(bytes), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["values/s"] = benchmark::Counter(values, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(WriteScene)->RangeMultiplier(2)->Range(128, 2048)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
