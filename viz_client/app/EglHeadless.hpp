#pragma once
// An OpenGL 3.3 core context without a window or a display (EGL, Mesa's surfaceless platform):
// what `bop-viewer --headless` and the rendering tests draw with. Mesa's llvmpipe renders on the
// CPU, so it works on machines with no GPU and no X server. Draw into an Offscreen target.
#include <string>

namespace bop::viz {

class EglHeadless {
public:
    EglHeadless();  // current on this thread afterwards; bop::Error saying what failed
    ~EglHeadless();
    EglHeadless(const EglHeadless&) = delete;
    EglHeadless& operator=(const EglHeadless&) = delete;

    std::string renderer() const;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string version() const;   // GL_VERSION

private:
    void* display_ = nullptr;  // EGLDisplay
    void* context_ = nullptr;  // EGLContext
};

}  // namespace bop::viz
