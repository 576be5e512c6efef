#pragma once
// The physical units of a scene (docs/physics.md §0): how many millimetres, kilograms and seconds
// one simulation unit of length, mass and time is. Force, energy and pressure follow from them.
// A scene without a material knows its lengths only (`physical` false): its mass, time and force
// stay simulation units and are reported as such.
#include <cmath>

namespace bop {

struct UnitSystem {
    double lengthMm = 0.0;  // mm per simulation length unit; 0: not known (bulk material)
    double massKg = 1.0;    // kg per simulation mass unit (one particle's mass)
    double timeS = 1.0;     // s per simulation time unit
    bool physical = false;  // mass, time and force are physical (a scene with materials)

    bool lengthKnown() const { return lengthMm > 0; }
    double lengthM() const { return lengthMm * 1e-3; }
    double forceN() const { return massKg * lengthM() / (timeS * timeS); }    // N per simulation force unit
    double energyJ() const { return forceN() * lengthM(); }                   // J per simulation energy unit
    double pressurePa() const { return forceN() / (lengthM() * lengthM()); }  // Pa per energy / length^3
    double stiffnessNPerMm() const { return forceN() / lengthMm; }            // N/mm per force / length

    double toMm(double length) const { return length * lengthMm; }
    double fromMm(double mm) const { return mm / lengthMm; }
    double toS(double time) const { return time * timeS; }
    double fromS(double s) const { return s / timeS; }
    double toN(double force) const { return force * forceN(); }
    double fromN(double n) const { return n / forceN(); }
    double toKpa(double pressure) const { return pressure * pressurePa() * 1e-3; }
    double fromKpa(double kpa) const { return kpa * 1e3 / pressurePa(); }

    // From a length scale, a mass per particle and a stiffness: the energy unit is the one in which
    // a modulus of `modulusSim` (energy / length^3) is `modulusPa`, and time follows as
    // sqrt(mass length^2 / energy).
    static UnitSystem fromModulus(double lengthMm, double massKg, double modulusPa, double modulusSim);
};

inline UnitSystem UnitSystem::fromModulus(double lengthMm, double massKg, double modulusPa, double modulusSim) {
    UnitSystem u;
    u.lengthMm = lengthMm;
    u.massKg = massKg;
    u.physical = true;
    const double l = u.lengthM();
    const double energyJ = modulusPa * l * l * l / modulusSim;
    u.timeS = std::sqrt(massKg * l * l / energyJ);
    return u;
}

}  // namespace bop
