#pragma once
// The LJ loop of mixed precision over cluster pairs (ClusterPairs.hpp), in the form the dynamics
// core would run it: for each pair of clusters, the sixteen entry pairs at once, with no gathers
// and no index per pair. The differences of the double positions, r^2 and r0^2 - r^2 (3 - r^2) in
// double lanes (eight at a time), rounded to float; f(r)/r in sixteen float lanes, as the rows'
// mixed loop (core/LjPairLoop.hpp) computes it; then back in double, times the double
// differences: each pair's force and virial in double, added to double sums. The cutoff test is
// in double and keeps only the lanes the list holds: the same pairs as the rows, counted once.
// Energies in double from the double r^2, when asked.
//
// Each row of clusters runs in two passes over blocks of its cluster pairs: f(r)/r and the virial
// first, the forces then, from the differences again: shorter chains of dependent operations per
// iteration. What each step of its making gave: docs/dynamics.md, "A cluster-pair layout, built
// and measured".
#include "ClusterPairs.hpp"
#include "core/PairKernel.hpp"

namespace bop::tools {

// Adds the LJ forces of the pairs of clusters [c0, c1) of `clusters` into f, 12 doubles per
// cluster (x of its four entries, then y, then z), and their virial, its volume part (the volume
// flags given to ClusterPairs::build), count and (with `energies`) energy into sums. species: per
// entry (the list's). Positions from clusters.pos (setPositions).
void ljClusterPairs(const core::PairKernel& kernel, const ClusterPairs& clusters, const std::uint8_t* species,
                    double* f, bool energies, std::size_t c0, std::size_t c1, core::PairKernel::Sums& sums);

}  // namespace bop::tools
