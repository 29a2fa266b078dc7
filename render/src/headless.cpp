#include "shore/render/headless.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

namespace shore::render {
namespace {

EGLDisplay open_display() {
  const auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display != nullptr) {
    EGLDisplay d = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) return d;
  }
  EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  EGLint major = 0, minor = 0;
  if (d == EGL_NO_DISPLAY || !eglInitialize(d, &major, &minor))
    throw ContextError("EGL: no display (neither Mesa's surfaceless platform nor the default display)");
  return d;
}

}  // namespace

HeadlessContext::HeadlessContext() {
  EGLDisplay d = open_display();
  display_ = d;
  if (!eglBindAPI(EGL_OPENGL_API)) throw ContextError("EGL: the OpenGL API is not available");
  const EGLint config_attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configs = 0;
  eglChooseConfig(d, config_attributes, &config, 1, &configs);
  const EGLint context_attributes[] = {
      EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext c = eglCreateContext(d, configs > 0 ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, context_attributes);
  if (c == EGL_NO_CONTEXT) {
    eglTerminate(d);
    throw ContextError("EGL: cannot create an OpenGL 3.3 core context (error " + std::to_string(eglGetError()) + ")");
  }
  context_ = c;
  make_current();
}

HeadlessContext::~HeadlessContext() {
  auto d = static_cast<EGLDisplay>(display_);
  eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(d, static_cast<EGLContext>(context_));
  eglTerminate(d);
}

void HeadlessContext::make_current() {
  if (!eglMakeCurrent(static_cast<EGLDisplay>(display_), EGL_NO_SURFACE, EGL_NO_SURFACE,
                      static_cast<EGLContext>(context_)))
    throw ContextError("EGL: cannot make the context current without a surface (error " +
                       std::to_string(eglGetError()) + ")");
}

std::string HeadlessContext::description() const {
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return std::string(version ? version : "?") + " | " + (renderer ? renderer : "?");
}

}  // namespace shore::render
