// The physical unit system of a scene (bop/common/UnitSystem.hpp, docs/physics.md §8.1): a length,
// a force and a time converted both ways, and the derived units held to their definitions.
#include "bop/common/UnitSystem.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using bop::UnitSystem;

TEST_CASE("a length, a force and a time convert to mm, N and s and back", "[common][units]") {
    // A scene of 1 mm voxels at r0 = 2 voxels: 1 simulation length = 2 / sqrt 3 mm. The energy unit
    // makes a modulus of 0.5 (energy / length^3) be 5 kPa; a particle weighs 5.66 mg.
    const double lengthMm = 2 / std::sqrt(3.0);
    const UnitSystem u = UnitSystem::fromModulus(lengthMm, 5.66e-6, 5e3, 0.5);
    REQUIRE(u.physical);
    CHECK(u.toMm(3.0) == Approx(3 * lengthMm));
    CHECK(u.fromMm(u.toMm(3.0)) == Approx(3.0));
    CHECK(u.fromN(u.toN(2.5)) == Approx(2.5));
    CHECK(u.fromS(u.toS(0.02)) == Approx(0.02));
    CHECK(u.fromKpa(u.toKpa(0.7)) == Approx(0.7));
    // The modulus it was made from reads back in kPa.
    CHECK(u.toKpa(0.5) == Approx(5.0));
    // Derived units against their definitions, in SI: F = m L / T^2, E = F L, P = F / L^2.
    const double l = lengthMm * 1e-3;
    CHECK(u.forceN() == Approx(u.massKg * l / (u.timeS * u.timeS)));
    CHECK(u.energyJ() == Approx(u.forceN() * l));
    CHECK(u.pressurePa() == Approx(u.forceN() / (l * l)));
    CHECK(u.stiffnessNPerMm() == Approx(u.forceN() / lengthMm));
    // Time from mass, length and energy: T = sqrt(m L^2 / E), the energy being 5e3 Pa * L^3 / 0.5.
    CHECK(u.timeS == Approx(std::sqrt(5.66e-6 * l * l / (5e3 * l * l * l / 0.5))));
}

TEST_CASE("a stiffer material is a faster clock: time scales as 1/sqrt(E), force as E", "[common][units]") {
    const UnitSystem soft = UnitSystem::fromModulus(1.0, 1e-6, 1e3, 1.0);
    const UnitSystem stiff = UnitSystem::fromModulus(1.0, 1e-6, 1e5, 1.0);
    CHECK(soft.timeS / stiff.timeS == Approx(10.0));
    CHECK(stiff.forceN() / soft.forceN() == Approx(100.0));
    // Mass scaling by 100 slows the clock tenfold and leaves forces (the statics) as they are.
    const UnitSystem scaled = UnitSystem::fromModulus(1.0, 1e-4, 1e3, 1.0);
    CHECK(scaled.timeS / soft.timeS == Approx(10.0));
    CHECK(scaled.forceN() == Approx(soft.forceN()));
}

TEST_CASE("a scene without materials knows its lengths only", "[common][units]") {
    UnitSystem u;
    CHECK_FALSE(u.lengthKnown());
    CHECK_FALSE(u.physical);
    u.lengthMm = 1.5;
    CHECK(u.lengthKnown());
}
