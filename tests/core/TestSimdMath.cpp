// The pair loops' e^x (core/SimdMath.hpp) against std::exp: the oriented loop's Gaussian weight
// rests on it, and the loops' forces must stay within 1e-12 of the reference kernel's.
#include "core/SimdMath.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace bop::core;

namespace {
double relativeError(double got, double want) {
    return std::abs(got - want) / want;
}
}  // namespace

TEST_CASE("simdExp is within a few units in the last place of std::exp, in one lane and in four", "[core][simd]") {
    std::mt19937_64 rng(20261203);
    std::uniform_real_distribution<double> wide(-700.0, 700.0), gaussian(-12.0, 0.0);
    double worst = 0;
    for (int k = 0; k < 200000; ++k) {
        const double x = k % 2 ? wide(rng) : gaussian(rng);  // the loops' use: -r^2 / 2 sigma^2
        worst = std::max(worst, relativeError(simdExp(x), std::exp(x)));
    }
    // Exact points: integers times ln 2 reduce to r = 0 or near it; the ends of the range.
    for (double x : {0.0, -1.0, 1.0, -0.5 * std::log(2.0), std::log(2.0), -700.0, 700.0, -1e-300, 1e-17})
        worst = std::max(worst, relativeError(simdExp(x), std::exp(x)));
    INFO("worst relative error " << worst);
    CHECK(worst < 5 * 0x1p-52);
    CHECK(simdExp(0.0) == 1.0);

    // Four lanes give each lane's scalar value.
    for (int k = 0; k < 1000; ++k) {
        const V4 x{gaussian(rng), wide(rng), gaussian(rng), wide(rng)};
        const V4 y = simdExp(x);
        for (int l = 0; l < 4; ++l) CHECK(relativeError(y[l], std::exp(x[l])) < 5 * 0x1p-52);
    }
}

TEST_CASE("simdExp clamps its argument to [-700, 700] instead of overflowing the exponent", "[core][simd]") {
    CHECK(simdExp(-800.0) == simdExp(-700.0));
    CHECK(simdExp(-1e308) == simdExp(-700.0));
    CHECK(simdExp(1e5) == simdExp(700.0));
    CHECK(std::isfinite(simdExp(700.0)));
    CHECK(simdExp(-700.0) > 0.0);
    CHECK(relativeError(simdExp(-700.0), std::exp(-700.0)) < 5 * 0x1p-52);
}

TEST_CASE("simdExp in sixteen float lanes is within a few float ulp of std::exp, and clamps to [-87, 87]",
          "[core][simd][mixed]") {
    std::mt19937_64 rng(20261207);
    std::uniform_real_distribution<float> wide(-87.0f, 87.0f), gaussian(-12.0f, 0.0f);
    double worst = 0;
    for (int k = 0; k < 20000; ++k) {
        V16F x;
        for (int l = 0; l < 16; ++l) x[l] = l % 2 ? wide(rng) : gaussian(rng);
        if (k == 0) x = V16F{0.0f, -1.0f, 1.0f, -0.34657359f, 0.69314718f, -87.0f, 87.0f, -1e-30f};
        const V16F y = simdExp(x);
        for (int l = 0; l < 16; ++l) worst = std::max(worst, relativeError(y[l], std::exp(double(x[l]))));
    }
    INFO("worst relative error against std::exp of the float argument " << worst);
    CHECK(worst < 4 * 0x1p-23);
    CHECK(simdExp(splat16(0.0f))[3] == 1.0f);
    const V16F clamped = simdExp(V16F{-100.0f, 100.0f, -1e30f, 1e30f});
    CHECK(clamped[0] == simdExp(splat16(-87.0f))[0]);
    CHECK(clamped[2] == clamped[0]);
    CHECK(clamped[1] == simdExp(splat16(87.0f))[0]);
    CHECK(clamped[3] == clamped[1]);
    CHECK(std::isfinite(clamped[1]));
    CHECK(clamped[0] > 0.0f);
}
