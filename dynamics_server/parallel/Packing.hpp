#pragma once
// Ids and other 64-bit integers travel in the double arrays of MPI messages bit for bit.
#include <cstdint>
#include <cstring>

namespace bop::parallel {

inline double idBits(std::uint64_t id) {
    double d;
    std::memcpy(&d, &id, sizeof d);
    return d;
}
inline std::uint64_t idOf(double d) {
    std::uint64_t id;
    std::memcpy(&id, &d, sizeof id);
    return id;
}

}  // namespace bop::parallel
