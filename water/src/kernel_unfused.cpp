// The row-pass kernels the fused ones replaced, built for the baseline instruction set: the
// bitwise reference of the tests (KernelChoice::unfused).
#define SHORE_KERNEL_NS unfused
#include "kernel_unfused.inc"
