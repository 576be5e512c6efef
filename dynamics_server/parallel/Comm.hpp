#pragma once
// The project's one door to MPI: a duplicated communicator with a Cartesian rank grid, and
// checked wrappers for the few calls the decomposed run makes. Every MPI return code is
// checked; a failure throws std::runtime_error naming the call and MPI's error string.
#include "Decomposition.hpp"
#include "Session.hpp"

#include <mpi.h>

#include <string>
#include <vector>

namespace bop::parallel {

// Throws std::runtime_error("MPI <what>: <error string>") unless rc == MPI_SUCCESS.
void check(int rc, const char* what);

class CartComm {
public:
    // Duplicates `base`, picks a rank grid for its size over the box (MPI_Dims_create, any rank
    // count including primes) and creates the Cartesian communicator, periodic per box axis.
    CartComm(MPI_Comm base, const core::Box& box);
    ~CartComm();
    CartComm(const CartComm&) = delete;
    CartComm& operator=(const CartComm&) = delete;

    MPI_Comm comm() const { return cart_; }
    int rank() const { return rank_; }
    int size() const { return size_; }
    const Coords& dims() const { return dims_; }
    const Coords& coords() const { return coords_; }
    // Neighbour ranks along an axis (MPI_PROC_NULL past a non-periodic face).
    int lower(int axis) const { return lower_[std::size_t(axis)]; }
    int upper(int axis) const { return upper_[std::size_t(axis)]; }

    // Exchanges a buffer with `to` while receiving one from `from` (sizes first).
    void sendRecv(const std::vector<double>& out, int to, std::vector<double>& in, int from, int tag) const;
    // Every rank's values, concatenated in rank order (the same on every rank).
    std::vector<double> allGather(const std::vector<double>& mine) const;
    // The same for buffers of any length per rank.
    std::vector<double> allGatherV(const std::vector<double>& mine) const;
    // Every rank's floats, concatenated in rank order, on rank 0 only (empty elsewhere).
    std::vector<float> gatherV(const std::vector<float>& mine) const;
    bool allTrue(bool mine) const;
    // Rank 0's buffer on every rank (sizes first).
    void broadcast(std::vector<double>& data) const;

private:
    MPI_Comm dup_ = MPI_COMM_NULL, cart_ = MPI_COMM_NULL;
    int rank_ = 0, size_ = 1;
    Coords dims_{1, 1, 1}, coords_{0, 0, 0};
    std::array<int, 3> lower_{}, upper_{};
};

}  // namespace bop::parallel
