// The haptic client's loop and local force model without a server: the clock on absolute
// deadlines, the virtual coupling (free space, contact, stiff springs), the safety ramps, the
// gradient-map field on a slab, the scripted paths, the finger, the workspace mapping.
#include "control/FieldForce.hpp"
#include "control/ForceModel.hpp"
#include "control/RateLoop.hpp"
#include "device/SimDevices.hpp"
#include "device/Workspace.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <thread>

using namespace bop;
using namespace bop::haptic;

TEST_CASE("haptic loop: deadlines a period apart, percentiles of lateness, missed deadlines skipped", "[haptic]") {
    LatenessHistogram h;
    for (int k = 1; k <= 100; ++k) h.add(k);  // 1 .. 100 us
    CHECK(h.percentile(50) == Approx(50.5));
    CHECK(h.percentile(99) == Approx(99.5));
    CHECK(h.max() == 100);

    RateLoop loop(1000);
    std::vector<LoopTick> ticks;
    loop.run([&](const LoopTick& t) {
        ticks.push_back(t);
        if (t.index == 20) std::this_thread::sleep_for(std::chrono::milliseconds(6));  // a stall
        return ticks.size() < 100;
    });
    REQUIRE(ticks.size() == 100);
    const PeriodStats s = loop.whole();
    CHECK(s.ticks == 100);
    CHECK(s.missed >= 5);                  // the stall skipped at least five deadlines...
    CHECK(ticks[21].dtS >= 0.006 - 1e-9);  // ...and the tick after it says so
    for (std::size_t k = 1; k < ticks.size(); ++k) {
        const double steps = ticks[k].dtS / 0.001;
        CHECK(std::abs(steps - std::round(steps)) < 1e-6);  // deadlines on the 1 ms grid
        CHECK(ticks[k].tS > ticks[k - 1].tS);
    }
    // However loaded the machine: every deadline up to the last tick's was a tick or is counted
    // as missed, and the loop is never early.
    CHECK(double(s.ticks + s.missed) == std::round(ticks.back().tS / 0.001) + 1);
    CHECK(s.rateHz <= 1000);
    CHECK(s.p50Us <= s.p99Us);
    CHECK(s.p99Us <= s.maxUs + 1);
}

namespace {

// Runs the model at 1 kHz for `seconds` with the hand at device(t) and feedback every tick
// from reaction(proxy) until `silentFrom`; returns the outputs.
std::vector<ForceOutput> simulate(ForceModel& m, double seconds, const std::function<Eigen::Vector3d(double)>& device,
                                  const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& reaction,
                                  double silentFrom = 1e300) {
    std::vector<ForceOutput> out;
    Eigen::Vector3d proxy = device(0);
    for (int k = 0; k * 0.001 < seconds; ++k) {
        const double t = k * 0.001;
        if (t < silentFrom) m.feedback(reaction(proxy), t);
        out.push_back(m.tick(t, 0.001, device(t)));
        proxy = out.back().proxy;
    }
    return out;
}

}  // namespace

TEST_CASE("virtual coupling: the proxy follows a free hand; in contact the hand feels the reaction", "[haptic]") {
    ForceModelParams p;
    ForceModel free(p);
    const auto moving = [](double t) { return Eigen::Vector3d(2 * t, 0, 0); };  // 2 length / s
    const auto none = [](const Eigen::Vector3d&) { return Eigen::Vector3d::Zero(); };
    const std::vector<ForceOutput> a = simulate(free, 2, moving, none);
    CHECK((a.back().proxy - moving(1.999)).norm() < 0.05);  // a few ticks behind the hand
    CHECK(a.back().force.norm() < 0.3);                     // the spring barely stretched

    ForceModel contact(p);
    const Eigen::Vector3d reaction(0, 0, 5);  // the server pushes the probe up with 5 force units
    const std::vector<ForceOutput> b = simulate(
        contact, 2, [](double) { return Eigen::Vector3d(0, 0, -1); }, [&](const Eigen::Vector3d&) { return reaction; });
    CHECK((b.back().force - reaction).norm() < 1e-3);  // at rest, the hand feels the reaction
    CHECK(b.back().gain == 1);
    CHECK((b.back().proxy - Eigen::Vector3d(0, 0, -1 + 5 / p.stiffness)).norm() < 1e-3);

    // A spring a hundred times stiffer stays stable (implicit integration): bounded, settles.
    ForceModelParams stiff = p;
    stiff.stiffness = 1000;
    stiff.damping = 2 * std::sqrt(stiff.stiffness * stiff.proxyMass);
    ForceModel s(stiff);
    const std::vector<ForceOutput> c = simulate(
        s, 1, [](double t) { return Eigen::Vector3d(t < 0.6 ? 0 : -0.5, 0, 0); },
        [](const Eigen::Vector3d& x) {
            return Eigen::Vector3d(x.x() < 0 ? -200 * x.x() : 0, 0, 0);  // a wall at x = 0
        });
    double largest = 0;
    for (const ForceOutput& o : c) largest = std::max(largest, o.force.norm());
    // The hand jumped 0.5 in one tick: at most the spring and the damper of that jump, once.
    CHECK(largest < stiff.stiffness * 0.5 + stiff.damping * 0.5 / 0.001);
    // Within 0.3 s it settles on the series springs of coupling and wall: 1000 * 200 / 1200 * 0.5.
    for (std::size_t k = 900; k < c.size(); ++k)
        CHECK(c[k].force.x() == Approx(1000.0 * 200 / 1200 * 0.5).epsilon(0.01));
}

TEST_CASE("safety: silence ramps the force to 0 within 50 ms; it comes back over half a second", "[haptic]") {
    ForceModelParams p;
    ForceModel m(p);
    const Eigen::Vector3d reaction(0, 0, 5);
    const std::vector<ForceOutput> o = simulate(
        m, 2.0, [](double) { return Eigen::Vector3d(0, 0, -1); }, [&](const Eigen::Vector3d&) { return reaction; },
        1.0);
    REQUIRE(o[999].force.norm() > 4.9);  // before the silence
    std::size_t zeroAt = 0;
    for (std::size_t k = 1000; k < o.size() && !zeroAt; ++k)
        if (o[k].force.norm() == 0) zeroAt = k;
    REQUIRE(zeroAt > 0);
    const double ms = double(zeroAt) - 999;  // since the last feedback, at 1 ms per tick
    INFO("force at 0 after " << ms << " ms");
    CHECK(ms <= 50);
    for (std::size_t k = 1000; k < zeroAt; ++k) CHECK(o[k].gain <= o[k - 1].gain);  // falling, never rising
    CHECK(silenceGain(p, 0.01) == 1);
    CHECK(silenceGain(p, p.silenceS + p.rampDownS) == Approx(0).margin(1e-12));

    // Feedback back at 1.5 s: the gain rises no faster than over rampUp.
    ForceModel back(p);
    std::vector<ForceOutput> r;
    for (int k = 0; k < 2500; ++k) {
        const double t = k * 0.001;
        if (t < 1.0 || t >= 1.5) back.feedback(reaction, t);
        r.push_back(back.tick(t, 0.001, Eigen::Vector3d(0, 0, -1)));
    }
    CHECK(r[1499].gain == 0);
    CHECK(r[1600].gain == Approx(0.2).margin(0.01));  // 100 ms of 500 ms
    CHECK(r[2100].gain == 1);
}

namespace {

// A slab: voxels with k < 10 inside the bag (volume 2), k = 10 its surface (species 1, normal +z),
// above outside; every voxel's nearest surface voxel is the one of its column at k = 10.
GradientMap slab() {
    GradientMap m;
    m.r0Voxels = 2;
    m.grid.dims = {4, 4, 20};
    const Dims& d = m.grid.dims;
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                m.occ.push_back(k < 10 ? 2 : k == 10 ? 1 : 0);
                m.nearest.push_back(std::uint32_t(i + d.nx * j));
            }
    for (int j = 0; j < d.ny; ++j)
        for (int i = 0; i < d.nx; ++i) {
            SurfaceVoxel s;
            s.voxel = std::uint32_t(d.index(i, j, 10));
            s.species = 1;
            m.surface.push_back(s);
        }
    return m;
}

}  // namespace

TEST_CASE("field force: zero outside the bag, growing with depth inside, along the outward normal", "[haptic]") {
    const FieldForce f(slab(), 4.0);
    const double h = f.voxelSize();   // sqrt 3 / 2
    const double surface = 10.5 * h;  // the surface voxels' centres
    CHECK(f.signedDistance({2 * h, 2 * h, surface}) == Approx(0).margin(1e-12));
    CHECK(f.signedDistance({2 * h, 2 * h, surface + 2 * h}) == Approx(2 * h));
    CHECK(f.signedDistance({2 * h, 2 * h, surface - 1.25 * h}) == Approx(-1.25 * h));  // continuous between centres
    CHECK(f({2 * h, 2 * h, surface + 0.3 * h}).norm() == 0);
    const Eigen::Vector3d in = f({2 * h, 2 * h, surface - 3 * h});
    CHECK(in.x() == 0);
    CHECK(in.y() == 0);
    CHECK(in.z() == Approx(4.0 * 3 * h));
    CHECK(f.top().z() == Approx(surface));
}

TEST_CASE("scripted paths: a poke goes in to its depth, holds and comes out; a circle keeps its radius", "[haptic]") {
    PathScript p;
    p.surfaceMm = {0, 0, 0};
    p.inward = {0, 0, -1};
    p.standoffMm = 10, p.depthMm = 5, p.speedMmPerS = 10, p.holdS = 1;
    CHECK(pathAt(p, 0).z() == Approx(10));
    CHECK(pathAt(p, 1.5).z() == Approx(-5));  // in after 15 mm at 10 mm/s
    CHECK(pathAt(p, 2.0).z() == Approx(-5));  // holding
    CHECK(pathAt(p, 3.0).z() == Approx(0));   // halfway out
    CHECK(pathDuration(p) == Approx(4.0));
    CHECK(pathAt(p, 9).z() == Approx(10));
    p.kind = PathKind::Circle;
    p.radiusMm = 3;
    const double start = 2.5, half = 3.14159265358979 * 3 / 10;  // s: the circle begins; half a turn
    const Eigen::Vector3d centre = 0.5 * (pathAt(p, start) + pathAt(p, start + half));
    for (double t = start; t < start + 2 * half; t += 0.05) {
        const Eigen::Vector3d q = pathAt(p, t);
        CHECK(q.z() == Approx(-5));
        CHECK((q - centre).norm() == Approx(3).epsilon(1e-6));
    }
    CHECK(pathDuration(p) == Approx(4.0 + 2 * half));
}

TEST_CASE("sim:finger pressed into a stiff surface by the force model comes to rest without oscillating", "[haptic]") {
    // The finger's path goes 5 mm into a surface at z = 0 mm; the "server" is a wall of 100
    // force/length (5 N/mm on the device), felt through the coupling (10 force/length, 0.5 N/mm).
    PathScript p;
    p.inward = {0, 0, -1};
    p.standoffMm = 5, p.depthMm = 5, p.speedMmPerS = 20, p.holdS = 3;
    auto finger = makeFingerDevice(p, FingerParams{}, DeviceLimits{});
    Workspace w;  // 0.1 length per mm, 0.5 N per force unit
    ForceModelParams mp;
    ForceModel model(mp);
    std::vector<double> z;
    for (int k = 0; k < 3000; ++k) {
        const double t = k * 0.001;
        const Eigen::Vector3d x = w.toScene(finger->read(t).positionMm);
        const ForceOutput out = model.tick(t, 0.001, x);
        // The "server": a wall of 100 force / length at z = 0 pushing the proxy out, for the next tick.
        model.feedback(Eigen::Vector3d(0, 0, out.proxy.z() < 0 ? -100 * out.proxy.z() : 0), t);
        finger->render(w.forceToDevice(out.force), t);
        z.push_back(x.z() / w.scale);  // mm
    }
    // The last second: at rest, short of the path's 5 mm because the surface pushes back.
    double lo = 1e9, hi = -1e9;
    for (std::size_t k = 2000; k < z.size(); ++k) lo = std::min(lo, z[k]), hi = std::max(hi, z[k]);
    INFO("finger z in the last second: " << lo << " .. " << hi << " mm");
    CHECK(hi - lo < 0.05);
    CHECK(lo > -5);
    CHECK(hi < 0.5);
}

TEST_CASE("workspace: device and scene coordinates and forces map back and forth; fit covers the scene", "[haptic]") {
    const Eigen::AlignedBox3d device(Eigen::Vector3d(-80, -60, -40), Eigen::Vector3d(80, 60, 40));
    const Eigen::AlignedBox3d scene(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(40, 40, 16));
    const Workspace w = Workspace::fit(device, scene, 0.5);
    CHECK(w.scale == Approx(40.0 / 120));  // y is the tightest axis
    CHECK((w.toScene(device.center()) - scene.center()).norm() < 1e-12);
    for (const Eigen::Vector3d& c : {scene.min(), scene.max()}) {
        CHECK(device.contains(w.toDevice(c)));
        CHECK((w.toScene(w.toDevice(c)) - c).norm() < 1e-9);
    }
    const Eigen::Vector3d f(1, -2, 3);
    CHECK((w.forceToScene(w.forceToDevice(f)) - f).norm() < 1e-12);
    CHECK(w.forceToDevice(f).norm() == Approx(0.5 * f.norm()));
}

TEST_CASE("workspace for a tissue in physical units: the device renders its newtons, mm for mm, no scale",
          "[haptic][units]") {
    const Eigen::AlignedBox3d device(Eigen::Vector3d(-80, -60, -40), Eigen::Vector3d(80, 60, 40));
    const Eigen::AlignedBox3d scene(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(40, 40, 16));
    const bop::UnitSystem units = bop::UnitSystem::fromModulus(1.155, 5.66e-6, 5e3, 2.1);
    const Workspace w = Workspace::forScene(device, scene, units, std::nullopt, 1.0);
    // A force of 3 simulation units is 3 forceN() newtons on the device, as the tissue gives it.
    const Eigen::Vector3d f(0, 0, 3);
    CHECK(w.forceToDevice(f).norm() == Approx(3 * units.forceN()));
    // 10 mm of device travel is 10 mm of tissue.
    const Eigen::Vector3d moved = w.toScene(device.center() + Eigen::Vector3d(10, 0, 0)) - w.toScene(device.center());
    CHECK(units.toMm(moved.norm()) == Approx(10.0));
    // A stated scale-down for a weak device, and the scale of a scene without units refused.
    CHECK(Workspace::forScene(device, scene, units, std::nullopt, 0.25).forceToDevice(f).norm() ==
          Approx(0.75 * units.forceN()));
    CHECK_THROWS_AS(Workspace::forScene(device, scene, units, 0.5, 1.0), std::invalid_argument);
    // Without materials: the box fit and --newtons-per-force (0.5 unless given).
    const Workspace plain = Workspace::forScene(device, scene, bop::UnitSystem{}, std::nullopt, 1.0);
    CHECK(plain.scale == Approx(40.0 / 120));
    CHECK(plain.forceToDevice(f).norm() == Approx(1.5));
}
