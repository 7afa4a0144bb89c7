// SPDX-License-Identifier: MIT
// Time per frame of SoBSplineDeformSurface drawn offscreen (800 x 600, EGL pbuffer, Mesa
// llvmpipe, read-back included), default complexity, for N x N free control points.
//   DrawStatic/<N>    the same deformed surface redrawn (tessellation cached)
//   DrawAnimated/<N>  one simulation step + re-tessellation + draw per frame
//   RunnerFrame/<N>/<kept>/<png>  what bsdeform-run --png-every 1 does per frame at its
//                     default 640 x 480: one step, renderOffscreen() with a fresh renderer
//                     (kept = 0, as before issue 11) or one kept for all frames (kept = 1), the
//                     PNG encoded in memory with libpng's defaults (png = 0, as before) or
//                     bsdeform::PngSettings' (png = 1)
//   PngEncode/<level>/<sub>  encodePng() of a 640 x 480 frame of a 128^2 surface at zlib level
//                     <level>, SUB filter on every row (sub = 1) or libpng's adaptive choice (0)
#include <Inventor/SbViewportRegion.h>
#include <Inventor/SoDB.h>
#include <Inventor/SoInput.h>
#include <Inventor/SoOffscreenRenderer.h>
#include <Inventor/actions/SoSearchAction.h>
#include <Inventor/nodes/SoDirectionalLight.h>
#include <Inventor/nodes/SoPerspectiveCamera.h>
#include <Inventor/nodes/SoSeparator.h>
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "bsdeform/NodesInit.h"
#include "bsdeform/OffscreenRenderer.h"
#include "bsdeform/SoBSplineDeformSurface.h"

namespace {

struct Scene {
  SoSeparator* root = nullptr;
  SoBSplineDeformSurface* surface = nullptr;
};

// With a camera and light of its own, or (as bsdeform-run frames a scene without one) none:
// renderOffscreen() then adds its three-quarter view of the whole surface and a headlight.
Scene makeScene(int N, bool camera = true) {
  bsdeform::disableDynamicNodeLoading();
  bsdeform::initNodes();
  const std::string text = std::string("#Inventor V2.1 ascii\nSeparator { ") +
                           (camera ? "PerspectiveCamera { position 0.5 -1.2 1.6 orientation 1 0 0 0.65 } "
                                     "DirectionalLight {} "
                                   : "") +
                           "Material { diffuseColor 0.9 0.5 0.2 } "
                           "SoBSplineDeformSurface { on FALSE damping 1 numUControlPoints " +
                           std::to_string(N) + " numVControlPoints " + std::to_string(N) +
                           " forces SoForceField { type REGION force 0 0 1 magnitude 60 } } }";
  SoInput in;
  in.setBuffer(text.data(), text.size());
  Scene s;
  s.root = SoDB::readAll(&in);
  s.root->ref();
  SoSearchAction sa;
  sa.setType(SoBSplineDeformSurface::getClassTypeId());
  sa.apply(s.root);
  s.surface = static_cast<SoBSplineDeformSurface*>(sa.getPath()->getTail());
  s.surface->stepSimulation(20);
  return s;
}

// False (and the benchmark skipped with the reason) without EGL offscreen contexts.
bool eglReady(benchmark::State& state) {
  std::string error;
  if (bsdeform::installEglOffscreenContexts(&error)) return true;
  state.SkipWithError(error.c_str());
  return false;
}

void draw(benchmark::State& state, bool animate) {
  if (!eglReady(state)) return;
  Scene s = makeScene(static_cast<int>(state.range(0)));
  SoOffscreenRenderer renderer(SbViewportRegion(800, 600));
  renderer.render(s.root);  // context creation and first-frame set-up are not measured
  for (auto _ : state) {
    if (animate) s.surface->stepSimulation(1);
    renderer.render(s.root);
    benchmark::DoNotOptimize(renderer.getBuffer());
  }
  state.counters["frames/s"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
  s.root->unref();
}

void RunnerFrame(benchmark::State& state) {
  if (!eglReady(state)) return;
  std::string error;
  Scene s = makeScene(static_cast<int>(state.range(0)), false);
  const bool kept = state.range(1) != 0;
  bsdeform::PngSettings png;
  if (state.range(2) == 0) png = bsdeform::PngSettings{6, false};  // libpng's defaults
  bsdeform::OffscreenRenderer renderer;
  bsdeform::Image image;
  std::vector<unsigned char> bytes;
  for (auto _ : state) {
    s.surface->stepSimulation(1);
    if (!bsdeform::renderOffscreen(s.root, 640, 480, image, error, bsdeform::kDefaultBackground,
                                   kept ? &renderer : nullptr) ||
        !bsdeform::encodePng(image, bytes, png)) {
      state.SkipWithError(error.c_str());
      break;
    }
    benchmark::DoNotOptimize(bytes.data());
  }
  state.counters["frames/s"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["PNG bytes"] = double(bytes.size());
  s.root->unref();
}

void PngEncode(benchmark::State& state) {
  if (!eglReady(state)) return;
  std::string error;
  Scene s = makeScene(128, false);
  bsdeform::Image image;
  if (!bsdeform::renderOffscreen(s.root, 640, 480, image, error)) {
    state.SkipWithError(error.c_str());
    return;
  }
  bsdeform::PngSettings settings;
  settings.zlibLevel = static_cast<int>(state.range(0));
  settings.subFilterOnly = state.range(1) != 0;
  std::vector<unsigned char> png;
  for (auto _ : state) {
    bsdeform::encodePng(image, png, settings);
    benchmark::DoNotOptimize(png.data());
  }
  state.counters["PNG bytes"] = double(png.size());
  s.root->unref();
}

void DrawStatic(benchmark::State& state) { draw(state, false); }
void DrawAnimated(benchmark::State& state) { draw(state, true); }

}  // namespace

BENCHMARK(DrawStatic)->Arg(16)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(DrawAnimated)->Arg(16)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK(RunnerFrame)
    ->Args({24, 0, 0})
    ->Args({24, 1, 1})
    ->Args({128, 0, 0})
    ->Args({128, 1, 0})
    ->Args({128, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(PngEncode)->ArgsProduct({{1, 2, 3, 4, 6}, {0, 1}})->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
