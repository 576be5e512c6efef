#pragma once
// The pressure of the blood (the volume particles) in a bag, paper §5.2 eqs. 13–15 with
// docs/physics.md §6: the kinetic sum and the virial of pairs of two volume particles (the bag's
// surface particles and the gradient map are the container wall, whose virial is -3PV and is
// not added). V is the volume of the volume voxels of the map in force.
#include "Model.hpp"
#include "Particles.hpp"

namespace bop::core {

struct BloodSums {
    double mv2 = 0;    // sum of m v^2 over volume-species particles (twice their kinetic energy), energy
    double count = 0;  // volume-species particles
};
BloodSums bloodSums(const Model& model, const Particles& p);

// Standard virial pressure P = (sum m v^2 + W) / (3V), energy / length^3 (docs/physics.md §6.1).
inline double virialPressure(double mv2, double virial, double volume) {
    return volume > 0 ? (mv2 + virial) / (3 * volume) : 0.0;
}
// The paper's eq. 15 as printed: (sum v^2 + W / N) / (3V), kept for comparison with Figure 12.
inline double paperEq15Pressure(double mv2, double virial, double count, double volume) {
    return volume > 0 && count > 0 ? (mv2 + virial / count) / (3 * volume) : 0.0;
}

}  // namespace bop::core
