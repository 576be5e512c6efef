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

void CartComm::sendRecv(const std::vector<double>& out, int to, std::vector<double>& in, int from, int tag) const {
    if (out.size() > std::size_t(std::numeric_limits<int>::max()))
        throw std::runtime_error("MPI_Sendrecv: " + std::to_string(out.size()) +
                                 " values exceed one message's int count");
    unsigned long long nOut = out.size(), nIn = 0;
    check(MPI_Sendrecv(&nOut, 1, MPI_UNSIGNED_LONG_LONG, to, tag, &nIn, 1, MPI_UNSIGNED_LONG_LONG, from, tag, cart_,
                       MPI_STATUS_IGNORE),
          "MPI_Sendrecv (count)");
    in.resize(from == MPI_PROC_NULL ? 0 : std::size_t(nIn));
    check(MPI_Sendrecv(out.data(), int(out.size()), MPI_DOUBLE, to, tag + 1, in.data(), int(in.size()), MPI_DOUBLE,
                       from, tag + 1, cart_, MPI_STATUS_IGNORE),
          "MPI_Sendrecv");
}

std::vector<double> CartComm::allGather(const std::vector<double>& mine) const {
    std::vector<double> all(mine.size() * std::size_t(size_));
    check(MPI_Allgather(mine.data(), int(mine.size()), MPI_DOUBLE, all.data(), int(mine.size()), MPI_DOUBLE, cart_),
          "MPI_Allgather");
    return all;
}

std::vector<double> CartComm::allGatherV(const std::vector<double>& mine) const {
    if (mine.size() > std::size_t(std::numeric_limits<int>::max()))
        throw std::runtime_error("MPI_Allgatherv: " + std::to_string(mine.size()) +
                                 " values exceed one message's int count");
    int count = int(mine.size());
    const std::size_t ranks = std::size_t(size_);
    std::vector<int> counts(ranks, 0), offsets(ranks, 0);
    check(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, cart_), "MPI_Allgather (counts)");
    long long total = 0;
    for (int c : counts) total += c;
    if (total > std::numeric_limits<int>::max())
        throw std::runtime_error("MPI_Allgatherv: " + std::to_string(total) + " values exceed one message's int count");
    for (int r = 1; r < size_; ++r) offsets[std::size_t(r)] = offsets[std::size_t(r) - 1] + counts[std::size_t(r) - 1];
    std::vector<double> all(std::size_t(offsets.back() + counts.back()));
    check(MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, cart_),
          "MPI_Allgatherv");
    return all;
}

std::vector<float> CartComm::gatherV(const std::vector<float>& mine) const {
    if (mine.size() > std::size_t(std::numeric_limits<int>::max()))
        throw std::runtime_error("MPI_Gatherv: " + std::to_string(mine.size()) +
                                 " values exceed one message's int count");
    int count = int(mine.size());
    const std::size_t ranks = std::size_t(size_);
    std::vector<int> counts(ranks, 0), offsets(ranks, 0);
    check(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, cart_), "MPI_Gather (counts)");
    long long total = 0;
    for (int c : counts) total += c;
    if (rank_ == 0 && total > std::numeric_limits<int>::max())
        throw std::runtime_error("MPI_Gatherv: " + std::to_string(total) + " values exceed one message's int count");
    for (int r = 1; r < size_; ++r) offsets[std::size_t(r)] = offsets[std::size_t(r) - 1] + counts[std::size_t(r) - 1];
    std::vector<float> all(rank_ == 0 ? std::size_t(total) : 0);
    check(MPI_Gatherv(mine.data(), count, MPI_FLOAT, all.data(), counts.data(), offsets.data(), MPI_FLOAT, 0, cart_),
          "MPI_Gatherv");
    return all;
}

void CartComm::broadcast(std::vector<double>& data) const {
    unsigned long long n = data.size();
    check(MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, cart_), "MPI_Bcast (count)");
    data.resize(std::size_t(n));
    if (n > 0) check(MPI_Bcast(data.data(), int(n), MPI_DOUBLE, 0, cart_), "MPI_Bcast");
}

bool CartComm::allTrue(bool mine) const {
    int in = mine ? 1 : 0, out = 0;
    check(MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LAND, cart_), "MPI_Allreduce");
    return out != 0;
}

}  // namespace bop::parallel
