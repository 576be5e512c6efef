#include "render/Offscreen.hpp"

#include "bop/common/Error.hpp"
#include "render/Gl.hpp"

#include <cstring>
#include <string>

namespace bop::viz {

Offscreen::Offscreen(int width, int height) : width_(width), height_(height) {
    if (width < 1 || height < 1)
        throw Error("Offscreen", "size " + std::to_string(width) + "x" + std::to_string(height));
    glGenFramebuffers(1, &framebuffer_);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    glGenRenderbuffers(1, &colour_);
    glBindRenderbuffer(GL_RENDERBUFFER, colour_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
    glGenRenderbuffers(1, &depth_);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("Offscreen", "framebuffer incomplete");
    glViewport(0, 0, width, height);
}

Offscreen::~Offscreen() {
    glDeleteRenderbuffers(1, &depth_);
    glDeleteRenderbuffers(1, &colour_);
    glDeleteFramebuffers(1, &framebuffer_);
}

void Offscreen::bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    glViewport(0, 0, width_, height_);
}

std::vector<std::uint8_t> Offscreen::readRgb() const {
    bind();
    return readBoundRgb(width_, height_);
}

std::vector<std::uint8_t> readBoundRgb(int width, int height) {
    std::vector<std::uint8_t> rgb(std::size_t(3) * width * height);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
    // OpenGL's first row is the bottom one.
    const std::size_t row = std::size_t(3) * width;
    std::vector<std::uint8_t> flipped(rgb.size());
    for (int y = 0; y < height; ++y)
        std::memcpy(&flipped[std::size_t(y) * row], &rgb[std::size_t(height - 1 - y) * row], row);
    return flipped;
}

}  // namespace bop::viz
