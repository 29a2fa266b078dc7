# Same bits on every machine.
#
# SHORE_CROSS_PLATFORM_DETERMINISTIC (default ON): every Shore target is compiled with
# -ffp-contract=off, so no compiler fuses a multiply and an add into an FMA on some paths
# and not on others. With it, the water module's AVX2 kernel, its generic kernel and a
# non-x86 build give the same bits, and so do the ordinary, sanitizer and -march=native
# builds. It costs under 10 % on the water benchmark (docs/BENCHMARKS.md), hence the
# default. OFF lets the AVX2 kernel contract (a few per cent faster); results are then the
# same on every x86-64 CPU with AVX2 + FMA for a given binary, but differ from the generic
# kernel's.
#
# Independently of the option, no Shore library uses approximate instructions (rsqrt, rcp)
# or the C library's transcendental functions in anything it computes into its state
# (shore/core/det_math.h); tests/core/test_no_approximate_instructions checks the former.
option(SHORE_CROSS_PLATFORM_DETERMINISTIC
       "Same bits from every kernel and CPU: compile with -ffp-contract=off (see cmake/ShoreDeterminism.cmake)" ON)
option(SHORE_WATER_NO_AVX2 "Build the water module with its generic kernel only (no AVX2 variant)" OFF)

if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  # Flags that make results depend on the compiler's whims are refused outright.
  foreach(_flags_var CMAKE_CXX_FLAGS CMAKE_CXX_FLAGS_${CMAKE_BUILD_TYPE})
    string(TOUPPER "${_flags_var}" _flags_var)
    if("${${_flags_var}}" MATCHES "(-ffast-math|-Ofast|-funsafe-math-optimizations|-freciprocal-math)")
      message(FATAL_ERROR "Shore: ${_flags_var} contains '${CMAKE_MATCH_1}', which lets the compiler use "
                          "approximate reciprocals and reorder sums, so results would differ between machines. "
                          "Remove it.")
    endif()
  endforeach()
  if(SHORE_CROSS_PLATFORM_DETERMINISTIC)
    add_compile_options(-ffp-contract=off)
  endif()
endif()
if(SHORE_CROSS_PLATFORM_DETERMINISTIC)
  # Lets tests and demos know which guarantee this build gives (not exported).
  add_compile_definitions(SHORE_CROSS_PLATFORM_DETERMINISTIC=1)
endif()
message(STATUS "Shore: cross-platform deterministic ${SHORE_CROSS_PLATFORM_DETERMINISTIC}, "
               "water generic kernel only ${SHORE_WATER_NO_AVX2}")
