#pragma once
// BOP_HOT_LOOP: a function compiled twice on x86-64 with GCC, for the baseline and for
// x86-64-v3 (AVX2, FMA: Haswell, 2013, and later), the loader choosing the one this CPU runs
// (GCC target_clones, an ifunc). The pair loops' arithmetic gains from FMA and from twice the
// vector registers; one binary still runs on every x86-64 node of a cluster. The loops it marks
// inline what they call (always_inline), so that the clone covers the whole loop.
//
// The clones round differently (FMA), so a run's trajectory may differ between CPUs, as it does
// between builds; on one machine it is the same every time.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(BOP_NO_CLONES) && \
    !defined(__SANITIZE_ADDRESS__)
#define BOP_HOT_LOOP __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define BOP_HOT_LOOP
#endif
