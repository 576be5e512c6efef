#pragma once
// MPI for a program's lifetime, behind a header without <mpi.h> so that tools outside
// parallel/ can start and stop it: MPI_Init in the constructor (errors returned, not fatal),
// MPI_Finalize in the destructor. The constructor also sets the threads each rank's loops use
// (core/Threads.hpp): OMP_NUM_THREADS if set, else this machine's cores over its ranks.
namespace bop::parallel {

class MpiSession {
public:
    MpiSession(int& argc, char**& argv);
    ~MpiSession();
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;

    static int worldSize();
    static int worldRank();
    // Ranks of this job on this rank's machine (MPI_COMM_TYPE_SHARED). Collective.
    static int ranksOnThisNode();
    // Waits for every rank (set-up steps that one rank does for all, such as the map cache).
    static void barrier();
    // Whether every rank passes true (set-up errors that must stop all ranks alike).
    static bool allTrue(bool mine);
    // Ends every rank of the job (after an error on one rank, the others may wait forever).
    [[noreturn]] static void abortAll(int code);
};

}  // namespace bop::parallel
