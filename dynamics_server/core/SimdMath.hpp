#pragma once
// Four doubles at a time for the pair loops (GCC/Clang vector extensions): V4 holds four lanes,
// arithmetic works lane by lane, with a few functions (square root, e^x, clamps, selects) the
// compiler evaluates in every lane. simdExp also takes a double, so that its test compares one
// lane with std::exp. In an x86-64-v3 clone (TargetClones.hpp) a V4 is one AVX register; in the
// baseline, two SSE2 halves.
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace bop::core {

using V4 = double __attribute__((vector_size(32)));
using V4Mask = std::int64_t __attribute__((vector_size(32)));  // lanes all ones (true) or zero
using V4Bits = std::uint64_t __attribute__((vector_size(32)));

[[gnu::always_inline]] inline V4 splat(double x) {
    return V4{x, x, x, x};
}
[[gnu::always_inline]] inline V4 select(V4Mask m, V4 a, V4 b) {
    return m ? a : b;
}
[[gnu::always_inline]] inline V4 vsqrt(V4 x) {
    return V4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
}
// max(x, lo) and min(x, hi), written as selects (no library call)
[[gnu::always_inline]] inline double atLeast(double x, double lo) {
    return x > lo ? x : lo;
}
[[gnu::always_inline]] inline V4 atLeast(V4 x, double lo) {
    return x > lo ? x : splat(lo);
}
[[gnu::always_inline]] inline double atMost(double x, double hi) {
    return x < hi ? x : hi;
}
[[gnu::always_inline]] inline V4 atMost(V4 x, double hi) {
    return x < hi ? x : splat(hi);
}
[[gnu::always_inline]] inline std::uint64_t bitsOf(double x) {
    return std::bit_cast<std::uint64_t>(x);
}
[[gnu::always_inline]] inline V4Bits bitsOf(V4 x) {
    return std::bit_cast<V4Bits>(x);
}
[[gnu::always_inline]] inline double fromBits(std::uint64_t b) {
    return std::bit_cast<double>(b);
}
[[gnu::always_inline]] inline V4 fromBits(V4Bits b) {
    return std::bit_cast<V4>(b);
}

// e^x, with x clamped to [-700, 700] (e^-700 is about 1e-304), for a double or four lanes.
// Within a few units in the last place of std::exp (tests/core/TestSimdMath.cpp). Cody-Waite
// reduction x = n ln2 + r with |r| <= ln2 / 2, a degree-13 Taylor polynomial for e^r (its
// remainder is below 5e-18), and 2^n written into the exponent bits.
template <typename T>
[[gnu::always_inline]] inline T simdExp(T x) {
    constexpr double kLog2e = 1.4426950408889634074;
    constexpr double kShift = 0x1.8p52;                    // adding it rounds to an integer kept in the low bits
    constexpr double kLn2Hi = 6.93147180369123816490e-01;  // ln 2's leading bits: n kLn2Hi is exact for |n| < 2^11
    constexpr double kLn2Lo = 1.90821492927058770002e-10;  // ln 2 - kLn2Hi
    x = atMost(atLeast(x, -700.0), 700.0);
    const T t = x * kLog2e + kShift;
    const T n = t - kShift;
    const T r = (x - n * kLn2Hi) - n * kLn2Lo;
    T p = r * (1.0 / 6227020800.0) + 1.0 / 479001600.0;  // 1/13!, 1/12!
    p = p * r + 1.0 / 39916800.0;
    p = p * r + 1.0 / 3628800.0;
    p = p * r + 1.0 / 362880.0;
    p = p * r + 1.0 / 40320.0;
    p = p * r + 1.0 / 5040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    p = p * r + 1.0;
    p = p * r + 1.0;
    // t's low mantissa bits hold 2^51 + n; adding the bias and shifting leaves n + 1023 in the
    // exponent field (1 <= n + 1023 <= 2033 after the clamp), sign and mantissa zero: 2^n.
    return p * fromBits((bitsOf(t) + 1023u) << 52);
}

// ---- sixteen floats, for the mixed-precision oriented loop (OrientedPairLoopMixed.cpp) ----
// One AVX-512 register, two AVX2, four SSE2. Scalars in the expressions must be floats (or
// constants a float holds exactly): the extensions refuse a double that would be rounded.
using V16F = float __attribute__((vector_size(64)));
using V16FMask = std::int32_t __attribute__((vector_size(64)));
using V16FBits = std::uint32_t __attribute__((vector_size(64)));

[[gnu::always_inline]] inline V16F splat16(float x) {
    return V16F{} + x;
}
[[gnu::always_inline]] inline V16F load16(const float* p) {  // any alignment
    V16F v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
[[gnu::always_inline]] inline void store16(float* to, V16F v) {
    std::memcpy(to, &v, sizeof v);
}
// Four doubles rounded to floats at `to` (the mixed loops' gathers work in V4, compute in V16F).
[[gnu::always_inline]] inline void toFloats(float* to, V4 v) {
    using V4F = float __attribute__((vector_size(16)));
    const V4F f = __builtin_convertvector(v, V4F);
    std::memcpy(to, &f, sizeof f);
}
[[gnu::always_inline]] inline V16F select(V16FMask m, V16F a, V16F b) {
    return m ? a : b;
}
[[gnu::always_inline]] inline V16F vsqrt(V16F x) {
    V16F r;
    for (int l = 0; l < 16; ++l) r[l] = std::sqrt(x[l]);
    return r;
}
// Compared with a vector, not the scalar: with a scalar GCC compares lane by lane.
[[gnu::always_inline]] inline V16F atLeast(V16F x, float lo) {
    return x > splat16(lo) ? x : splat16(lo);
}
[[gnu::always_inline]] inline V16F atMost(V16F x, float hi) {
    return x < splat16(hi) ? x : splat16(hi);
}

// e^x in float lanes, x clamped to [-87, 87]: within about 2 float ulp of std::exp
// (tests/core/TestSimdMath.cpp). simdExp's scheme in float: x = n ln2 + r, |r| <= ln2 / 2, a
// degree-7 Taylor polynomial (remainder below 6e-9), 2^n written into the exponent bits.
[[gnu::always_inline]] inline V16F simdExp(V16F x) {
    constexpr float kLog2e = 1.44269504f;
    constexpr float kShift = 0x1.8p23f;        // adding it rounds to an integer kept in the low bits
    constexpr float kLn2Hi = 0.693145752f;     // ln 2's leading bits (0x1.62e4p-1): n kLn2Hi is exact for |n| < 2^9
    constexpr float kLn2Lo = 1.42860682e-06f;  // ln 2 - kLn2Hi
    x = atMost(atLeast(x, -87.0f), 87.0f);
    const V16F t = x * kLog2e + kShift;
    const V16F n = t - kShift;
    const V16F r = (x - n * kLn2Hi) - n * kLn2Lo;
    V16F p = r * (1.0f / 5040.0f) + (1.0f / 720.0f);
    p = p * r + (1.0f / 120.0f);
    p = p * r + (1.0f / 24.0f);
    p = p * r + (1.0f / 6.0f);
    p = p * r + 0.5f;
    p = p * r + 1.0f;
    p = p * r + 1.0f;
    // t's low mantissa bits hold 2^22 + n: adding the bias and shifting leaves n + 127 in the
    // exponent field (1 <= n + 127 <= 253 after the clamp), sign and mantissa zero: 2^n.
    return p * std::bit_cast<V16F>((std::bit_cast<V16FBits>(t) + 127u) << 23);
}

}  // namespace bop::core
