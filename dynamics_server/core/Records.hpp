#pragma once
// What crosses between processes is a record: a struct whose fields are declared once and
// travel as its bytes (ids as the integers they are), in gathers, broadcasts and sums alike
// (Exchange.hpp; parallel/Comm.hpp moves the bytes). Plain values only: no pointers, nothing to
// destroy.
#include <cstddef>
#include <cstring>
#include <type_traits>
#include <vector>

namespace bop::core {

template <class R>
inline constexpr bool kIsRecord = std::is_standard_layout_v<R>&& std::is_trivially_destructible_v<R>;

template <class R>
std::vector<std::byte> recordBytes(const std::vector<R>& records) {
    static_assert(kIsRecord<R>, "only records cross between processes");
    std::vector<std::byte> b(records.size() * sizeof(R));
    if (!b.empty()) std::memcpy(b.data(), static_cast<const void*>(records.data()), b.size());
    return b;
}

template <class R>
std::vector<R> recordsOf(const std::vector<std::byte>& bytes) {
    static_assert(kIsRecord<R>, "only records cross between processes");
    std::vector<R> records(bytes.size() / sizeof(R));
    if (!records.empty()) std::memcpy(static_cast<void*>(records.data()), bytes.data(), records.size() * sizeof(R));
    return records;
}

// Field by field, the sum of records whose every field is a double (Eigen vectors of doubles
// included), added in the order given (rank order: the same sum on every process).
template <class R>
R sumInOrder(const std::vector<R>& records) {
    static_assert(kIsRecord<R> && sizeof(R) % sizeof(double) == 0, "a record of doubles");
    constexpr std::size_t n = sizeof(R) / sizeof(double);
    double sum[n] = {};
    for (const R& r : records) {
        double v[n];
        std::memcpy(v, static_cast<const void*>(&r), sizeof r);
        for (std::size_t k = 0; k < n; ++k) sum[k] += v[k];
    }
    R out;
    std::memcpy(static_cast<void*>(&out), sum, sizeof out);
    return out;
}

}  // namespace bop::core
