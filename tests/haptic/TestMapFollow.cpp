// The haptic client's map copy follows the server's map (control/MapFollow.hpp): edits the server
// lists (a blade from another client, voxels that yielded) reach the copy through the front and a
// client session, paged and in order, and the copy ends equal, record for record, to the map with
// the same edits made directly; the client's own stroke, made before and listed again, changes
// nothing the second time; a refused edit leaves the copy as it was.
#include "bop/common/GradientMapCrop.hpp"
#include "bop/common/GradientMapEdit.hpp"
#include "bop/common/Units.hpp"
#include "client/ClientSession.hpp"
#include "control/BladeCuts.hpp"
#include "control/MapFollow.hpp"
#include "protocol/ProtocolSamples.hpp"
#include "server/ServerFront.hpp"
#include "shape/ShapeBuilder.hpp"
#include "shape/ShapeTestUtil.hpp"

#include <catch2/catch.hpp>

#include <thread>

using namespace bop;
using namespace std::chrono_literals;

namespace {

const Dims kDims{44, 26, 26};

SurfaceGeometryParams params() {
    SurfaceGeometryParams p;
    p.sigmaVoxels = 1.5;
    return p;
}

// Two balls side by side, radius 9 voxels, r0 2 voxels.
GradientMap twoBalls() {
    shape::BagLayout l;
    l.bag = Volume<std::uint8_t>(kDims, 0);
    l.parent = {0, 0, 0};
    for (std::size_t v = 0; v < kDims.count(); ++v) {
        const Eigen::Vector3d x = kDims.coords(v).cast<double>() + Eigen::Vector3d::Constant(0.5);
        if ((x - Eigen::Vector3d(11, 13, 13)).norm() < 9) l.bag.data[v] = 1;
        if ((x - Eigen::Vector3d(33, 13, 13)).norm() < 9) l.bag.data[v] = 2;
    }
    VoxelGrid g;
    g.dims = kDims;
    return shape::buildGradientMap(g, l, 2.0, params(), nullptr, 1);
}

GradientMap edited(const GradientMap& map, const MapPatch& patch) {
    return patch.empty() ? map : applyPatch(map, patch);
}

MapWindowReader reader(const GradientMap& map) {
    return [&map](const VoxelWindow& w) { return cropGradientMap(map, w); };
}

}  // namespace

TEST_CASE("haptic map copy: the server's edits reach it through the front, and it ends equal to the server's map",
          "[haptic][cut]") {
    const GradientMap original = twoBalls();
    const double h = voxelLength(original.r0Voxels);
    // The server's edits: a blade across the first ball (from another client), then the cap of
    // the second ball above z = 19 voxels (a yield), then the first blade again (our own stroke).
    const protocol::Cut blade{Eigen::Vector3d(11, 13, -2) * h, Eigen::Vector3d(11, 13, 28) * h, 2.5 * h};
    protocol::MapEdit yield;
    for (std::size_t v = 0; v < kDims.count(); ++v)
        if (original.occ[v] != 0 && kDims.coords(v).z() >= 19 && kDims.coords(v).x() > 22) yield.voxels.push_back(v);
    REQUIRE(yield.voxels.size() > 20);
    auto list = std::make_shared<std::vector<protocol::MapEdit>>(
        std::vector<protocol::MapEdit>{{blade, {}}, yield, {blade, {}}});

    // The truth: the same edits made on the map directly.
    BladeSweep sweep;
    sweep.a = blade.from / h, sweep.b = blade.to / h, sweep.radius = blade.radius / h;
    GradientMap truth = edited(original, cutPatch(reader(original), kDims, original.r0Voxels, sweep, params()));
    truth = edited(truth, voxelsPatch(reader(truth), kDims, truth.r0Voxels, yield.voxels, params()));
    REQUIRE(truth.occ != original.occ);

    protocol::FrontOptions fo;
    fo.basePort = 0;
    protocol::ServerFront front(fo, protocol::samples::sampleScene(2));
    front.setMapEdits(list);
    protocol::ClientSession session;
    session.connect(front.controlEndpoint(), 5s);

    haptic::FieldForce field(original, 1.0);
    haptic::FieldCutter cutter(field, params());
    cutter.push(haptic::Stroke{blade.from, blade.to, blade.radius});  // our own, at once
    haptic::MapFollower follower(cutter);
    const auto t0 = std::chrono::steady_clock::now();
    double s = 0;
    while (follower.taken() < list->size() && s < 5) {  // a 1 kHz loop's ticks, the feedback saying 3
        std::this_thread::sleep_for(1ms);
        s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        session.pollFeedback();
        follower.tick(session, s, std::uint32_t(list->size()));
    }
    REQUIRE(follower.taken() == list->size());
    CHECK(follower.requests() == 1);
    cutter.drain();
    CHECK(cutter.applied() == 4);
    CHECK(cutter.refused() == 0);

    test::requireSameMap(*field.map(), truth);
    // The field the hand feels: inside where the cap was is now outside.
    CHECK(haptic::FieldForce(original, 1.0).signedDistance(Eigen::Vector3d(33, 13, 20.5) * h) < 0);
    CHECK(field.signedDistance(Eigen::Vector3d(33, 13, 20.5) * h) > 0);

    // More edits later: the follower asks from where it stopped. A blade through everything is
    // refused by the copy as by the server, and voxels beyond the grid too: the map stays.
    auto more = std::make_shared<std::vector<protocol::MapEdit>>(*list);
    more->push_back({protocol::Cut{Eigen::Vector3d(-5, 13, 13) * h, Eigen::Vector3d(50, 13, 13) * h, 40 * h}, {}});
    more->push_back({protocol::Cut{}, {kDims.count() + 3}});
    front.setMapEdits(more);
    while (follower.taken() < more->size() && s < 10) {
        std::this_thread::sleep_for(1ms);
        s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        session.pollFeedback();
        follower.tick(session, s, std::uint32_t(more->size()));
    }
    REQUIRE(follower.taken() == more->size());
    cutter.drain();
    CHECK(cutter.refused() == 2);
    CHECK(cutter.lastRefusal().find("beyond the map") != std::string::npos);
    CHECK(field.map()->occ == truth.occ);
}
