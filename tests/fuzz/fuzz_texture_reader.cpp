// libFuzzer target: build with -DCLOTHSIM_FUZZ=ON and clang (docs/hardening.md).
#include <cstddef>
#include <cstdint>

#include "fuzz_inputs.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  clothsim::fuzz::fuzz_texture(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
