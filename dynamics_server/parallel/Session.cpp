#include "Session.hpp"

#include "Comm.hpp"
#include "core/Threads.hpp"

#include <algorithm>
#include <cstdlib>
#include <thread>

namespace bop::parallel {

MpiSession::MpiSession(int& argc, char**& argv) {
    check(MPI_Init(&argc, &argv), "MPI_Init");
    check(MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
    // Threads per rank: OMP_NUM_THREADS if set, else the machine's cores shared among its ranks
    // (OpenMP alone would give every rank all of them).
    if (!std::getenv("OMP_NUM_THREADS"))
        core::setThreadCount(std::max(1, int(std::thread::hardware_concurrency()) / ranksOnThisNode()));
}

MpiSession::~MpiSession() {
    MPI_Finalize();
}

int MpiSession::worldSize() {
    int n = 1;
    check(MPI_Comm_size(MPI_COMM_WORLD, &n), "MPI_Comm_size");
    return n;
}

int MpiSession::ranksOnThisNode() {
    MPI_Comm node;
    check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node), "MPI_Comm_split_type");
    int n = 1;
    check(MPI_Comm_size(node, &n), "MPI_Comm_size");
    MPI_Comm_free(&node);
    return n;
}

int MpiSession::worldRank() {
    int r = 0;
    check(MPI_Comm_rank(MPI_COMM_WORLD, &r), "MPI_Comm_rank");
    return r;
}

void MpiSession::barrier() {
    check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");
}

bool MpiSession::allTrue(bool mine) {
    int in = mine ? 1 : 0, out = 0;
    check(MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD), "MPI_Allreduce");
    return out != 0;
}

void MpiSession::abortAll(int code) {
    MPI_Abort(MPI_COMM_WORLD, code);
    std::exit(code);  // MPI_Abort does not return; this keeps [[noreturn]] honest if it did
}

}  // namespace bop::parallel
