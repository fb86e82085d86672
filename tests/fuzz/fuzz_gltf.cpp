// libFuzzer targets for the glTF reader and writer (gltf_input.h): whole files (fuzz_gltf),
// or the compressed stream of a Draco or meshopt file (compressed_input.h), chosen by
// FFD_FUZZ_DRACO / FFD_FUZZ_MESHOPT at compile time.
#include "compressed_input.h"
#include "fuzz_target.h"
#include "gltf_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ffd::fuzz::one_input(data, size, [](std::string_view bytes) {
#if defined(FFD_FUZZ_DRACO)
    ffd::fuzz::check_gltf_round_trip(ffd::fuzz::draco_glb(bytes));
#elif defined(FFD_FUZZ_MESHOPT)
    ffd::fuzz::check_gltf_round_trip(ffd::fuzz::meshopt_glb(bytes));
#else
    ffd::fuzz::check_gltf_round_trip(bytes);
#endif
  });
}
