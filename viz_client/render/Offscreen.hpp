#pragma once
// A framebuffer in GPU memory (RGBA8 colour, 24-bit depth) to draw into without a window, and
// its pixels read back for PNG files. Needs a current OpenGL context.
#include <cstdint>
#include <vector>

namespace bop::viz {

class Offscreen {
public:
    Offscreen(int width, int height);  // pixels; bound for drawing afterwards
    ~Offscreen();
    Offscreen(const Offscreen&) = delete;
    Offscreen& operator=(const Offscreen&) = delete;

    void bind() const;
    int width() const { return width_; }
    int height() const { return height_; }
    // RGB bytes, row-major, the top row first (as Canvas and PNG files have them).
    std::vector<std::uint8_t> readRgb() const;

private:
    int width_, height_;
    unsigned framebuffer_ = 0, colour_ = 0, depth_ = 0;
};

// RGB bytes of the bound read framebuffer (a window's back buffer, say), top row first.
std::vector<std::uint8_t> readBoundRgb(int width, int height);

}  // namespace bop::viz
