// libFuzzer targets for the volume readers and their writers: one binary per format,
// chosen by FFD_FUZZ_VOLUME at compile time (tests/fuzz/CMakeLists.txt).
#include <stdexcept>

#include "fuzz_target.h"
#include "volume_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ffd::fuzz::one_input(data, size, [](std::string_view bytes) {
    try {
      ffd::fuzz::check_volume_round_trip(FFD_FUZZ_VOLUME, bytes);
    } catch (const std::logic_error& e) {
      __builtin_trap();  // a property failed: a finding
    }
  });
}
