// The libFuzzer entry point of one target of fuzz_targets.h, chosen at
// compile time by SURFREG_FUZZ_TARGET (its name, e.g. "ply").
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string_view>

#include "tests/fuzz/fuzz_targets.h"

namespace {

surfreg::fuzz::FuzzFunction Target() {
  for (const auto& target : surfreg::fuzz::FuzzTargets()) {
    if (std::strcmp(target.name, SURFREG_FUZZ_TARGET) == 0) return target.run;
  }
  std::cerr << "no fuzz target named " << SURFREG_FUZZ_TARGET << "\n";
  std::abort();
}

}  // namespace

// Anything but a normal return (an exception escaping, an invariant broken,
// a sanitizer report) is a finding that libFuzzer saves as a crash input.
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  static const surfreg::fuzz::FuzzFunction run = Target();
  run(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
