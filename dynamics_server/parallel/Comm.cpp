#include "Comm.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace bop::parallel {

void check(int rc, const char* what) {
    if (rc == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    if (MPI_Error_string(rc, text, &length) != MPI_SUCCESS) length = 0;
    throw std::runtime_error(std::string("MPI ") + what + ": " + std::string(text, std::size_t(length)));
}

CartComm::CartComm(MPI_Comm base, const core::Box& box) {
    check(MPI_Comm_dup(base, &dup_), "MPI_Comm_dup");
    check(MPI_Comm_set_errhandler(dup_, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
    check(MPI_Comm_size(dup_, &size_), "MPI_Comm_size");
    int dims[3] = {0, 0, 0};
    check(MPI_Dims_create(size_, 3, dims), "MPI_Dims_create");
    // MPI_Dims_create orders the factors largest first; give the largest to the longest axis.
    std::array<int, 3> axes{0, 1, 2};
    const Eigen::Vector3d L = box.size();
    std::sort(axes.begin(), axes.end(), [&](int a, int b) { return L[a] > L[b] || (L[a] == L[b] && a < b); });
    for (int k = 0; k < 3; ++k) dims_[std::size_t(axes[std::size_t(k)])] = dims[k];
    int periods[3];
    for (int a = 0; a < 3; ++a) periods[a] = box.periodic[std::size_t(a)] ? 1 : 0;
    check(MPI_Cart_create(dup_, 3, dims_.data(), periods, 0, &cart_), "MPI_Cart_create");
    check(MPI_Comm_set_errhandler(cart_, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
    check(MPI_Comm_rank(cart_, &rank_), "MPI_Comm_rank");
    check(MPI_Cart_coords(cart_, rank_, 3, coords_.data()), "MPI_Cart_coords");
    for (int a = 0; a < 3; ++a)
        check(MPI_Cart_shift(cart_, a, 1, &lower_[std::size_t(a)], &upper_[std::size_t(a)]), "MPI_Cart_shift");
}

CartComm::~CartComm() {
    if (cart_ != MPI_COMM_NULL) MPI_Comm_free(&cart_);
    if (dup_ != MPI_COMM_NULL) MPI_Comm_free(&dup_);
}

namespace {

int intCount(std::size_t bytes, const char* what) {
    if (bytes > std::size_t(std::numeric_limits<int>::max()))
        throw std::runtime_error(std::string(what) + ": " + std::to_string(bytes) +
                                 " bytes exceed one message's int count");
    return int(bytes);
}

// Offsets of each rank's part, from the parts' sizes in bytes (rank order).
std::vector<int> offsetsOf(const std::vector<int>& counts, const char* what) {
    std::vector<int> offsets(counts.size(), 0);
    long long total = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) {
        offsets[r] = int(total);
        total += counts[r];
        intCount(std::size_t(total), what);
    }
    return offsets;
}

}  // namespace

std::size_t CartComm::exchangeCounts(std::size_t out, int to, int from, int tag) const {
    unsigned long long nOut = out, nIn = 0;
    check(MPI_Sendrecv(&nOut, 1, MPI_UNSIGNED_LONG_LONG, to, tag, &nIn, 1, MPI_UNSIGNED_LONG_LONG, from, tag, cart_,
                       MPI_STATUS_IGNORE),
          "MPI_Sendrecv (count)");
    return from == MPI_PROC_NULL ? 0 : std::size_t(nIn);
}

void CartComm::sendRecvBytes(const void* out, std::size_t outBytes, int to, void* in, std::size_t inBytes, int from,
                             int tag) const {
    check(MPI_Sendrecv(out, intCount(outBytes, "MPI_Sendrecv"), MPI_BYTE, to, tag, in,
                       intCount(inBytes, "MPI_Sendrecv"), MPI_BYTE, from, tag, cart_, MPI_STATUS_IGNORE),
          "MPI_Sendrecv");
}

std::vector<std::byte> CartComm::allGatherBytes(const std::vector<std::byte>& mine) const {
    const int n = intCount(mine.size(), "MPI_Allgather");
    std::vector<std::byte> all(mine.size() * std::size_t(size_));
    intCount(all.size(), "MPI_Allgather");
    check(MPI_Allgather(mine.data(), n, MPI_BYTE, all.data(), n, MPI_BYTE, cart_), "MPI_Allgather");
    return all;
}

std::vector<std::byte> CartComm::gatherVBytes(const std::vector<std::byte>& mine, bool everyRank) const {
    const char* what = everyRank ? "MPI_Allgatherv" : "MPI_Gatherv";
    int count = intCount(mine.size(), what);
    std::vector<int> counts(std::size_t(size_), 0);
    if (everyRank)
        check(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, cart_), "MPI_Allgather (counts)");
    else
        check(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, cart_), "MPI_Gather (counts)");
    const bool here = everyRank || rank_ == 0;
    const std::vector<int> offsets = here ? offsetsOf(counts, what) : std::vector<int>(counts.size(), 0);
    std::vector<std::byte> all(here ? std::size_t(offsets.back()) + std::size_t(counts.back()) : 0);
    if (everyRank)
        check(MPI_Allgatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, cart_),
              what);
    else
        check(MPI_Gatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, 0, cart_),
              what);
    return all;
}

void CartComm::broadcastBytes(std::vector<std::byte>& data) const {
    unsigned long long n = data.size();
    check(MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, cart_), "MPI_Bcast (count)");
    data.resize(std::size_t(n));
    if (n > 0) check(MPI_Bcast(data.data(), intCount(data.size(), "MPI_Bcast"), MPI_BYTE, 0, cart_), "MPI_Bcast");
}

bool CartComm::allTrue(bool mine) const {
    int in = mine ? 1 : 0, out = 0;
    check(MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LAND, cart_), "MPI_Allreduce");
    return out != 0;
}

}  // namespace bop::parallel
