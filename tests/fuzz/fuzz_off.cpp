// libFuzzer harness for the OFF loader (fuzz_inputs.hpp says what it runs).

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "tests/fuzz/fuzz_inputs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  lhr::fuzz::run_off(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
