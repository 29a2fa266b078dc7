// libFuzzer's entry point for one target, chosen when compiling (SHORE_FUZZ_TARGET, one of
// the functions of entries.h).
#include <cstddef>
#include <cstdint>

#include "entries.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  (void)shore::fuzz::SHORE_FUZZ_TARGET({data, size});
  return 0;
}
