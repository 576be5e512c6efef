#pragma once
// The cluster-pair layout's LJ loop in the form the dynamics core would run it (ClusterLjLoop.hpp)
// against the core's own LJ loop over the rows of the same pruned list, in double and in mixed
// precision, on the same positions, one core: what issue 53's rule asks of a layout once built.
#include "core/Model.hpp"
#include "core/Params.hpp"
#include "core/Particles.hpp"

namespace bop::tools {

struct ClusterFormResult {
    std::size_t clusterPairs = 0;  // cluster pairs listed (16 entry pairs each)
    std::size_t inRange = 0;       // entry pairs within the cutoff (each once)
    // Best of the timed passes, ns per pair in range: the cluster loop, the rows in double, in mixed.
    double clusterNs = 0, rowsDoubleNs = 0, rowsMixedNs = 0;
    // The cluster loop against the rows in double: |dF| / |F| over every entry together, and the
    // relative differences of the virial and of the energy; whether the counts in range agree.
    double forceDifference = 0, virialDifference = 0, energyDifference = 0;
    bool sameCount = false;
};

// The particles' LJ pairs in `box` (the model's species and the params' weights), listed as the
// core lists them (cutoff + skin, pruned to cutoff + 0.05 r0), each loop timed `repeats` times.
ClusterFormResult measureClusterForm(const core::Model& model, const core::Params& params,
                                     const core::Particles& particles, const core::Box& box, int repeats);

}  // namespace bop::tools
