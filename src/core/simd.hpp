#pragma once
// Compiler hints for the solvers' hot loops.

// The hot loops are compiled for AVX-512, AVX2 and baseline x86-64, and the loader picks the clone the CPU
// supports, so one binary is fast on current machines and still runs on old ones. No FMA contraction
// (CMakeLists.txt): every clone rounds identically.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(ROV_TETHER_NO_CLONES)
#define ROV_TETHER_TARGET_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define ROV_TETHER_TARGET_CLONES
#endif
// Loops called from a cloned function must be inlined into it, or they would be compiled for the
// baseline target only.
#if defined(__GNUC__)
#define ROV_TETHER_INLINE inline __attribute__((always_inline))
#else
#define ROV_TETHER_INLINE inline
#endif
