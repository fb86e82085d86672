// libFuzzer targets for the mesh readers and for building a mesh from what they read: one
// binary per format, chosen by FFD_FUZZ_FORMAT at compile time (tests/fuzz/CMakeLists.txt).
#include "fuzz_target.h"
#include "mesh/build_mesh.h"
#include "mesh/obj_io.h"
#include "mesh/off_io.h"
#include "mesh/ply_io.h"
#include "mesh/stl_io.h"
#include "reader_paths.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return ffd::fuzz::one_input(data, size, [](std::string_view bytes) {
#if defined(FFD_FUZZ_OBJ)  // the fast path must read every input as the general path does
    ffd::fuzz::check_obj_paths_agree(bytes);
#elif defined(FFD_FUZZ_OFF)
    ffd::fuzz::check_off_paths_agree(bytes);
#endif
    ffd::PolygonSoup soup = FFD_FUZZ_READER(bytes, "fuzz");
    ffd::build_mesh(std::move(soup), "fuzz");
  });
}
