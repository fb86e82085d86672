// libFuzzer targets for the mesh readers and for building a mesh from what they read: one
// binary per format, chosen by FFD_FUZZ_FORMAT at compile time (tests/fuzz/CMakeLists.txt).
#include "fuzz_target.h"
#include "mesh/build_mesh.h"
#include "mesh/obj_io.h"
#include "mesh/off_io.h"
#include "mesh/ply_io.h"
#include "mesh/stl_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ffd::fuzz::one_input(data, size, [](std::string_view bytes) {
    const ffd::PolygonSoup soup = FFD_FUZZ_READER(bytes, "fuzz");
    ffd::build_mesh(std::move(soup), "fuzz");
  });
}
