# SHORE_FUZZ=ON: the libFuzzer targets fuzz_<loader> (fuzz/README.md; ./shore fuzz builds
# and runs them). Needs clang; every target of the build gets AddressSanitizer,
# UndefinedBehaviorSanitizer and libFuzzer's coverage instrumentation, and the fuzz
# executables libFuzzer's driver.
option(SHORE_FUZZ "Build the libFuzzer targets fuzz_<loader> (clang only; instruments the whole build)" OFF)
if(SHORE_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "SHORE_FUZZ=ON needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++ "
                        "(./shore fuzz does)")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
  message(STATUS "Shore: libFuzzer targets with ASan and UBSan")
endif()
