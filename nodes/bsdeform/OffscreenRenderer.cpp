// SPDX-License-Identifier: MIT
#include "bsdeform/OffscreenRenderer.h"
#include "bsdeform/AtomicWrite.h"

#include "bsdeform/DefaultView.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <Inventor/C/glue/gl.h>
#include <Inventor/SbViewportRegion.h>
#include <Inventor/SoOffscreenRenderer.h>
#include <Inventor/nodes/SoCamera.h>
#include <Inventor/nodes/SoDirectionalLight.h>
#include <Inventor/nodes/SoPerspectiveCamera.h>
#include <Inventor/nodes/SoSeparator.h>
#include <fcntl.h>
#include <png.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

namespace bsdeform {

namespace {

struct EglOffscreen {
  // Coin 4.0.0's cc_glglue_context_max_dimensions() reads a flag of its private GLX context
  // struct through this pointer even with callbacks installed; a zeroed prefix keeps that
  // read harmless (coin-notes §5).
  unsigned char coinPrefix[128] = {};
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLSurface surface = EGL_NO_SURFACE;
  EGLContext context = EGL_NO_CONTEXT;
  EGLDisplay prevDisplay = EGL_NO_DISPLAY;
  EGLSurface prevDraw = EGL_NO_SURFACE, prevRead = EGL_NO_SURFACE;
  EGLContext prevContext = EGL_NO_CONTEXT;
};

std::string g_eglError;

EGLDisplay surfacelessDisplay() {
  static EGLDisplay display = EGL_NO_DISPLAY;
  static bool tried = false;
  if (tried) return display;
  tried = true;
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!getPlatformDisplay) {
    g_eglError = "EGL has no eglGetPlatformDisplayEXT";
    return display;
  }
  EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (d == EGL_NO_DISPLAY || !eglInitialize(d, &major, &minor)) {
    g_eglError = "cannot initialise Mesa's surfaceless EGL display";
    return display;
  }
  display = d;
  return display;
}

void* createOffscreen(unsigned int width, unsigned int height) {
  EGLDisplay d = surfacelessDisplay();
  if (d == EGL_NO_DISPLAY) return nullptr;
  if (!eglBindAPI(EGL_OPENGL_API)) {
    g_eglError = "eglBindAPI(EGL_OPENGL_API) failed";
    return nullptr;
  }
  const EGLint configAttribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8,
                                  EGL_BLUE_SIZE, 8, EGL_ALPHA_SIZE, 8, EGL_DEPTH_SIZE, 24, EGL_STENCIL_SIZE, 8,
                                  EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config;
  EGLint count = 0;
  if (!eglChooseConfig(d, configAttribs, &config, 1, &count) || count < 1) {
    g_eglError = "no EGL pbuffer config with RGBA8, depth 24, stencil 8";
    return nullptr;
  }
  auto* ctx = new EglOffscreen;
  ctx->display = d;
  const EGLint surfaceAttribs[] = {EGL_WIDTH, EGLint(width), EGL_HEIGHT, EGLint(height), EGL_NONE};
  ctx->surface = eglCreatePbufferSurface(d, config, surfaceAttribs);
  ctx->context = eglCreateContext(d, config, EGL_NO_CONTEXT, nullptr);
  if (ctx->surface == EGL_NO_SURFACE || ctx->context == EGL_NO_CONTEXT) {
    g_eglError = "cannot create an EGL pbuffer surface or context";
    if (ctx->surface != EGL_NO_SURFACE) eglDestroySurface(d, ctx->surface);
    if (ctx->context != EGL_NO_CONTEXT) eglDestroyContext(d, ctx->context);
    delete ctx;
    return nullptr;
  }
  return ctx;
}

SbBool makeCurrent(void* data) {
  auto* ctx = static_cast<EglOffscreen*>(data);
  ctx->prevDisplay = eglGetCurrentDisplay();
  ctx->prevDraw = eglGetCurrentSurface(EGL_DRAW);
  ctx->prevRead = eglGetCurrentSurface(EGL_READ);
  ctx->prevContext = eglGetCurrentContext();
  eglBindAPI(EGL_OPENGL_API);
  return eglMakeCurrent(ctx->display, ctx->surface, ctx->surface, ctx->context) ? TRUE : FALSE;
}

void reinstatePrevious(void* data) {
  auto* ctx = static_cast<EglOffscreen*>(data);
  if (ctx->prevContext != EGL_NO_CONTEXT && ctx->prevDisplay != EGL_NO_DISPLAY)
    eglMakeCurrent(ctx->prevDisplay, ctx->prevDraw, ctx->prevRead, ctx->prevContext);
  else
    eglMakeCurrent(ctx->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

void destruct(void* data) {
  auto* ctx = static_cast<EglOffscreen*>(data);
  if (eglGetCurrentContext() == ctx->context)
    eglMakeCurrent(ctx->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroySurface(ctx->display, ctx->surface);
  eglDestroyContext(ctx->display, ctx->context);
  delete ctx;
}

}  // namespace

bool installEglOffscreenContexts(std::string* error) {
  static std::once_flag once;
  static bool ok = false;
  std::call_once(once, [] {
    // Probe once so that a machine without EGL reports a reason instead of failing later.
    void* probe = createOffscreen(4, 4);
    if (!probe) return;
    destruct(probe);
    static cc_glglue_offscreen_cb_functions functions = {createOffscreen, makeCurrent, reinstatePrevious, destruct};
    cc_glglue_context_set_offscreen_cb_functions(&functions);
    ok = true;
  });
  if (!ok && error) *error = g_eglError.empty() ? "EGL offscreen contexts are not available" : g_eglError;
  return ok;
}

OffscreenRenderer::OffscreenRenderer() = default;
OffscreenRenderer::~OffscreenRenderer() = default;

bool renderOffscreen(SoNode* scene, int width, int height, Image& out, std::string& error, const SbColor& background,
                     OffscreenRenderer* reuse) {
  if (!scene || width < 1 || height < 1 || width > 16384 || height > 16384) {
    error = "renderOffscreen: no scene or image size out of 1..16384: " + std::to_string(width) + " x " +
            std::to_string(height);
    return false;
  }
  if (!installEglOffscreenContexts(&error)) return false;
  const SbViewportRegion viewport{short(width), short(height)};
  SoSeparator* root = new SoSeparator;
  root->ref();
  auto* headlight = new SoDirectionalLight;  // as every viewer has, along the view direction
  // and a backlight opposite it, as the viewer has (ui/viewer/Backlight.h): it lights only what
  // the headlight does not reach, a sheet's side that faces away from the view direction
  auto* backlight = new SoDirectionalLight;
  if (findSceneCamera(scene)) {
    // traversed before the scene's camera, the lights are placed in eye space: -z is the view
    headlight->direction.setValue(0, 0, -1);
    backlight->direction.setValue(0, 0, 1);
    root->addChild(headlight);
    root->addChild(backlight);
    root->addChild(scene);
  } else {
    auto* camera = new SoPerspectiveCamera;
    headlight->direction = viewDirection(StandardView::Default);  // after the camera: world space
    backlight->direction = -viewDirection(StandardView::Default);
    root->addChild(camera);
    root->addChild(headlight);
    root->addChild(backlight);
    root->addChild(scene);
    frameView(camera, scene, viewport);  // the viewer's and the README's default view
  }
  // A kept SoOffscreenRenderer keeps its GL context. For a smaller size Coin would keep it too
  // and draw into a corner of the larger canvas, which llvmpipe rasterises a little
  // differently (seen: one byte off by one): a new size gets a new renderer, so that a kept
  // renderer's images equal a fresh one's.
  std::unique_ptr<SoOffscreenRenderer> fresh;
  std::unique_ptr<SoOffscreenRenderer>& renderer = reuse ? reuse->m_renderer : fresh;
  if (!renderer || renderer->getViewportRegion().getWindowSize() != viewport.getWindowSize())
    renderer = std::make_unique<SoOffscreenRenderer>(viewport);
  renderer->setComponents(SoOffscreenRenderer::RGB);
  renderer->setBackgroundColor(background);
  const bool ok = renderer->render(root);
  if (ok) {
    out.width = width;
    out.height = height;
    out.rgb.resize(size_t(width) * height * 3);
    const unsigned char* buf = renderer->getBuffer();
    const size_t row = size_t(width) * 3;
    for (int y = 0; y < height; ++y)  // Coin's buffer is bottom-up
      std::memcpy(out.rgb.data() + row * y, buf + row * (height - 1 - y), row);
  } else {
    error = "SoOffscreenRenderer::render failed" + (g_eglError.empty() ? std::string() : ": " + g_eglError);
  }
  root->unref();
  return ok;
}

namespace {
void appendPng(png_structp png, png_bytep data, png_size_t size) {
  auto* out = static_cast<std::vector<unsigned char>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + size);
}

}  // namespace

// Into memory (a frame is small): the file is then written with plain write(2) calls whose
// every error is seen. libpng reports errors by longjmp; the setjmp frame has no locals that
// change after it.
bool encodePng(const Image& image, std::vector<unsigned char>& out, const PngSettings& settings) {
  out.clear();
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, info ? &info : nullptr);
    return false;
  }
  png_set_write_fn(png, &out, appendPng, nullptr);
  png_set_compression_level(png, settings.zlibLevel);
  if (settings.subFilterOnly) png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y)
    png_write_row(png, const_cast<png_bytep>(image.rgb.data() + size_t(y) * image.width * 3));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

bool writePng(const Image& image, const std::string& path, std::string& error, bool syncToDisk) {
  if (image.width < 1 || image.height < 1 || image.rgb.size() != size_t(image.width) * image.height * 3) {
    error = "writePng: empty or inconsistent image for " + path;
    return false;
  }
  std::vector<unsigned char> bytes;
  if (!encodePng(image, bytes)) {
    error = "cannot write '" + path + "': PNG encoding failed";
    return false;
  }
  // All or nothing: a temporary file of our own in the same directory, written, synced and
  // renamed over `path` only when every step succeeded (a full disk keeps the previous image).
  return writeFileAtomically(path, bytes.data(), bytes.size(), error, syncToDisk);
}

bool syncFileSystem(const std::string& directory, std::string& error) {
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  int why = fd < 0 ? errno : 0;
  if (!why && ::syncfs(fd) != 0) why = errno;
  if (fd >= 0) ::close(fd);
  if (why) error = "cannot sync the files written to '" + directory + "': " + std::strerror(why);
  return why == 0;
}

}  // namespace bsdeform
