#pragma once
// What the CPU running Shore offers, each asked once. Kernels with a wider path choose it
// at run time with these; each kernel's contract is that every path gives the same bits.

/// Defined where Shore can choose x86 paths at run time: an x86 target and a compiler with
/// __builtin_cpu_supports and function target attributes (GCC, Clang).
#if (defined(__x86_64__) || defined(__i386__)) && (defined(__GNUC__) || defined(__clang__))
#define SHORE_X86_DISPATCH 1
#endif

namespace shore {

/// AVX (256-bit doubles). __builtin_cpu_supports reports it only where the OS saves the
/// ymm state too.
[[nodiscard]] inline bool cpu_has_avx() {
#if defined(SHORE_X86_DISPATCH)
  static const bool has = __builtin_cpu_supports("avx");
  return has;
#else
  return false;
#endif
}

/// AVX2 with FMA.
[[nodiscard]] inline bool cpu_has_avx2_fma() {
#if defined(SHORE_X86_DISPATCH)
  static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return has;
#else
  return false;
#endif
}

/// AVX-512 F, VL, DQ and BW, with AVX2 and FMA (reported only where the OS saves the zmm
/// state too).
[[nodiscard]] inline bool cpu_has_avx512() {
#if defined(SHORE_X86_DISPATCH)
  static const bool has = cpu_has_avx2_fma() && __builtin_cpu_supports("avx512f") &&
                          __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") &&
                          __builtin_cpu_supports("avx512bw");
  return has;
#else
  return false;
#endif
}

}  // namespace shore
