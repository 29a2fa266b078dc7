#pragma once
// What the CPU running Shore offers, each asked once. Kernels with a wider path choose it
// at run time with these; each kernel's contract is that every path gives the same bits.

/// Defined where Shore can choose x86 paths at run time: an x86 target and a compiler with
/// __builtin_cpu_supports and function target attributes (GCC, Clang).
#if (defined(__x86_64__) || defined(__i386__)) && (defined(__GNUC__) || defined(__clang__))
#define SHORE_X86_DISPATCH 1
#endif

namespace shore {

/// The vector extensions Shore's kernels choose between, asked of the CPU once.
struct CpuFeatures {
  /// AVX (256-bit doubles). __builtin_cpu_supports reports it only where the OS saves the
  /// ymm state too.
  bool avx = false;
  bool avx2_fma = false;  ///< AVX2 with FMA
  /// AVX-512 F, VL, DQ and BW, with AVX2 and FMA (reported only where the OS saves the zmm
  /// state too).
  bool avx512 = false;
};

/// What this CPU offers (all false where Shore cannot dispatch: SHORE_X86_DISPATCH unset).
[[nodiscard]] inline const CpuFeatures& cpu_features() {
  static const CpuFeatures f = [] {
    CpuFeatures c;
#if defined(SHORE_X86_DISPATCH)
    c.avx = __builtin_cpu_supports("avx");
    c.avx2_fma = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    c.avx512 = c.avx2_fma && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
               __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw");
#endif
    return c;
  }();
  return f;
}

[[nodiscard]] inline bool cpu_has_avx() { return cpu_features().avx; }
[[nodiscard]] inline bool cpu_has_avx2_fma() { return cpu_features().avx2_fma; }
[[nodiscard]] inline bool cpu_has_avx512() { return cpu_features().avx512; }

}  // namespace shore
