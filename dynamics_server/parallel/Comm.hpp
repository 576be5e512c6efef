#pragma once
// The project's one door to MPI: a duplicated communicator with a Cartesian rank grid, and
// checked wrappers for the few calls the decomposed run makes. Every MPI return code is
// checked; a failure throws std::runtime_error naming the call and MPI's error string.
#include "Decomposition.hpp"
#include "Session.hpp"
#include "core/Records.hpp"

#include <mpi.h>

#include <cstddef>
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

    // Records (core/Records.hpp) travel as their bytes; every call below is collective except
    // sendRecv.
    // Exchanges a buffer with `to` while receiving one from `from` (sizes first).
    template <class T>
    void sendRecv(const std::vector<T>& out, int to, std::vector<T>& in, int from, int tag) const {
        static_assert(core::kIsRecord<T>);
        in.resize(exchangeCounts(out.size(), to, from, tag));
        sendRecvBytes(out.data(), out.size() * sizeof(T), to, in.data(), in.size() * sizeof(T), from, tag + 1);
    }
    // Every rank's records, concatenated in rank order (the same on every rank): as many on each
    // (allGather), any number (allGatherV), on rank 0 only (gatherV; empty elsewhere).
    template <class T>
    std::vector<T> allGather(const std::vector<T>& mine) const {
        return core::recordsOf<T>(allGatherBytes(core::recordBytes(mine)));
    }
    template <class T>
    std::vector<T> allGatherV(const std::vector<T>& mine) const {
        return core::recordsOf<T>(gatherVBytes(core::recordBytes(mine), true));
    }
    template <class T>
    std::vector<T> gatherV(const std::vector<T>& mine) const {
        return core::recordsOf<T>(gatherVBytes(core::recordBytes(mine), false));
    }
    bool allTrue(bool mine) const;
    // Rank 0's records on every rank (sizes first).
    template <class T>
    void broadcast(std::vector<T>& data) const {
        std::vector<std::byte> b = core::recordBytes(data);
        broadcastBytes(b);
        data = core::recordsOf<T>(b);
    }

    std::vector<std::byte> allGatherBytes(const std::vector<std::byte>& mine) const;
    // Every rank's bytes in rank order: on every rank (all), or on rank 0 only.
    std::vector<std::byte> gatherVBytes(const std::vector<std::byte>& mine, bool all) const;
    void broadcastBytes(std::vector<std::byte>& data) const;

private:
    // The record counts of a sendRecv (`out` sent to `to`; what comes from `from`).
    std::size_t exchangeCounts(std::size_t out, int to, int from, int tag) const;
    void sendRecvBytes(const void* out, std::size_t outBytes, int to, void* in, std::size_t inBytes, int from,
                       int tag) const;
    MPI_Comm dup_ = MPI_COMM_NULL, cart_ = MPI_COMM_NULL;
    int rank_ = 0, size_ = 1;
    Coords dims_{1, 1, 1}, coords_{0, 0, 0};
    std::array<int, 3> lower_{}, upper_{};
};

}  // namespace bop::parallel
