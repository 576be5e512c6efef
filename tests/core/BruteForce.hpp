#pragma once
// The step's forces of a ForceField against PairForces::bruteForce (O(N^2), pair by
// pair): both runs' stats and the largest differences, for the pair-loop tests.
#include "core/ForceField.hpp"

namespace bop::test {

struct BruteForceComparison {
    core::ForceStats field, brute;           // stats of ForceField::compute and of the reference
    double maxForce = 0;                     // the largest reference force
    double forceError = 0, torqueError = 0;  // the largest |difference| over particles
};

// Computes p's forces with `field` (energies on), and the reference's on a copy, with `params`'
// weights (the field's).
BruteForceComparison compareWithBruteForce(const core::Model& m, const core::Params& params, core::ForceField& field,
                                           core::Particles& p, bool energies = true);

}  // namespace bop::test
