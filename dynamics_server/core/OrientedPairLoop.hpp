#pragma once
// The oriented pair loop: co-normal and co-planar forces and torques (docs/physics.md §1.2) over
// the wide neighbour list, which holds only surface particles with oriented weights, within the
// oriented cutoff plus skin. The LJ part of those pairs is the LJ loop's. Four entries at a
// time (PairBlocks.hpp, V4 lanes of SimdMath.hpp): per pair one exponential (simdExp, within a
// few ulp of std::exp) and one square root, the taper branch-free (t clamps to 0 below its
// start), entries beyond the cutoff masked out. Forces and torques equal PairKernel::apply's
// oriented part to rounding (tests/core/TestBagKernel.cpp).
#include "LjPairLoop.hpp"

namespace bop::core {

// The oriented loop's further inputs per entry: normals and co-planar curvature weights (1
// without a map), and where torques go (t[k - base], base PairInputs's).
struct OrientedInputs {
    const Eigen::Vector3d* normal;
    const float* curvature;
    Eigen::Vector3d* t;
};

// Adds the oriented forces and torques of rows [x0, x1) of `pairs` to in.f and o.t, and their
// virial, count and (with `energies`) energy to sums.
void orientedPairs(const PairKernel& kernel, const NeighbourList::Pairs& pairs, const PairInputs& in,
                   const OrientedInputs& o, bool energies, std::size_t x0, std::size_t x1, PairKernel::Sums& sums);
// The same in float lanes (in.mixed; OrientedPairLoopMixed.cpp), sums in double. orientedPairs
// calls it when in.mixed is set.
void orientedPairsMixed(const PairKernel& kernel, const NeighbourList::Pairs& pairs, const PairInputs& in,
                        const OrientedInputs& o, bool energies, std::size_t x0, std::size_t x1, PairKernel::Sums& sums);

}  // namespace bop::core
