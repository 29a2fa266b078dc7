// The fast kernels built for AVX-512 (F, VL, DQ, BW) with 512-bit vectors (see
// water/CMakeLists.txt); run only when the CPU has them (kernel_dispatch.cpp). The same
// source and the same exact operations as the AVX2 variant, twice as wide: the spring and
// update loops are bound by how many instructions they issue, not by the square roots.
#define SHORE_KERNEL_NS avx512
#include "kernel_impl.inc"
