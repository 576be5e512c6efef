#include "bop/common/Canvas.hpp"

#include "bop/common/Error.hpp"
#include "bop/common/Npy.hpp"  // writeFileAtomic

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

// Debian's libstb.so exports the stb_image_write functions (stbi_write_png_to_func),
// so no STB_IMAGE_WRITE_IMPLEMENTATION here: link with -lstb.
#include <stb/stb_image_write.h>

// stb_easy_font is header-only (static functions, no implementation define);
// silence warnings for the helpers we do not call.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wcast-align"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

namespace bop {

namespace {

constexpr int kLineHeight = 12;  // stb_easy_font line spacing, px at scale 1

// Printable ASCII and '\n' only: stb_easy_font indexes its tables by char - 32.
std::string sanitise(const std::string& text) {
    std::string s = text;
    for (char& ch : s)
        if (ch != '\n' && (ch < 32 || ch > 126)) ch = '?';
    return s;
}

struct Stop {
    double t;
    Rgb c;
};

template <std::size_t N>
Rgb interpolate(const Stop (&stops)[N], double t) {
    if (!(t > stops[0].t)) return stops[0].c;  // also NaN
    if (t >= stops[N - 1].t) return stops[N - 1].c;
    std::size_t i = 1;
    while (stops[i].t < t) ++i;
    const Stop& a = stops[i - 1];
    const Stop& b = stops[i];
    const double u = (t - a.t) / (b.t - a.t);
    auto mix = [u](std::uint8_t p, std::uint8_t q) {
        return static_cast<std::uint8_t>(std::lround(p + u * (double(q) - double(p))));
    };
    return {mix(a.c.r, b.c.r), mix(a.c.g, b.c.g), mix(a.c.b, b.c.b)};
}

void appendBytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(context);
    const auto* p = static_cast<const unsigned char*>(data);
    out->insert(out->end(), p, p + size);
}

}  // namespace

Canvas Canvas::fromRgb(int width, int height, std::vector<std::uint8_t> rgb) {
    Canvas c(width, height, Rgb{0, 0, 0});
    if (rgb.size() != c.pixels_.size())
        throw std::invalid_argument("Canvas: " + std::to_string(rgb.size()) + " bytes for " + std::to_string(width) +
                                    " x " + std::to_string(height) + " RGB pixels");
    c.pixels_ = std::move(rgb);
    return c;
}

Canvas::Canvas(int width, int height, Rgb fill) : width_(width), height_(height) {
    if (width < 0 || height < 0)
        throw std::invalid_argument("Canvas: negative size " + std::to_string(width) + " x " + std::to_string(height));
    pixels_.resize(std::size_t(width) * std::size_t(height) * 3);
    for (std::size_t i = 0; i < pixels_.size(); i += 3) {
        pixels_[i] = fill.r;
        pixels_[i + 1] = fill.g;
        pixels_[i + 2] = fill.b;
    }
}

void Canvas::set(int x, int y, Rgb c) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    const std::size_t i = (std::size_t(y) * std::size_t(width_) + std::size_t(x)) * 3;
    pixels_[i] = c.r;
    pixels_[i + 1] = c.g;
    pixels_[i + 2] = c.b;
}

Rgb Canvas::get(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_ || y >= height_)
        throw std::out_of_range("Canvas::get(" + std::to_string(x) + ", " + std::to_string(y) + ") outside " +
                                std::to_string(width_) + " x " + std::to_string(height_));
    const std::size_t i = (std::size_t(y) * std::size_t(width_) + std::size_t(x)) * 3;
    return {pixels_[i], pixels_[i + 1], pixels_[i + 2]};
}

void Canvas::drawLine(int x0, int y0, int x1, int y1, Rgb c, int width) {
    const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0), sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    const int back = width / 2;
    for (int err = dx + dy;;) {
        fillRect(x0 - back, y0 - back, width, width, c);
        if (x0 == x1 && y0 == y1) return;
        const int e2 = 2 * err;
        if (e2 >= dy) err += dy, x0 += sx;
        if (e2 <= dx) err += dx, y0 += sy;
    }
}

void Canvas::fillRect(int x, int y, int w, int h, Rgb c) {
    const int x0 = std::max(x, 0), y0 = std::max(y, 0);
    const int x1 = int(std::min<long long>(width_, (long long)x + w));
    const int y1 = int(std::min<long long>(height_, (long long)y + h));
    for (int yy = y0; yy < y1; ++yy)
        for (int xx = x0; xx < x1; ++xx) set(xx, yy, c);
}

void Canvas::drawText(int x, int y, const std::string& text, Rgb c, int scale) {
    if (scale < 1 || text.empty()) return;
    std::string s = sanitise(text);
    // Each quad is 4 vertices of 16 bytes; no glyph uses more than ~20 quads.
    std::vector<char> buffer((s.size() + 1) * 64 * 24);
    const int quads = stb_easy_font_print(0.0f, 0.0f, s.data(), nullptr, buffer.data(), int(buffer.size()));
    for (int q = 0; q < quads; ++q) {
        // Vertices 0 and 2 are opposite corners of an axis-aligned quad (integer coords).
        float v0[2], v2[2];  // x, y of vertices 0 and 2
        std::memcpy(v0, buffer.data() + q * 64, sizeof v0);
        std::memcpy(v2, buffer.data() + q * 64 + 32, sizeof v2);
        const int qx0 = int(std::lround(v0[0])), qy0 = int(std::lround(v0[1]));
        const int qx1 = int(std::lround(v2[0])), qy1 = int(std::lround(v2[1]));
        fillRect(x + qx0 * scale, y + qy0 * scale, (qx1 - qx0) * scale, (qy1 - qy0) * scale, c);
    }
}

int Canvas::textWidth(const std::string& text, int scale) const {
    std::string s = sanitise(text);
    return stb_easy_font_width(s.data()) * std::max(scale, 1);
}

int Canvas::textHeight(const std::string& text, int scale) const {
    if (text.empty()) return 0;
    const int lines = 1 + int(std::count(text.begin(), text.end(), '\n'));
    return lines * kLineHeight * std::max(scale, 1);
}

void Canvas::blit(int x, int y, const Canvas& src) {
    for (int sy = 0; sy < src.height_; ++sy) {
        const int dy = y + sy;
        if (dy < 0 || dy >= height_) continue;
        for (int sx = 0; sx < src.width_; ++sx) set(x + sx, dy, src.get(sx, sy));
    }
}

void Canvas::writePng(const std::string& path) const {
    if (width_ == 0 || height_ == 0)
        throw Error(path, "cannot write an empty picture (" + std::to_string(width_) + " x " + std::to_string(height_) +
                              " px)");
    std::vector<unsigned char> png;
    if (!stbi_write_png_to_func(appendBytes, &png, width_, height_, 3, pixels_.data(), width_ * 3))
        throw Error(path, "cannot encode PNG");
    writeFileAtomic(path, png.data(), png.size());
}

Rgb colourMap(double t) {
    // matplotlib viridis sampled at t = 0, 1/8, ..., 1.
    static const Stop stops[] = {
        {0.000, {68, 1, 84}},    {0.125, {71, 45, 123}},  {0.250, {59, 82, 139}},
        {0.375, {44, 114, 142}}, {0.500, {33, 145, 140}}, {0.625, {40, 174, 128}},
        {0.750, {94, 201, 98}},  {0.875, {173, 220, 48}}, {1.000, {253, 231, 37}},
    };
    return interpolate(stops, t);
}

Rgb divergingMap(double t) {
    if (std::isnan(t)) t = 0.0;
    // ColorBrewer RdBu end and quarter colours around pure white.
    static const Stop stops[] = {
        {-1.0, {33, 102, 172}}, {-0.5, {103, 169, 207}}, {0.0, {255, 255, 255}},
        {0.5, {239, 138, 98}},  {1.0, {178, 24, 43}},
    };
    return interpolate(stops, t);
}

}  // namespace bop
