#pragma once
// The ranks of a decomposed run behind core::Exchange (core/Simulation.hpp steps with it): the
// subdomain of this rank, migration of particles to the rank that owns their position, the halo
// plan and its refresh, balancing of the cut planes, and reductions in rank order.
//
// Halo: staged along the split axes, x then y then z; each stage also forwards the ghosts that
// earlier stages brought, so edges and corners arrive without extra messages. Axes with one rank
// need no messages: the core makes the periodic images itself. The plan (which particles go where)
// is kept until the next rebuild; refreshes send positions and normals along it.
//
// Migration: one hop per split axis per pass, passes until every particle is home (moved planes,
// or a particle faster than half the skin per step, can put one several subdomains away).
//
// Balance: the cut planes move to the particle-count quantiles at start-up and whenever a rebuild
// finds the most loaded rank more than 10% above the mean (core/Simulation.cpp decides).
//
// Every message is one of the typed records of MpiMessages.hpp, with its plan's tag.
#include "Comm.hpp"
#include "Decomposition.hpp"
#include "MpiMessages.hpp"
#include "core/Exchange.hpp"

#include <vector>

namespace bop::parallel {

class MpiExchange : public core::Exchange {
public:
    // reach: the widest halo the run needs (core::haloReach), the narrowest subdomain.
    MpiExchange(const CartComm& comm, const core::Box& box, double reach);

    int rank() const override { return comm_.rank(); }
    int size() const override { return comm_.size(); }
    void broadcast(std::vector<core::Command>& commands) override;
    bool allTrue(bool mine) override { return comm_.allTrue(mine); }

    core::Box region(const core::Box&) const override { return dec_.subdomain(comm_.coords()); }
    double imbalance(std::size_t mine) override;
    bool splitsAxis(int axis) const override { return comm_.dims()[std::size_t(axis)] > 1; }

    bool wrapsEveryDrift() const override { return false; }
    void migrate(core::Particles& p) override;
    bool rebalance(core::Particles& p) override;
    void buildHalo(const core::Particles& p, double range, core::Halo& halo) override;
    void updateHalo(const core::Particles& p, core::Halo& halo) override;
    bool hasGhosts() const override { return comm_.size() > 1; }
    void shareGhostValues(const std::vector<double>& mine, std::vector<double>& ghosts) override;

    Counts counts() const override { return {haloBytes_, migrations_, rebalances_, initialImbalance_}; }
    std::array<int, 3> grid() const override { return comm_.dims(); }
    const Decomposition& decomposition() const { return dec_; }
    const CartComm& comm() const { return comm_; }

protected:
    bool ownsPosition(const Eigen::Vector3d& x) const override { return dec_.owner(x) == comm_.coords(); }
    std::vector<std::byte> allGatherBytes(const std::vector<std::byte>& mine) override {
        return comm_.allGatherBytes(mine);
    }
    std::vector<std::byte> allGatherVBytes(const std::vector<std::byte>& mine) override {
        return comm_.gatherVBytes(mine, true);
    }
    std::vector<std::byte> gatherVBytes(const std::vector<std::byte>& mine) override {
        return comm_.gatherVBytes(mine, false);
    }
    void broadcastBytes(std::vector<std::byte>& b) override { comm_.broadcastBytes(b); }

private:
    struct Stage {
        int axis = 0;
        std::vector<std::uint32_t> toLower, toUpper;  // sources: particle i, or particles + halo index
        Eigen::Vector3d lowerShift = Eigen::Vector3d::Zero(), upperShift = Eigen::Vector3d::Zero();
        std::size_t fromUpperAt = 0, fromUpperCount = 0, fromLowerAt = 0, fromLowerCount = 0;  // halo ranges
    };
    void wrapAndMigrate(core::Particles& p);  // one hop along each split axis

    const CartComm& comm_;
    core::Box box_;  // the whole box
    Decomposition dec_;
    std::vector<Stage> stages_;
    std::size_t particlesAtBuild_ = 0;          // the sources' numbering of the plan
    std::vector<GhostRefresh> out_[2], in_[2];  // message buffers, kept to avoid fresh pages every step
    std::size_t haloBytes_ = 0, migrations_ = 0, rebalances_ = 0;
    double initialImbalance_ = -1;  // the first imbalance() asked (start-up, uniform cuts)
};

}  // namespace bop::parallel
