// Extended XYZ snapshots: bit-exact round trip of a trajectory, files from other tools, and a
// bop::Error naming the file and the line for every malformed input.
#include "TestUtil.hpp"
#include "app/files/ExtendedXyz.hpp"
#include "bop/common/Error.hpp"
#include "core/Threads.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace bop;
using bop::app::XyzFrameInfo;

namespace {

// Names as the server writes them (not chemical symbols: ASE reads them from `type`).
const std::vector<std::string> kNames = {"", "sheet-surface", "fill-volume"};

// n particles: species 1 volume (identity orientation), species 2 oriented with spin.
core::Particles randomParticles(std::mt19937_64& rng, int n) {
    std::uniform_real_distribution<double> u(-10, 10);
    std::normal_distribution<double> g;
    core::Particles p;
    for (int i = 0; i < n; ++i) {
        const bool oriented = i % 2 == 1;
        const Eigen::Quaterniond q =
            oriented ? Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)) : Eigen::Quaterniond::Identity();
        const std::size_t k =
            p.add({u(rng), u(rng), u(rng)}, oriented ? 2 : 1, rng() >> 33, q);  // ids < 2^31, as runs give
        p.vel[k] = {g(rng), g(rng), g(rng)};
        if (oriented) p.omega[k] = {g(rng), g(rng), 1e-300 * g(rng)};
    }
    return p;
}

XyzFrameInfo randomInfo(std::mt19937_64& rng, long long step) {
    std::uniform_real_distribution<double> u(0, 1);
    XyzFrameInfo info;
    info.step = step;
    info.time = step * 0.1 + u(rng);
    info.boxLo = {-u(rng), -0.1 * u(rng), -1e5 * u(rng)};
    info.boxHi = {u(rng) * 3, 0.3 + u(rng), 7e5 * u(rng)};
    info.periodic = {true, false, step % 2 == 0};
    return info;
}

void requireSame(const app::XyzFrame& got, const core::Particles& p, const XyzFrameInfo& info) {
    CHECK(got.info.step == info.step);
    CHECK(got.info.time == info.time);
    CHECK(got.info.boxLo == info.boxLo);
    CHECK(got.info.boxHi == info.boxHi);
    CHECK(got.info.periodic == info.periodic);
    const core::Particles& r = got.particles;
    REQUIRE(r.size() == p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
        INFO("particle " << i);
        CHECK(r.pos[i] == p.pos[i]);
        CHECK(r.vel[i] == p.vel[i]);
        CHECK(r.q[i].coeffs() == p.q[i].coeffs());
        CHECK(r.normal[i] == p.normal[i]);
        CHECK(r.omega[i] == p.omega[i]);
        CHECK(r.species[i] == p.species[i]);
        CHECK(r.id[i] == p.id[i]);
        CHECK(r.force[i] == Eigen::Vector3d::Zero());
    }
}

std::string errorOf(const std::string& path, int frame = -1, const std::vector<std::string>& names = {"", "A", "B"}) {
    try {
        app::readExtendedXyz(path, names, frame);
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

// A python3 that can import ase, or "".
std::string pythonWithAse() {
    for (const char* py : {"python3", "/usr/bin/python3"}) {
        const std::string cmd = std::string(py) + " -c \"import ase.io\" > /dev/null 2>&1";
        if (std::system(cmd.c_str()) == 0) return py;
    }
    return "";
}

}  // namespace

TEST_CASE("extended XYZ trajectory reads back bit-exactly", "[app][xyz]") {
    test::TempDir dir("xyz");
    const std::string path = dir.file("traj.xyz");
    std::mt19937_64 rng(42);
    std::vector<core::Particles> parts;
    std::vector<XyzFrameInfo> infos;
    for (int f = 0; f < 3; ++f) {
        parts.push_back(randomParticles(rng, 20 + 7 * f));
        infos.push_back(randomInfo(rng, 1000 * f + 1));
        app::appendExtendedXyz(path, parts.back(), kNames, infos.back());
    }
    requireSame(app::readExtendedXyz(path, kNames, 1), parts[1], infos[1]);
    requireSame(app::readExtendedXyz(path, kNames), parts[2], infos[2]);
    requireSame(app::readExtendedXyz(path, kNames, 0), parts[0], infos[0]);
    // Species are looked up by name: another numbering of the same names maps them accordingly.
    const auto renumbered = app::readExtendedXyz(path, {"", "fill-volume", "sheet-surface", "X"}, 0);
    CHECK(renumbered.particles.species[0] == 2);
    CHECK(renumbered.particles.species[1] == 1);

    SECTION("header lines") {
        std::ostringstream os;
        app::writeExtendedXyz(os, parts[0], kNames, infos[0]);
        std::istringstream is(os.str());
        std::string count, comment;
        std::getline(is, count);
        std::getline(is, comment);
        CHECK(count == "20");
        CHECK_THAT(comment, Catch::Contains("Lattice=\"") && Catch::Contains("Origin=\"") &&
                                Catch::Contains("Properties=type:S:1:pos:R:3:velo:R:3:normal:R:3:"
                                                "orientation:R:4:omega:R:3:id:I:1:Z:I:1") &&
                                Catch::Contains("Step=1 ") && Catch::Contains("pbc=\"T F F\""));
    }
    SECTION("ASE reads it: names, species numbers, ids and positions") {
        // python3-ase is a test dependency (scripts/install-deps.sh): missing, the test fails.
        const std::string py = pythonWithAse();
        REQUIRE_FALSE(py.empty());
        const std::string printed = dir.file("ase.txt");
        const int code =
            std::system((py +
                         " -c \"import ase.io, sys; f = ase.io.read(sys.argv[1], index=':'); a = f[2]; "
                         "print(len(f), len(a)); print(*a.arrays['type']); print(*a.numbers); print(*a.arrays['id']); "
                         "print(*('%.17g' % x for x in a.positions.ravel())); print(f[1].info['Step'])\" " +
                         path + " > " + printed + " 2>&1")
                            .c_str());
        std::ifstream in(printed);
        const std::string out((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        INFO(out);
        REQUIRE(code == 0);
        std::istringstream is(out);
        std::size_t frames = 0, atoms = 0;
        is >> frames >> atoms;
        CHECK(frames == 3);
        REQUIRE(atoms == parts[2].size());
        const core::Particles& p = parts[2];
        for (std::size_t i = 0; i < atoms; ++i) {
            std::string name;
            is >> name;
            CHECK(name == kNames[p.species[i]]);
        }
        for (std::size_t i = 0; i < atoms; ++i) {
            int z = 0;
            is >> z;
            CHECK(z == p.species[i]);
        }
        for (std::size_t i = 0; i < atoms; ++i) {
            std::uint64_t id = 0;
            is >> id;
            CHECK(id == p.id[i]);
        }
        for (std::size_t i = 0; i < atoms; ++i)
            for (int a = 0; a < 3; ++a) {
                double x = 0;
                is >> x;
                CHECK(x == p.pos[i][a]);
            }
        long long step = 0;
        is >> step;
        CHECK(step == 1001);
    }
}

TEST_CASE("a large frame, formatted in blocks on the threads, is the same text at any thread count", "[app][xyz]") {
    // More lines than one group of blocks (64 x 4,096 lines, ExtendedXyz.cpp), the last block short.
    test::TempDir dir("xyz-large");
    std::mt19937_64 rng(5);
    const core::Particles p = randomParticles(rng, 64 * 4096 + 3 * 4096 + 17);
    const XyzFrameInfo info = randomInfo(rng, 77);
    const int before = core::threadCount();
    std::string text[2];
    for (int threads : {1, 2}) {
        core::setThreadCount(threads);
        std::ostringstream os;
        app::writeExtendedXyz(os, p, kNames, info);
        text[threads - 1] = os.str();
    }
    core::setThreadCount(before);
    CHECK(text[0] == text[1]);
    CHECK(std::size_t(std::count(text[0].begin(), text[0].end(), '\n')) == p.size() + 2);
    const std::string path = dir.file("large.xyz");
    std::ofstream(path, std::ios::binary) << text[1];
    requireSame(app::readExtendedXyz(path, kNames), p, info);  // every line, in order, to the bit
}

TEST_CASE("extended XYZ files of other tools load with defaults", "[app][xyz]") {
    test::TempDir dir("xyz");
    const std::vector<std::string> names = {"", "membrane", "cell"};
    SECTION("species and positions only") {
        const auto path = test::writeText(dir.file("min.xyz"),
                                          "2\nProperties=species:S:1:pos:R:3\ncell 1 2 3\nmembrane -4.5 +5 6e-1\n");
        const auto f = app::readExtendedXyz(path, names);
        const auto& p = f.particles;
        REQUIRE(p.size() == 2);
        CHECK(p.species == std::vector<std::uint8_t>{2, 1});
        CHECK(p.pos[1] == Eigen::Vector3d(-4.5, 5, 0.6));
        CHECK(p.vel[0] == Eigen::Vector3d::Zero());
        CHECK(p.omega[1] == Eigen::Vector3d::Zero());
        CHECK(p.q[0].coeffs() == Eigen::Quaterniond::Identity().coeffs());
        CHECK(p.normal[1] == Eigen::Vector3d::UnitZ());
        CHECK(p.id == std::vector<std::uint64_t>{0, 1});
        CHECK(f.info.periodic == std::array<bool, 3>{false, false, false});
        CHECK(f.info.step == 0);
    }
    SECTION("type numbers, normals and a cell without BoxHi") {
        const auto path = test::writeText(
            dir.file("normals.xyz"),
            "3\r\nLattice=\"2 0 0 0 3 0 0 0 4\" Origin=\"1 1 1\" Properties=type:I:1:pos:R:3:normal:R:3 comment\r\n"
            "1 0 0 0 0 0 -2\r\n2 0 0 0 3 0 0\r\n1 0 0 0 0 0 0\r\n");
        const auto f = app::readExtendedXyz(path, names);
        const auto& p = f.particles;
        REQUIRE(p.size() == 3);
        CHECK(p.species == std::vector<std::uint8_t>{1, 2, 1});
        CHECK(p.normal[0].isApprox(-Eigen::Vector3d::UnitZ(), 1e-14));
        CHECK(p.normal[1].isApprox(Eigen::Vector3d::UnitX(), 1e-14));
        CHECK((p.q[1] * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitY(), 1e-14));  // shortest arc
        CHECK(p.normal[2] == Eigen::Vector3d::UnitZ());
        CHECK(f.info.boxLo == Eigen::Vector3d(1, 1, 1));
        CHECK(f.info.boxHi == Eigen::Vector3d(3, 4, 5));
        CHECK(f.info.periodic == std::array<bool, 3>{true, true, true});  // extended XYZ default with a Lattice
    }
}

TEST_CASE("files of earlier versions restart: names in species, ids above 2^63 mapped", "[app][xyz]") {
    test::TempDir dir("xyz");
    // A birth at step 999, voxel 7 as earlier versions numbered it (bit 63 set), a seed and a
    // placed particle: the birth takes bit 62 instead, the others stay.
    const std::uint64_t oldBirth = (std::uint64_t(1) << 63) | (std::uint64_t(1000) << 32) | 7;
    const auto path = test::writeText(dir.file("old.xyz"),
                                      "3\nProperties=species:S:1:pos:R:3:id:I:1:species_number:I:1 Step=1000\n"
                                      "B 0 0 0 " +
                                          std::to_string(oldBirth) + " 2\nA 1 0 0 " +
                                          std::to_string(std::uint64_t(5) << 32) + " 1\nA 2 0 0 3 1\n");
    const auto f = app::readExtendedXyz(path, {"", "A", "B"});
    CHECK(f.particles.species == std::vector<std::uint8_t>{2, 1, 1});
    CHECK(f.particles.id[0] == ((std::uint64_t(1) << 62) | (std::uint64_t(1000) << 32) | 7));
    CHECK(f.particles.id[1] == std::uint64_t(5) << 32);
    CHECK(f.particles.id[2] == 3);
}

TEST_CASE("malformed extended XYZ gives an error naming file and line", "[app][xyz]") {
    test::TempDir dir("xyz");
    using Catch::Contains;
    auto file = [&](const std::string& name, const std::string& text) { return test::writeText(dir.file(name), text); };
    const std::string props = "Properties=species:S:1:pos:R:3";

    const auto missing = dir.file("absent.xyz");
    CHECK_THAT(errorOf(missing), Contains(missing) && Contains("cannot open"));
    auto check = [&](const std::string& path, const std::string& line, const std::string& what, int frame = -1) {
        INFO(path);
        CHECK_THAT(errorOf(path, frame), Contains(path) && Contains(line) && Contains(what) && Contains("expected"));
    };
    check(file("empty.xyz", ""), "line 1:", "no frame");
    check(file("count.xyz", "two\n" + props + "\nA 0 0 0\nA 1 1 1\n"), "line 1:", "particle count");
    check(file("count2.xyz", "2 atoms\n" + props + "\n"), "line 1:", "particle count");
    check(file("negative.xyz", "-1\n" + props + "\n"), "line 1:", "particle count");
    check(file("noprops.xyz", "1\nLattice=\"1 0 0 0 1 0 0 0 1\"\nA 0 0 0\n"), "line 2:", "Properties");
    check(file("nopos.xyz", "1\nProperties=species:S:1:x:R:3\nA 0 0 0\n"), "line 2:", "pos");
    check(file("nospecies.xyz", "1\nProperties=pos:R:3\n0 0 0\n"), "line 2:", "species");
    check(file("poscount.xyz", "1\nProperties=species:S:1:pos:R:2\nA 0 0\n"), "line 2:", "pos:R:3");
    check(file("triples.xyz", "1\nProperties=species:S:1:pos:R\nA 0 0 0\n"), "line 2:", "triples");
    check(file("badtype.xyz", "1\nProperties=species:S:1:pos:X:3\nA 0 0 0\n"), "line 2:", "malformed");
    check(file("quote.xyz", "1\nLattice=\"1 0 0 " + props + "\nA 0 0 0\n"), "line 2:", "quote");
    check(file("skew.xyz", "1\nLattice=\"1 0 0 1 1 0 0 0 1\" " + props + "\nA 0 0 0\n"), "line 2:", "orthogonal");
    check(file("pbc.xyz", "1\npbc=\"T F\" " + props + "\nA 0 0 0\n"), "line 2:", "pbc");
    check(file("time.xyz", "1\nTime=soon " + props + "\nA 0 0 0\n"), "line 2:", "Time");
    check(file("short.xyz", "2\n" + props + "\nA 0 0 0\nB 1 1\n"), "line 4:", "columns");
    check(file("long.xyz", "1\n" + props + "\nA 0 0 0 7\n"), "line 3:", "columns");
    check(file("nan.xyz", "1\n" + props + "\nA 0 abc 0\n"), "line 3:", "'abc'");
    check(file("inf.xyz", "1\n" + props + "\nA 0 inf 0\n"), "line 3:", "'inf'");
    check(file("species.xyz", "1\n" + props + "\nC 0 0 0\n"), "line 3:", "unknown species 'C'");
    CHECK_THAT(errorOf(dir.file("species.xyz")), Contains("A, B"));
    check(file("typenum.xyz", "1\nProperties=type:I:1:pos:R:3\n7 0 0 0\n"), "line 3:", "species number");
    check(file("id.xyz", "1\nProperties=species:S:1:pos:R:3:id:I:1\nA 0 0 0 -3\n"), "line 3:", "id");
    check(file("quat.xyz", "1\nProperties=species:S:1:pos:R:3:orientation:R:4\nA 0 0 0 0 0 0 0\n"),
          "line 3:", "orientation");
    const auto two = file("two.xyz", "1\n" + props + "\nA 0 0 0\n1\n" + props + "\nB 1 1 1\n");
    check(two, "line 6:", "frame 2", 2);
    check(two, "line 6:", "frame -2", -2);
    CHECK_THAT(errorOf(two, 1), Contains("(no error)"));
    check(file("trunc.xyz", "1\n" + props + "\nA 0 0 0\n3\n" + props + "\nA 0 0 0\nA 1 1 1\n"), "line 8:", "truncated");
    CHECK_THAT(errorOf(dir.file("trunc.xyz"), 0), Contains("(no error)"));  // frame 0 is complete
    check(file("nocomment.xyz", "1\n" + props + "\nA 0 0 0\n1\n"), "line 5:", "comment line");
}

TEST_CASE("extended XYZ writer errors", "[app][xyz]") {
    test::TempDir dir("xyz");
    using Catch::Contains;
    core::Particles p;
    p.add({0, 0, 0}, 3, 0);
    std::ostringstream os;
    CHECK_THROWS_WITH(app::writeExtendedXyz(os, p, {"", "A", "B"}, {}), Contains("species number 3"));
    CHECK_THROWS_WITH(app::writeExtendedXyz(os, p, {"", "A", "B", "big cell"}, {}), Contains("whitespace"));
    core::Particles big;
    big.add({0, 0, 0}, 1, std::uint64_t(1) << 63);
    CHECK_THROWS_WITH(app::writeExtendedXyz(os, big, {"", "A"}, {}), Contains("signed 64-bit"));
    const std::string bad = dir.file("no/such/dir/out.xyz");
    CHECK_THROWS_WITH(app::appendExtendedXyz(bad, p, {"", "A", "B", "C"}, {}),
                      Contains(bad) && Contains("cannot write"));
}
