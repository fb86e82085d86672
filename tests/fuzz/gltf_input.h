// The glTF fuzz target's check, shared with the ctest replay of its corpus: bytes are read
// as GLB (when they start with "glTF") or as glTF JSON; what reads must also write, as
// GLB and as embedded JSON, and read back with the same vertices.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string_view>

#include "mesh/gltf_io.h"

namespace ffd::fuzz {

inline void check_gltf_round_trip(std::string_view bytes) {
  const bool binary = bytes.substr(0, 4) == "glTF";
  const Mesh mesh = read_gltf(bytes, binary ? "fuzz.glb" : "fuzz.gltf", binary);
  for (const bool glb : {true, false}) {
    std::ostringstream os;
    write_gltf(os, mesh, nullptr, glb);
    const std::string written = os.str();
    const Mesh back = read_gltf(written, glb ? "back.glb" : "back.gltf", glb);
    if (back.num_vertices() != mesh.num_vertices())
      throw std::logic_error("a written glTF reads back with another vertex count");
  }
}

}  // namespace ffd::fuzz
