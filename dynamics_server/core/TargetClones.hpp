#pragma once
// BOP_HOT_LOOP: a function compiled three times on x86-64 with GCC, for the baseline, for
// x86-64-v3 (AVX2, FMA: Haswell, 2013, and later) and for x86-64-v4 (AVX-512 F/BW/CD/DQ/VL:
// Skylake-X, Zen 4 and later), the loader choosing the best one this CPU runs (GCC
// target_clones, an ifunc). The pair loops' arithmetic gains from FMA, from twice the vector
// registers (v3) and from mask registers and 32 of them (v4); one binary still runs on every
// x86-64 node of a cluster. The loops it marks inline what they call (always_inline), so that the
// clone covers the whole loop.
//
// The clones round differently (FMA), so a run's trajectory may differ between CPUs, as it does
// between builds; on one machine it is the same every time, at any thread count.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(BOP_NO_CLONES) && \
    !defined(__SANITIZE_ADDRESS__)
#define BOP_HOT_LOOP __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#define BOP_HOT_LOOP_CLONES 1
#else
#define BOP_HOT_LOOP
#define BOP_HOT_LOOP_CLONES 0
#endif

namespace bop::core {

// The clone of the hot loops that runs on this CPU, as the loader picks it: "x86-64-v4",
// "x86-64-v3" or "baseline" ("baseline (no clones in this build)" where BOP_HOT_LOOP is empty).
inline const char* hotLoopClone() {
#if BOP_HOT_LOOP_CLONES
    __builtin_cpu_init();
    if (__builtin_cpu_supports("x86-64-v4")) return "x86-64-v4";
    if (__builtin_cpu_supports("x86-64-v3")) return "x86-64-v3";
    return "baseline";
#else
    return "baseline (no clones in this build)";
#endif
}

}  // namespace bop::core
