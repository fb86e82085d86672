// libFuzzer target for the glTF reader and writer (gltf_input.h).
#include "fuzz_target.h"
#include "gltf_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ffd::fuzz::one_input(data, size, [](std::string_view bytes) { ffd::fuzz::check_gltf_round_trip(bytes); });
}
