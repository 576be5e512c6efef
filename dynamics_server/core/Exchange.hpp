#pragma once
// What a step needs from the other processes of a run (Simulation.hpp): the same calls in the same
// order on every process. This base class is the run of one process, where there are none: the
// region is the whole box, every particle is here, no ghosts, and a gather returns what it was
// given. parallel/MpiExchange.hpp plugs in the ranks of a decomposed run (halo plan, migration,
// balancing, reductions) behind the same calls.
#include "Command.hpp"
#include "ForceField.hpp"
#include "Model.hpp"
#include "Particles.hpp"
#include "Records.hpp"

#include <array>
#include <cstddef>
#include <vector>

namespace bop::core {

// What a refresh did (Exchange::refresh...): the ghosts moved along their plan (Kept); a new
// halo, so a new neighbour list (Rebuilt); new cut planes too, so a new region and its map
// windows (Moved).
enum class RegionChange { Kept, Rebuilt, Moved };

class Exchange {
public:
    virtual ~Exchange() = default;

    // ---- the policy of a step: when particles migrate, cut planes move and halos are built ----
    // (Exchange.cpp, the one place that decides; the calls below are its pieces). Collective.
    // A rebuild moves the cut planes when the busiest process holds more than this over the mean.
    static constexpr double kRebalanceAbove = 1.1;
    // At the start: cut planes for similar counts, and the halo.
    RegionChange start(Particles& p, Halo& halo, double range);
    // After a drift (`listHolds`: this process's neighbour list still holds): where every
    // process's holds, the ghosts' positions along the plan; otherwise every particle to its
    // owner, then new cut planes or a new halo.
    RegionChange afterDrift(Particles& p, Halo& halo, double range, bool listHolds);
    // After particles were born, died or moved on some process: new cut planes or a new halo.
    RegionChange afterChange(Particles& p, Halo& halo, double range);
    // Before construction's check: every particle to its owner and the ghosts out to `range`
    // (the birth front). Whether they may have moved (never for one process, which wraps them
    // into the box at every drift).
    bool widen(Particles& p, Halo& halo, double range);
    // Particles in the neighbour list's cell order (SpatialOrder.hpp, cells of at least `cell`
    // length units over `box`): sorted at start() and, once `everySteps` drifts have passed since
    // the last sort, at the next rebuild (after migration, before the halo's plan). everySteps 0:
    // never sorted. A sort moves particles only between indices: the neighbour list orders its
    // entries by id within a cell, so a step's forces do not depend on it (docs/dynamics.md,
    // "Particle order").
    void sortParticles(const Box& box, double cell, long long everySteps) {
        sortBox_ = box;
        sortCell_ = cell;
        sortEvery_ = everySteps;
    }

    virtual int rank() const { return 0; }
    virtual int size() const { return 1; }

    // ---- agreement and reductions (collective) ----
    // Rank 0's commands on every process.
    virtual void broadcast(std::vector<Command>&) {}
    virtual bool allTrue(bool mine) { return mine; }
    // Every process's records concatenated in rank order (the same on every process): sums over
    // them in that order are the same everywhere, and at every rank count for whole numbers.
    // allGather: as many records on every process; allGatherV: any number.
    template <class R>
    std::vector<R> allGather(const std::vector<R>& mine) {
        return recordsOf<R>(allGatherBytes(recordBytes(mine)));
    }
    template <class R>
    std::vector<R> allGatherV(const std::vector<R>& mine) {
        return recordsOf<R>(allGatherVBytes(recordBytes(mine)));
    }
    // Every process's records in rank order on rank 0 only (empty elsewhere).
    template <class R>
    std::vector<R> gatherV(const std::vector<R>& mine) {
        return recordsOf<R>(gatherVBytes(recordBytes(mine)));
    }
    // Rank 0's records on every process.
    template <class R>
    void broadcastRecords(std::vector<R>& records) {
        std::vector<std::byte> b = recordBytes(records);
        broadcastBytes(b);
        records = recordsOf<R>(b);
    }

    // ---- the region of this process ----
    // This process's part of the whole box (the whole box here).
    virtual Box region(const Box& whole) const { return whole; }
    bool owns(const Eigen::Vector3d& x) const { return size() == 1 || ownsPosition(x); }
    // Most particles on one process over the mean (collective).
    virtual double imbalance(std::size_t /*mine*/) { return 1.0; }
    // Whether the processes split the box along this axis (none does here).
    virtual bool splitsAxis(int /*axis*/) const { return false; }

    // ---- particles and ghosts (collective) ----
    // One process wraps positions into the periodic box every drift; ranks wrap when they
    // migrate, so that their ghosts' positions stay continuous between rebuilds.
    virtual bool wrapsEveryDrift() const { return true; }
    // Every particle to the process that owns its position, periodic axes wrapped.
    virtual void migrate(Particles&) {}
    // New cut planes for similar counts, the particles moved to their owners; false when the
    // region did not move (here: never).
    virtual bool rebalance(Particles&) { return false; }
    // Copies of the other processes' particles within `range` of this region (a new plan), and
    // their positions and normals again along the same plan. Periodic images on axes a process
    // spans whole are the core's (the cell list's), never ghosts.
    virtual void buildHalo(const Particles&, double /*range*/, Halo& halo) { halo = Halo{}; }
    virtual void updateHalo(const Particles&, Halo&) {}
    virtual bool hasGhosts() const { return false; }
    // One value per particle here to the ghosts that are its copies elsewhere, along the halo's
    // plan: `ghosts` gets one per ghost, in halo order. Collective.
    virtual void shareGhostValues(const std::vector<double>& /*mine*/, std::vector<double>& ghosts) { ghosts.clear(); }

    // ---- what the exchange did (this process's share; nothing for one process) ----
    struct Counts {
        std::size_t haloBytesPerStep = 0;  // bytes this process sent for the halo in the last exchange
        std::size_t migrations = 0;        // particles this process sent away
        std::size_t rebalances = 0;        // times the cut planes moved
        double initialImbalance = 1;       // with uniform cuts, before the first balancing
    };
    virtual Counts counts() const { return {}; }
    // Processes along each axis of the box.
    virtual std::array<int, 3> grid() const { return {1, 1, 1}; }

protected:
    virtual bool ownsPosition(const Eigen::Vector3d&) const { return true; }
    // The records' bytes, concatenated in rank order (the same size on every process, or any).
    virtual std::vector<std::byte> allGatherBytes(const std::vector<std::byte>& mine) { return mine; }
    virtual std::vector<std::byte> allGatherVBytes(const std::vector<std::byte>& mine) { return mine; }
    virtual std::vector<std::byte> gatherVBytes(const std::vector<std::byte>& mine) { return mine; }
    virtual void broadcastBytes(std::vector<std::byte>&) {}

private:
    RegionChange rebuild(Particles& p, Halo& halo, double range, bool balance, bool sortNow);
    void sortIfDue(Particles& p, bool now);

    Box sortBox_;
    double sortCell_ = 1;
    long long sortEvery_ = 0, driftsSinceSort_ = 0;
};

}  // namespace bop::core
