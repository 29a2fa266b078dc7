// The fast kernels built for the baseline instruction set.
#define SHORE_KERNEL_NS generic
#include "kernel_impl.inc"
