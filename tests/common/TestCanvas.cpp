#include "TestUtil.hpp"
#include "bop/common/Canvas.hpp"
#include "bop/common/Error.hpp"

#include <catch2/catch.hpp>

// Debian's libstb.so provides stbi_load; no STB_IMAGE_IMPLEMENTATION (link -lstb).
#include <stb/stb_image.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

std::string tempPath(const std::string& name) {
    static const bop::test::TempDir dir("canvas");
    return dir.file(name);
}

const bop::Rgb kBlack{0, 0, 0};
const bop::Rgb kWhite{255, 255, 255};

}  // namespace

TEST_CASE("Canvas fill, set, get and clipping", "[canvas]") {
    bop::Canvas c(5, 4, {1, 2, 3});
    CHECK(c.width() == 5);
    CHECK(c.height() == 4);
    CHECK(c.get(4, 3) == bop::Rgb{1, 2, 3});
    c.set(2, 1, {9, 8, 7});
    CHECK(c.get(2, 1) == bop::Rgb{9, 8, 7});
    c.set(-1, 0, kWhite);  // ignored
    c.set(5, 0, kWhite);   // ignored
    CHECK_THROWS_AS(c.get(5, 0), std::out_of_range);
    CHECK_THROWS_AS(bop::Canvas(-1, 2, kBlack), std::invalid_argument);
}

TEST_CASE("a Canvas made from RGB bytes has them row by row, top row first", "[canvas]") {
    std::vector<std::uint8_t> rgb(3 * 3 * 2);
    for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = std::uint8_t(10 * i);
    const bop::Canvas c = bop::Canvas::fromRgb(3, 2, rgb);
    CHECK(c.get(0, 0) == bop::Rgb{0, 10, 20});
    CHECK(c.get(2, 0) == bop::Rgb{60, 70, 80});
    CHECK(c.get(1, 1) == bop::Rgb{120, 130, 140});
    CHECK(c.pixels() == rgb);
    CHECK_THROWS_AS(bop::Canvas::fromRgb(3, 3, rgb), std::invalid_argument);
}

TEST_CASE("fillRect colours exactly the pixels of the rectangle", "[canvas]") {
    bop::Canvas c(10, 8, kBlack);
    const bop::Rgb red{200, 10, 20};
    c.fillRect(2, 3, 4, 2, red);       // x 2..5, y 3..4
    c.fillRect(8, 6, 10, 10, kWhite);  // clipped to x 8..9, y 6..7
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 10; ++x) {
            const bool inRed = x >= 2 && x < 6 && y >= 3 && y < 5;
            const bool inWhite = x >= 8 && y >= 6;
            INFO("pixel " << x << ", " << y);
            CHECK(c.get(x, y) == (inRed ? red : inWhite ? kWhite : kBlack));
        }
}

TEST_CASE("drawText stays inside its text box", "[canvas]") {
    for (int scale : {1, 3}) {
        bop::Canvas c(80, 60, kBlack);
        const int x0 = 7, y0 = 5;
        const std::string text = "0123";
        c.drawText(x0, y0, text, kWhite, scale);
        const int w = c.textWidth(text, scale);
        const int h = c.textHeight(text, scale);
        CHECK(w == scale * c.textWidth(text));
        CHECK(w > 0);
        CHECK(h == 12 * scale);
        int inside = 0, outside = 0;
        int minX = 1000, maxX = -1;
        for (int y = 0; y < c.height(); ++y)
            for (int x = 0; x < c.width(); ++x) {
                const bop::Rgb p = c.get(x, y);
                REQUIRE((p == kBlack || p == kWhite));
                if (p != kWhite) continue;
                const bool in = x >= x0 && x < x0 + w && y >= y0 && y < y0 + h;
                (in ? inside : outside)++;
                minX = std::min(minX, x);
                maxX = std::max(maxX, x);
            }
        INFO("scale " << scale);
        CHECK(inside > 4 * 6 * scale * scale);  // several strokes per digit
        CHECK(outside == 0);
        // The four digits span most of the box width.
        CHECK(maxX - minX + 1 > w / 2);
    }
}

TEST_CASE("blit copies with clipping", "[canvas]") {
    bop::Canvas dst(6, 6, kBlack);
    bop::Canvas src(3, 3, {5, 6, 7});
    src.set(0, 0, kWhite);
    dst.blit(4, -1, src);  // visible part: src x 0..1, y 1..2 at dst x 4..5, y 0..1
    CHECK(dst.get(4, 0) == bop::Rgb{5, 6, 7});
    CHECK(dst.get(5, 1) == bop::Rgb{5, 6, 7});
    CHECK(dst.get(3, 0) == kBlack);
    CHECK(dst.get(4, 2) == kBlack);
}

TEST_CASE("writePng then stbi_load gives the same pixels", "[canvas]") {
    bop::Canvas c(37, 21, {10, 20, 30});
    for (int y = 0; y < c.height(); ++y)
        for (int x = 0; x < c.width(); ++x) c.set(x, y, bop::colourMap(double(x) / (c.width() - 1)));
    c.fillRect(3, 4, 5, 6, {255, 0, 128});
    c.drawText(1, 1, "Hi", kWhite);
    const std::string path = tempPath("picture.png");
    c.writePng(path);
    CHECK_FALSE(fs::exists(path + ".tmp"));

    int w = 0, h = 0, n = 0;
    unsigned char* img = stbi_load(path.c_str(), &w, &h, &n, 3);
    REQUIRE(img != nullptr);
    CHECK(w == c.width());
    CHECK(h == c.height());
    CHECK(n == 3);
    std::size_t differing = 0;
    for (std::size_t i = 0; i < c.pixels().size(); ++i)
        if (img[i] != c.pixels()[i]) ++differing;
    stbi_image_free(img);
    CHECK(differing == 0);
}

TEST_CASE("writePng reports an unwritable path", "[canvas]") {
    bop::Canvas c(2, 2, kBlack);
    const std::string path = tempPath("no_such_dir") + "/x.png";
    CHECK_THROWS_WITH(c.writePng(path), Catch::Contains(path));
    CHECK_THROWS_AS(bop::Canvas(0, 3, kBlack).writePng(tempPath("empty.png")), bop::Error);
}

TEST_CASE("colour maps", "[canvas]") {
    CHECK(bop::colourMap(0.0) == bop::Rgb{68, 1, 84});
    CHECK(bop::colourMap(1.0) == bop::Rgb{253, 231, 37});
    CHECK(bop::colourMap(-3.0) == bop::colourMap(0.0));
    CHECK(bop::colourMap(7.0) == bop::colourMap(1.0));
    // Viridis brightens monotonically (green channel rises).
    for (int i = 0; i < 100; ++i) CHECK(bop::colourMap(i / 100.0).g <= bop::colourMap((i + 1) / 100.0).g);
    CHECK(bop::divergingMap(0.0) == kWhite);
    const bop::Rgb blue = bop::divergingMap(-1.0), red = bop::divergingMap(1.0);
    CHECK(blue.b > blue.r);
    CHECK(red.r > red.b);
    CHECK(bop::divergingMap(-5.0) == blue);
    CHECK(bop::divergingMap(5.0) == red);
}
