// bop-kernel-floor: what the pair loops' arithmetic alone costs on this CPU. Each operation runs
// over an array that stays in the L1 cache (no positions gathered, no forces scattered), in the
// same x86-64-v3 clone and with the same four-lane types as the loops (core/SimdMath.hpp), and
// the best of several passes is printed as ns per element. An LJ pair needs one division and one
// square root (LjForm::forceOverR); an oriented pair needs both and an e^x besides. Where those
// alone take longer than a ns-per-pair target, no layout of the loops meets it in double precision
// on this CPU (scripts/bench/floor.sh).
#include "core/Potentials.hpp"
#include "core/SimdMath.hpp"
#include "core/TargetClones.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <vector>

namespace bop::tools {

using core::V4;
constexpr std::size_t kLanes = 4;

// One pass of op over n elements (n a multiple of 8), four lanes at a time; out keeps the
// results live.
template <typename Op>
[[gnu::always_inline]] inline void overLanes(const double* x, double* out, std::size_t n, Op op) {
    for (std::size_t k = 0; k < n; k += kLanes) {
        const V4 r = op(V4{x[k], x[k + 1], x[k + 2], x[k + 3]});
        for (std::size_t l = 0; l < kLanes; ++l) out[k + l] = r[l];
    }
}

BOP_HOT_LOOP void divisions(const double* x, double* out, std::size_t n) {
    overLanes(x, out, n, [](V4 v) { return 1.0 / v; });
}

BOP_HOT_LOOP void roots(const double* x, double* out, std::size_t n) {
    overLanes(x, out, n, [](V4 v) { return core::vsqrt(v); });
}

BOP_HOT_LOOP void divisionsAndRoots(const double* x, double* out, std::size_t n) {
    overLanes(x, out, n, [](V4 v) { return 1.0 / v + core::vsqrt(v); });
}

BOP_HOT_LOOP void exponentials(const double* x, double* out, std::size_t n) {
    overLanes(x, out, n, [](V4 v) { return core::simdExp(-v); });
}

// The LJ loop's own f(r)/r, over independent pairs (the compiler may use all four lanes).
BOP_HOT_LOOP void ljForces(const core::LjForm& lj, const double* r2, double* out, std::size_t n) {
    for (std::size_t k = 0; k < n; ++k) out[k] = lj.forceOverR(r2[k]);
}

// A dependent chain of integer additions, one per cycle: its ns per element is the clock period.
// Eight to a loop turn on x86-64, so that the loop's own counting and branch run beside them.
BOP_HOT_LOOP void additions(const double*, double* out, std::size_t n) {
    std::uint64_t a = 0;
#if defined(__x86_64__)
    for (std::size_t k = 0; k + 8 <= n; k += 8)
        asm volatile(
            "add %1, %0\n\tadd %1, %0\n\tadd %1, %0\n\tadd %1, %0\n\t"
            "add %1, %0\n\tadd %1, %0\n\tadd %1, %0\n\tadd %1, %0"
            : "+r"(a)
            : "r"(k));
#else
    for (std::size_t k = 0; k < n; ++k) {
        a += k;
        asm volatile("" : "+r"(a));  // keeps each addition, in order
    }
#endif
    out[0] = double(a);
}

}  // namespace bop::tools

int main(int argc, char** argv) {
    using namespace bop;
    CLI::App app{
        "bop-kernel-floor: ns per element of the pair loops' arithmetic alone (division, square root, "
        "e^x, LJ f(r)/r) on this CPU, operands in L1"};
    std::size_t elements = 1024, passes = 40000;
    int repeats = 5;
    std::string csv;
    app.add_option("--elements", elements,
                   "array length per pass, a multiple of 8 (the operand and result arrays, 16 bytes per element, stay "
                   "in a 32 KiB L1)")
        ->check(CLI::Range(std::size_t(8), std::size_t(2048)));
    app.add_option("--passes", passes, "passes over the array per timing")->check(CLI::Range(1, 10000000));
    app.add_option("--repeats", repeats, "timings per operation; the best is printed")->check(CLI::Range(1, 100));
    app.add_option("--csv", csv, "also write operation,ns_per_element to this file");
    CLI11_PARSE(app, argc, argv);
    elements -= elements % 8;  // four lanes, and the additions eight to a turn

    // Squared distances across the LJ range, 0.7 to 1.0 of the cutoff^2 (the switch included).
    const core::LjForm lj;
    std::vector<double> x(elements), out(elements);
    for (std::size_t k = 0; k < elements; ++k) x[k] = lj.cutoff2() * (0.7 + 0.3 * double(k) / double(elements));
    using Op = std::function<void(const double*, double*, std::size_t)>;
    const std::pair<const char*, Op> ops[] = {
        {"integer add (clock period)", tools::additions},
        {"division 1/x", tools::divisions},
        {"square root", tools::roots},
        {"division and square root", tools::divisionsAndRoots},
        {"e^x (simdExp)", tools::exponentials},
        {"LJ f(r)/r (forceOverR)", [&](const double* a, double* b, std::size_t n) { tools::ljForces(lj, a, b, n); }},
    };
    std::ofstream file;
    if (!csv.empty()) {
        file.open(csv);
        if (!file) {
            std::fprintf(stderr, "bop-kernel-floor: error: cannot write %s\n", csv.c_str());
            return 2;
        }
        file << "operation,ns_per_element\n";
    }
    std::printf("%-28s %14s\n", "operation", "ns per element");
    double check = 0;
    for (const auto& [name, op] : ops) {
        double best = 1e300;
        for (int r = 0; r < repeats; ++r) {
            const auto t0 = std::chrono::steady_clock::now();
            for (std::size_t p = 0; p < passes; ++p) op(x.data(), out.data(), elements);
            const std::chrono::duration<double, std::nano> dt = std::chrono::steady_clock::now() - t0;
            best = std::min(best, dt.count() / double(passes * elements));
            check += out[elements / 2];
        }
        std::printf("%-28s %14.3f\n", name, best);
        if (file) file << '"' << name << "\"," << best << '\n';
    }
    std::printf("(checksum %.6g)\n", check);
    return 0;
}
