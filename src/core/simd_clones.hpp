#pragma once
// Private: ISOFORGE_SIMD_CLONES compiles a function three times — AVX-512, AVX2 and the baseline
// (x86-64-v2 or whatever the build targets) — and picks one at load time by CPU feature. Use it on
// plain loops the compiler vectorizes (no intrinsics), so every clone has the same source.
//
// Clones are named by feature, not by CPU model: GCC's `arch=skylake-avx512` / `arch=haswell`
// resolvers test the CPU *model*, which newer or virtual CPUs do not match, so the baseline ran
// everywhere. The build uses -ffp-contract=off, so no clone contracts to FMA and all of them
// compute the same bits.
#if defined(__GNUC__) && !defined(__clang__) && (defined(__x86_64__) || defined(__i386__))
#define ISOFORGE_SIMD_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define ISOFORGE_SIMD_CLONES
#endif
