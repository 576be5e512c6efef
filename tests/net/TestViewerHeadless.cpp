// bop-viewer --headless against a served run (2 ranks): it connects, draws the frames it gets
// and writes them as PNG files of the asked size showing the particles.
#include "ServerProcess.hpp"
#include "TestUtil.hpp"

#include <catch2/catch.hpp>
#include <stb/stb_image.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <regex>

using namespace bop;
using namespace std::chrono_literals;

TEST_CASE("bop-viewer --headless writes the frames of a 2-rank server as pictures of its particles", "[net][gui]") {
    test::TempDir dir("viewer-headless");
    test::ServerProcess srv({test::mpiexec(), "-np", "2", "--oversubscribe", test::buildDir() + "/dynamics_server/bop-server",
                             test::sourceDir() + "/config/scenes/bulk-box.toml", "--port", "0", "--publish-hz", "20",
                             "-o", dir.file("run")});
    const std::string out = dir.file("frames");
    const auto [code, printed] = test::runCommand(test::buildDir() + "/viz_client/bop-viewer " + srv.endpoint() +
                                                  " --headless --frames 4 --width 320 --height 240 --out " + out +
                                                  " 2>&1");
    INFO(printed);
    REQUIRE(code == 0);
    // Steps advance from frame to frame: the pictures are of a running server.
    std::vector<long long> steps;
    const std::regex line("frame [0-9]+: step ([0-9]+), 2048 particles");
    for (auto it = std::sregex_iterator(printed.begin(), printed.end(), line); it != std::sregex_iterator(); ++it)
        steps.push_back(std::stoll((*it)[1]));
    REQUIRE(steps.size() == 4);
    for (std::size_t k = 1; k < steps.size(); ++k) CHECK(steps[k] > steps[k - 1]);
    for (int k = 1; k <= 4; ++k) {
        const std::string png = out + "/frame-00000" + std::to_string(k) + ".png";
        int w = 0, h = 0, channels = 0;
        unsigned char* rgb = stbi_load(png.c_str(), &w, &h, &channels, 3);
        REQUIRE(rgb != nullptr);
        CHECK(w == 320);
        CHECK(h == 240);
        // The background is (0.1, 0.1, 0.12) x 255; the box of particles fills a good part of it.
        std::size_t particles = 0;
        for (int i = 0; i < w * h; ++i)
            particles += std::abs(rgb[3 * i] - 26) > 2 || std::abs(rgb[3 * i + 1] - 26) > 2 || std::abs(rgb[3 * i + 2] - 31) > 2;
        stbi_image_free(rgb);
        INFO(png << ": " << particles << " particle pixels");
        CHECK(particles > std::size_t(w * h) / 10);
    }
    srv.stop(SIGINT);
}
