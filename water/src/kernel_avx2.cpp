// The fast kernels built for AVX2 + FMA (see water/CMakeLists.txt); run only when the CPU
// has them (kernel_dispatch.cpp).
#define SHORE_KERNEL_NS avx2
#include "kernel_impl.inc"
