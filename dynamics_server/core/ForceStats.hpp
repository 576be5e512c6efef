#pragma once
// What a force evaluation reports: energies, virials, the probe's reaction and pair counts
// (ForceStats), and where its time went (PhaseTimes).
#include <Eigen/Core>

#include <cstddef>

namespace bop::core {

struct ForceStats {
    double pairEnergy = 0;    // LJ + co-normal + co-planar energy (weights symmetrised) + bonds, energy units
    double probeEnergy = 0;   // energy of the probe's interaction with the particles
    double virial = 0;        // sum over pairs of r_ij . F_j (conservative pair forces), energy
    double virialVolume = 0;  // the same over pairs of two volume particles only
    // sum over volume particles of (x - map centre) . F^GM: the gradient map's wall virial on
    // the blood, -3PV for a gas the map alone contains (energy)
    double wallVirial = 0;
    Eigen::Vector3d probeReaction = Eigen::Vector3d::Zero();  // force of the particles on the probe
    std::size_t pairsInRange = 0;                             // pairs within the LJ cutoff
    std::size_t orientedPairsInRange = 0;                     // pairs with oriented weights within their cutoff
};

struct PhaseTimes {
    double neighbours = 0, pairs = 0, gradientMap = 0, probe = 0;  // seconds, accumulated
    // The two pair loops' time summed over threads (CPU seconds) and the pairs in range they
    // handled, accumulated: ns per pair of each kind.
    double ljLoopSeconds = 0, orientedLoopSeconds = 0;
    double ljPairs = 0, orientedPairs = 0;
};

}  // namespace bop::core
