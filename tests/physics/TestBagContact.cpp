// Two bags side by side, one pushed into the other by the probe. Bag a is a slab 8 voxels (4 r0)
// thick, bag b a box beside it across a gap of 1 voxel (their sheets about r0 apart); both placed
// and settled from a two-label image. The probe presses a's near face from inside a, towards b.
// The same run without the probe is the reference. b can move only through the pair forces
// between the bags: with them, its centre of mass moves; with their LJ weight set to 0 it moves
// by round-off only (the probe never comes within its reach of b). Each bag is held to
// its map, so the push is small: a's sheet slides aside under the probe more than it bulges.
#include "OneProcessRun.hpp"
#include "TestUtil.hpp"
#include "app/scene/RunStart.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <map>

using namespace bop;

namespace {

const Eigen::Vector3i kSize(38, 28, 28);  // image voxels of 1 mm
constexpr int kA0 = 6, kA1 = 14;          // bag a: x in [6, 14)
constexpr int kB0 = 15, kB1 = 29;         // bag b: x in [15, 29); both y, z in [6, 22)

std::string writeScene(const test::TempDir& dir) {
    std::vector<std::uint8_t> voxels;
    for (int z = 0; z < kSize.z(); ++z)
        for (int y = 0; y < kSize.y(); ++y)
            for (int x = 0; x < kSize.x(); ++x) {
                const bool yz = y >= 6 && y < 22 && z >= 6 && z < 22;
                voxels.push_back(!yz ? 0 : x >= kA0 && x < kA1 ? 1 : x >= kB0 && x < kB1 ? 2 : 0);
            }
    std::ofstream(dir.file("two.raw"), std::ios::binary)
        .write(reinterpret_cast<const char*>(voxels.data()), std::streamsize(voxels.size()));
    return test::writeText(dir.file("two.toml"),
                           "[grid]\npadding_voxels = 4\nr0_voxels = 2.0\n[shape]\nsmoothing_sigma_voxels = 1.5\n"
                           "[[shape.bag]]\nsource = \"raw\"\nfile = \"two.raw\"\nsize_voxels = [38, 28, 28]\n"
                           "spacing_mm = [1.0, 1.0, 1.0]\nlabels = [1, 2]\nname = \"box\"\n"
                           "[dynamics]\ntime_step = 0.02\nseed = 1\n[run]\nsteps = 20000\n");
}

struct Outcome {
    Eigen::Vector3d centreB = Eigen::Vector3d::Zero();  // b's centre of mass, voxels
    std::map<std::uint64_t, Eigen::Vector3d> b;         // b's particles by id, voxels
    double reaction = 0;                                // largest reaction on the probe along -x
};

// Settles the scene for 1500 steps, then 600 more with or without the probe pressing a: it moves
// over 300 steps from 4 voxels inside a's near face to 1.4 voxels inside it, on the face's middle,
// and stays there. Small and strong, it reaches 2.4 voxels: b's nearest particles stay beyond.
Outcome run(bool poke, double ljBetweenBags) {
    test::TempDir dir("bag-contact");
    app::Scene scene = app::loadScene(writeScene(dir));
    const core::Model& m = *scene.model;
    REQUIRE(m.speciesCount() == 4);
    for (int a : {1, 2})
        for (int b : {3, 4}) scene.params.lj(a, b) = scene.params.lj(b, a) = ljBetweenBags;
    test::OneProcessRun r(scene);
    r->run(1500);
    const double h = voxelLength(r.wholeMap().r0Voxels);
    const Eigen::Vector3d origin = r.wholeMap().grid.originMm;  // 1 mm voxels: the image's voxel 0
    auto toSim = [&](double x, double y, double z) {            // image mm to simulation length
        return Eigen::Vector3d((x - origin.x()) * h, (y - origin.y()) * h, (z - origin.z()) * h);
    };
    core::ProbeState& probe = r->probe();
    probe.params = {0.75, 10.0};  // repels within 0.75 r0 = 1.5 voxels, reaches 1.6 times that
    const Eigen::Vector3d from = toSim(kA1 - 4, 14, 14), to = toSim(kA1 - 1.4, 14, 14);
    Outcome out;
    for (int s = 0; s < 600; ++s) {
        probe.active = poke;
        probe.position = from + (to - from) * std::min(1.0, s / 300.0);
        r->step();
        out.reaction = std::max(out.reaction, -r->stats().forces.probeReaction.x());
    }
    const core::Particles& p = r->particles();
    std::size_t n = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
        if (p.species[i] >= 3) {
            out.b[p.id[i]] = p.pos[i] / h;
            out.centreB += p.pos[i] / h;
            ++n;
        }
    out.centreB /= double(n);
    return out;
}

}  // namespace

TEST_CASE("the probe pushes one bag into its neighbour, which moves; without LJ between them it does not",
          "[physics][contact]") {
    for (double lj : {1.0, 0.0}) {
        const Outcome still = run(false, lj), pushed = run(true, lj);
        REQUIRE(still.b.size() == pushed.b.size());
        double largest = 0;
        for (const auto& [id, x] : still.b) largest = std::max(largest, (pushed.b.at(id) - x).norm());
        const Eigen::Vector3d shift = pushed.centreB - still.centreB;
        INFO("LJ between the bags " << lj << ": b's centre of mass moved " << shift.transpose()
                                    << " voxels; its particles up to " << largest << " voxels; probe reaction up to "
                                    << pushed.reaction);
        CHECK(pushed.reaction > 1.0);  // the probe did press a
        if (lj > 0) {
            CHECK(shift.norm() > 2e-4);  // (1.4e-3 voxels when written)
            CHECK(largest > 0.01);       // (0.044)
        } else {
            CHECK(shift.norm() < 1e-9);  // round-off: a's particles change the order of b's sums
            CHECK(largest < 1e-9);
        }
    }
}
