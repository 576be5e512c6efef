#pragma once
// Verlet neighbour list built from cell lists (paper §4.5 and its expected "double frame rate"):
// every pair closer than cutoff + skin is stored once (half list, Newton's third law), and the
// list is reused until some particle has moved more than skin / 2 since it was built.
//
// The list works on entries: the particles themselves, sorted by cell for memory locality, and
// on periodic axes their ghost images within cutoff + skin of the opposite face. A pair across
// a periodic face is stored once, between the particle with the smaller index and the ghost of
// the other, so the pair loop needs no minimum image and no shifts; forces on ghosts are folded
// back into their owners. The same entries will carry the halo of an MPI subdomain.
//
// Entry positions are unwrapped from the moment of the build: a particle that crosses a
// periodic face keeps a continuous entry position, so every stored pair stays valid.
#include "Model.hpp"

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace bop::core {

class NeighbourList {
public:
    // range: cutoff + skin, simulation length units. Periodic axes need a side of at least
    // 2 * range (std::invalid_argument otherwise).
    void build(const Box& box, double range, const std::vector<Eigen::Vector3d>& pos);

    // Moves the entries with the particles. Returns false (entries untouched) when the particle
    // count differs from the build or a particle moved farther than maxMove since the build:
    // then build again.
    bool update(const Box& box, const std::vector<Eigen::Vector3d>& pos, double maxMove);

    std::size_t entryCount() const { return owner_.size(); }
    std::size_t ghostCount() const { return owner_.size() - particles_; }
    std::size_t pairCount() const { return nbr_.size(); }
    std::size_t builds() const { return builds_; }
    double range() const { return range_; }

    const std::vector<std::uint32_t>& owner() const { return owner_; }      // particle of each entry
    const std::vector<Eigen::Vector3d>& positions() const { return pos_; }  // current entry positions
    // Neighbours of entry e: neighbours()[first(e) .. first(e + 1)), entry indices.
    std::uint32_t first(std::size_t e) const { return start_[e]; }
    const std::uint32_t* neighbours() const { return nbr_.data(); }

private:
    double range_ = 0;
    std::size_t particles_ = 0, builds_ = 0;
    std::vector<std::uint32_t> owner_, start_, nbr_;
    std::vector<Eigen::Vector3d> pos_, ref_;      // entry positions now and at the build
    std::vector<Eigen::Vector3d> built_;          // particle positions at the build
    std::vector<Eigen::Vector3d> move_;           // per particle, displacement since the build
};

}  // namespace bop::core
