#pragma once
// The LJ pair loop: LJ forces over the short neighbour list (every pair within the LJ cutoff
// plus skin), the hot loop of bulk material and of a bag's volume, with the species weights
// looked up per pair only when they differ between species pairs. Its forces are LjForm's
// forceOverR() whether or not energies are asked for, so a trajectory does not depend on the
// steps that report. (Measured on this project's machine: two pairs at a time in SSE2 registers
// and batches that vectorise f(r)/r were no faster; nor were four pairs at a time in AVX lanes
// with the oriented loop's blocks (PairBlocks.hpp), 12-16 ns per pair in range before, 16-24
// after on the torus: the loop is bound by loads and stores, not by its arithmetic.)
#include "NeighbourList.hpp"
#include "PairKernel.hpp"

namespace bop::core {

// What a pair loop reads, per neighbour-list entry (e, species) and per species number
// (isVolume), and where it adds forces: f[k - base] for entry k (a chunk's buffer starts at its
// first row; torques t of the oriented loop alike). `mixed`: both loops' pair arithmetic in
// single precision (docs/dynamics.md, "Mixed precision").
struct PairInputs {
    const Eigen::Vector3d* e;
    const std::uint8_t* species;
    const char* isVolume;
    Eigen::Vector3d* f;
    std::size_t base = 0;
    bool mixed = false;
};

// Adds the LJ forces of rows [x0, x1) of `pairs` to in.f and their virial, count and (with
// `energies`) energy to sums. With in.mixed, the list's entries in blocks across rows
// (PairBlocks.hpp), sixteen at a time: the differences of the double positions, r^2 and r0^2 - r^2
// worked out in double and rounded to float, f(r)/r, the forces and the virial in float lanes,
// each added to the double sums (forces, virial) in list order; energies in double from the
// double differences (only on the steps that ask: the forces are the same on every step).
void ljForcePairs(const PairKernel& kernel, const NeighbourList::Pairs& pairs, const PairInputs& in, bool energies,
                  std::size_t x0, std::size_t x1, PairKernel::Sums& sums);

}  // namespace bop::core
