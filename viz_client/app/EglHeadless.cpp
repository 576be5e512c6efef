#include "app/EglHeadless.hpp"

#include "bop/common/Error.hpp"
#include "render/Gl.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>

namespace bop::viz {
namespace {

std::string eglError(const char* what) {
    return std::string(what) + " failed (EGL error 0x" + [] {
        char hex[16];
        std::snprintf(hex, sizeof hex, "%04x", unsigned(eglGetError()));
        return std::string(hex);
    }() + ")";
}

// Mesa's surfaceless platform, else the first EGL device (NVIDIA's driver offers devices, not
// Mesa's platform; that path is not tested on this project's machines, which have no GPU).
EGLDisplay headlessDisplay() {
    const auto getPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!getPlatformDisplay) throw Error("EGL", "no eglGetPlatformDisplayEXT (is Mesa's libegl-mesa0 installed?)");
    EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d != EGL_NO_DISPLAY) return d;
    const auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    EGLDeviceEXT device = nullptr;
    EGLint devices = 0;
    if (queryDevices && queryDevices(1, &device, &devices) && devices > 0)
        d = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
    if (d == EGL_NO_DISPLAY)
        throw Error("EGL", "no headless display: neither Mesa's surfaceless platform nor an EGL device");
    return d;
}

}  // namespace

EglHeadless::EglHeadless() {
    EGLDisplay d = headlessDisplay();
    EGLint major = 0, minor = 0;
    if (!eglInitialize(d, &major, &minor)) throw Error("EGL", eglError("eglInitialize"));
    display_ = d;
    if (!eglBindAPI(EGL_OPENGL_API)) throw Error("EGL", eglError("eglBindAPI(OpenGL)"));
    const EGLint attributes[] = {
        EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLContext c = eglCreateContext(d, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (c == EGL_NO_CONTEXT) throw Error("EGL", eglError("creating an OpenGL 3.3 core context"));
    context_ = c;
    if (!eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, c)) throw Error("EGL", eglError("eglMakeCurrent"));
}

EglHeadless::~EglHeadless() {
    if (!display_) return;
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_) eglDestroyContext(display_, context_);
    eglTerminate(display_);
}

std::string EglHeadless::renderer() const {
    return reinterpret_cast<const char*>(glGetString(GL_RENDERER));
}
std::string EglHeadless::version() const {
    return reinterpret_cast<const char*>(glGetString(GL_VERSION));
}

}  // namespace bop::viz
