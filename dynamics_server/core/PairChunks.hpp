#pragma once
// The pair loops of a step on the threads, with results that do not depend on how many there
// are. The neighbour list's rows are cut into chunks of about equal work, fixed by the list
// alone (not by the thread count). Each chunk adds its pairs' forces and torques into its own
// buffer, which covers its rows and the entries they reach (a pair's second entry always comes
// after its row, so a buffer runs from the chunk's first row to the farthest entry it touches).
// The buffers are then summed entry by entry, in chunk order, and the chunks' energies and
// virials likewise: the same bits at 1, 2 or 16 threads.
#include "LjPairLoop.hpp"
#include "OrientedPairLoop.hpp"
#include "PrunedPairs.hpp"

#include <cstdint>
#include <vector>

namespace bop::core {

// Where PairChunks::run may add each entry's force and torque: force[owner[e]], torque[owner[e]].
// Only where every entry is its particle's one entry (a list without images or ghosts), so that
// no two entries add to one particle.
struct ParticleTargets {
    Eigen::Vector3d* force = nullptr;
    Eigen::Vector3d* torque = nullptr;  // when oriented
    const std::uint32_t* owner = nullptr;
};

class PairChunks {
public:
    // Cuts the rows of `list` (after each build); `oriented`: its wide pairs are used too.
    void plan(const NeighbourList& list, bool oriented);

    // Every loop of the step over every chunk: LJ pairs, oriented pairs (if planned so), and
    // each one's halo pairs when `halo`, from `sets` (the planned list's pairs or a pruned copy
    // of them: the same rows, so the same chunks). Writes f (and t when oriented) for every entry, and the
    // sums of the pairs within the subdomain and of those with halo ghosts; adds the LJ and the
    // oriented loops' time, summed over threads, to seconds[0] and seconds[1].
    // With `into` set, each entry's force (and torque) is added to its particle's (ParticleTargets)
    // instead of written to f (and t).
    void run(const PairKernel& kernel, const PrunedPairs::Sets& sets, PairInputs in, OrientedInputs o, bool energies,
             bool halo, PairKernel::Sums& sums, PairKernel::Sums& haloSums, double seconds[2],
             ParticleTargets into = {});

    std::size_t count() const { return chunks_.size(); }

private:
    struct Chunk {
        std::uint32_t x0 = 0, x1 = 0;  // its rows
        std::uint32_t hi = 0;          // one past the last entry it touches
        std::size_t offset = 0;        // its buffer in bf_ / bt_
        std::uint32_t firstCover = 0;  // the first chunk whose buffer may reach x0
    };
    // Cuts the rows into `count` chunks of about total / count work each; their buffers' length.
    template <typename Work>
    std::size_t cut(const NeighbourList& list, std::size_t count, double total, const Work& work);

    std::vector<Chunk> chunks_;
    bool oriented_ = false;
    std::vector<Eigen::Vector3d> bf_, bt_;
    std::vector<PairKernel::Sums> sums_, haloSums_;
    std::vector<double> ljSeconds_, orientedSeconds_;  // per chunk, the last run
};

}  // namespace bop::core
