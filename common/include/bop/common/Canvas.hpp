#pragma once
// A small RGB raster for pictures written by tools (slices, plots, contact sheets).
// Coordinates are pixels, x rightward, y downward, (0, 0) the top-left pixel.
// Text uses the stb_easy_font bitmap font (ASCII, about 6 px advance and 12 px line
// height at scale 1). PNG output uses stb_image_write (linked from Debian's -lstb).
#include <cstdint>
#include <string>
#include <vector>

namespace bop {

struct Rgb {
    std::uint8_t r, g, b;
    bool operator==(const Rgb&) const = default;
};

class Canvas {
public:
    // width, height: pixels (>= 0; std::invalid_argument if negative).
    Canvas(int width, int height, Rgb fill);
    // A picture from row-major RGB bytes, the top row first (std::invalid_argument unless there
    // are 3 * width * height of them).
    static Canvas fromRgb(int width, int height, std::vector<std::uint8_t> rgb);

    int width() const { return width_; }
    int height() const { return height_; }

    // Sets one pixel; pixels outside the canvas are ignored.
    void set(int x, int y, Rgb c);
    // Reads one pixel; std::out_of_range outside the canvas.
    Rgb get(int x, int y) const;

    // Fills pixels [x, x + w) x [y, y + h), clipped to the canvas.
    void fillRect(int x, int y, int w, int h, Rgb c);

    // A line from (x0, y0) to (x1, y1), `width` px wide (Bresenham steps, each a width x width
    // square), clipped to the canvas.
    void drawLine(int x0, int y0, int x1, int y1, Rgb c, int width = 2);

    // Draws text with its top-left corner at (x, y); scale is an integer pixel
    // magnification (>= 1). '\n' starts a new line 12 * scale px lower; characters
    // outside printable ASCII are drawn as '?'. Clipped to the canvas.
    void drawText(int x, int y, const std::string& text, Rgb c, int scale = 1);
    // Width (px) of the widest line of text at this scale; every pixel drawText
    // sets lies in [x, x + textWidth) x [y, y + textHeight).
    int textWidth(const std::string& text, int scale = 1) const;
    // Height (px) of text at this scale: 12 * scale per line.
    int textHeight(const std::string& text, int scale = 1) const;

    // Copies src with its top-left corner at (x, y), clipped.
    void blit(int x, int y, const Canvas& src);

    // Writes an 8-bit RGB PNG atomically (path + ".tmp", then rename).
    // Throws bop::Error(path, ...) on failure.
    void writePng(const std::string& path) const;

    // Row-major RGB bytes, 3 * width * height.
    const std::vector<std::uint8_t>& pixels() const { return pixels_; }

private:
    int width_, height_;
    std::vector<std::uint8_t> pixels_;
};

// Perceptually ordered colour map (viridis, 9 stops, linear interpolation):
// t = 0 dark purple, t = 1 yellow; t is clamped to [0, 1], NaN maps to t = 0.
Rgb colourMap(double t);

// Diverging blue-white-red map: t = -1 blue, 0 white, +1 red; clamped to [-1, 1],
// NaN maps to white.
Rgb divergingMap(double t);

}  // namespace bop
