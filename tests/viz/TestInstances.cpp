// The viewer's data-to-instances stage (viz_client/scene/Instances.hpp): kinds, colours, filters,
// the cut plane, and quantised frames drawn where float ones are.
#include "codec/Codec.hpp"
#include "codec/Quantise.hpp"
#include "scene/Instances.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace bop;
using namespace bop::viz;
using protocol::SpeciesKind;

namespace {

// Two species, a surface one (red) and a volume one (blue); r0 = sqrt 3.
protocol::SceneInfo scene() {
    protocol::SceneInfo s;
    s.species = {{"membrane", SpeciesKind::Surface, {220, 40, 30, 255}},
                 {"fill", SpeciesKind::Volume, {30, 60, 200, 128}}};
    s.boxLo = Eigen::Vector3d(-10, -10, -10);
    s.boxHi = Eigen::Vector3d(10, 10, 10);
    return s;
}

// n particles on a line along x from -n/2 to n/2, species alternating 1, 2; every fifth has
// species `odd` instead.
protocol::StateFrame frame(std::size_t n, int odd = 2) {
    protocol::StateFrame f;
    f.frameParticleCount = std::uint32_t(n);
    for (std::size_t i = 0; i < n; ++i) {
        const float x = float(i) - float(n) / 2;
        f.positions.insert(f.positions.end(), {x, 0.5f * x, 1.0f});
        const float c = std::cos(0.1f * float(i)), s = std::sin(0.1f * float(i));
        f.normals.insert(f.normals.end(), {c, s, 0.0f});
        f.species.push_back(std::uint8_t(i % 5 == 4 ? odd : 1 + i % 2));
    }
    return f;
}

}  // namespace

TEST_CASE("instances: surface particles become discs facing their normals, volume ones spheres", "[viz]") {
    const protocol::SceneInfo s = scene();
    const protocol::StateFrame f = frame(20);
    Instances out;
    buildInstances(f, s, {}, out);
    CHECK(out.surfels.size() + out.spheres.size() == 20);
    CHECK(out.drawnPerSpecies[1] == out.surfels.size());
    CHECK(out.drawnPerSpecies[2] == out.spheres.size());
    CHECK(out.cut + out.hidden + out.unknownSpecies == 0);
    const std::uint32_t red = packRgba({220, 40, 30, 255}), blue = packRgba({30, 60, 200, 128});
    CHECK(red == 0xFF1E28DCu);  // red byte lowest, as GL reads four unsigned bytes
    std::size_t k = 0;
    for (std::size_t i = 0; i < 20; ++i) {
        if (f.species[i] != 1) continue;
        const Surfel& d = out.surfels[k++];
        CHECK(d.position[0] == f.positions[3 * i]);
        CHECK(d.normal[1] == f.normals[3 * i + 1]);
        CHECK(d.rgba == red);
        CHECK(d.radius == Approx(kSurfelRadiusR0 * s.r0));
    }
    for (const Sphere& b : out.spheres) {
        CHECK(b.rgba == blue);
        CHECK(b.radius == Approx(kSphereRadiusR0 * s.r0));
    }
    // Discs of this radius leave no hole between neighbours of a triangulated sheet stretched to
    // 1.5 r0: the circumradius of such a triangle is 1.5 r0 / sqrt 3.
    CHECK(kSurfelRadiusR0 >= 1.5 / std::sqrt(3.0));
}

TEST_CASE("instances: kinds and species can be hidden, and unknown species are drawn grey", "[viz]") {
    const protocol::SceneInfo s = scene();
    Instances out;
    ViewFilter v;
    v.showSurface = false;
    buildInstances(frame(20), s, v, out);  // 8 of species 1, 12 of species 2
    CHECK(out.surfels.empty());
    CHECK(out.hidden == 8);
    v = {};
    v.hiddenSpecies = {false, false, true};
    buildInstances(frame(20), s, v, out);
    CHECK(out.spheres.empty());
    CHECK(out.hidden == 12);
    buildInstances(frame(20, 9), s, {}, out);  // species 9 is not in the scene info
    CHECK(out.unknownSpecies == 4);
    std::size_t grey = 0;
    for (const Sphere& b : out.spheres) grey += b.rgba == packRgba(kUnknownSpeciesRgba);
    CHECK(grey == 4);
    protocol::StateFrame bare = frame(20);  // no normals: discs cannot face anything
    bare.normals.clear();
    buildInstances(bare, s, {}, out);
    CHECK(out.surfels.empty());
    CHECK(out.spheres.size() == 20);
}

TEST_CASE("instances: the cut plane removes what lies in front of it", "[viz]") {
    const protocol::SceneInfo s = scene();
    const protocol::StateFrame f = frame(41);
    ViewFilter v;
    v.cut = CutPlane{Eigen::Vector3d(2.5, 0, 0), Eigen::Vector3d(3, 0, 0)};  // keeps x <= 2.5
    Instances out;
    buildInstances(f, s, v, out);
    std::size_t kept = 0;
    for (std::size_t i = 0; i < f.count(); ++i) kept += f.positions[3 * i] <= 2.5f;
    CHECK(out.surfels.size() + out.spheres.size() == kept);
    CHECK(out.cut == f.count() - kept);
    for (const Surfel& d : out.surfels) CHECK(d.position[0] <= 2.5f);
    for (const Sphere& b : out.spheres) CHECK(b.position[0] <= 2.5f);
    v.cut->normal = Eigen::Vector3d(-1, 0, 0);  // the other side
    buildInstances(f, s, v, out);
    CHECK(out.cut == kept - 1);  // x = 2.5 itself lies on the plane: kept both times
}

TEST_CASE("instances: a quantised frame is drawn where the float frame is, within the stated error", "[viz]") {
    const protocol::SceneInfo s = scene();
    protocol::StateFrame f = frame(19);  // inside the box: nothing clamped
    f.quantLo = s.boxLo;
    f.quantHi = s.boxHi;
    f.encoding = protocol::FrameEncoding::Quantised16;
    const protocol::Buffer b = protocol::encodeStateFrame(f);
    const auto q = protocol::decodeStateFrame(b.data(), b.size());
    REQUIRE(q.ok());
    Instances exact, coded;
    buildInstances(f, s, {}, exact);
    buildInstances(q.value, s, {}, coded);
    REQUIRE(coded.surfels.size() == exact.surfels.size());
    REQUIRE(coded.spheres.size() == exact.spheres.size());
    const Eigen::Vector3d bound = protocol::positionErrorBound(s.boxLo, s.boxHi);
    for (std::size_t k = 0; k < exact.surfels.size(); ++k) {
        for (int a = 0; a < 3; ++a)
            CHECK(std::abs(coded.surfels[k].position[a] - exact.surfels[k].position[a]) <= bound[a]);
        const Eigen::Vector3d n0(exact.surfels[k].normal[0], exact.surfels[k].normal[1], exact.surfels[k].normal[2]);
        const Eigen::Vector3d n1(coded.surfels[k].normal[0], coded.surfels[k].normal[1], coded.surfels[k].normal[2]);
        CHECK(std::acos(std::min(1.0, n0.normalized().dot(n1.normalized()))) <= protocol::kOctMaxAngleRad);
    }
}
