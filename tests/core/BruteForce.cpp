#include "BruteForce.hpp"

#include <algorithm>

namespace bop::test {

BruteForceComparison compareWithBruteForce(const core::Model& m, const core::Params& params, core::ForceField& field,
                                           core::Particles& p, bool energies) {
    BruteForceComparison c;
    field.compute(m, core::wholeMapOf(m), core::ProbeState{}, p, c.field, nullptr, energies);
    core::Particles q = p;
    for (std::size_t i = 0; i < q.size(); ++i) {
        q.force[i].setZero();
        q.torque[i].setZero();
    }
    core::PairForces::bruteForce(m, params, q, c.brute);
    for (std::size_t i = 0; i < p.size(); ++i) {
        c.maxForce = std::max(c.maxForce, q.force[i].norm());
        c.forceError = std::max(c.forceError, (p.force[i] - q.force[i]).norm());
        c.torqueError = std::max(c.torqueError, (p.torque[i] - q.torque[i]).norm());
    }
    return c;
}

}  // namespace bop::test
