#pragma once
// The pair loop of models without oriented weights on steps that report no energy: LJ forces
// alone over the neighbour list, the hot loop of bulk material, with the species weights looked
// up per pair only when there is more than one species. The forces equal PairKernel::applyLj's
// to rounding. (Measured on this project's machine: two pairs at a time in SSE2 registers and
// batches that vectorise f(r)/r were no faster; the loop is bound by loads and stores.)
#include "NeighbourList.hpp"
#include "PairKernel.hpp"

namespace bop::core {

// Adds the forces of the pairs to f (one per neighbour-list entry) and their virial and count
// to sums. e, species: per entry; isVolume: per species number.
void ljForcePairs(const PairKernel& kernel, const NeighbourList::Pairs& pairs, const Eigen::Vector3d* e,
                  const std::uint8_t* species, const char* isVolume, Eigen::Vector3d* f, PairKernel::Sums& sums);

}  // namespace bop::core
