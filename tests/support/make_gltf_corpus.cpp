// make_gltf_corpus OBJ FOLDER: writes the OBJ's triangles as glTF in every coding
// (gltf_encode.h) to FOLDER: NAME_plain, NAME_draco (lossless), NAME_draco_lossy
// (edgebreaker, quantized), NAME_meshopt and NAME_quantized, each as .glb and .gltf.
#include <filesystem>
#include <fstream>
#include <iostream>

#include "support/gltf_encode.h"

int main(int argc, char** argv) {
  using namespace ffd::test;
  if (argc != 3) {
    std::cerr << "usage: make_gltf_corpus OBJ FOLDER\n";
    return 2;
  }
  const std::filesystem::path obj = argv[1], folder = argv[2];
  const PlainGeometry g = obj_geometry(obj.string());
  const std::string stem = obj.stem().string();
  struct Kind { GltfCoding coding; bool lossless; std::string name; };
  const Kind kinds[] = {{GltfCoding::Plain, true, "plain"}, {GltfCoding::Draco, true, "draco"},
                        {GltfCoding::Draco, false, "draco_lossy"}, {GltfCoding::Meshopt, true, "meshopt"},
                        {GltfCoding::Quantized, true, "quantized"}};
  for (const Kind& k : kinds)
    for (const bool binary : {true, false}) {
      std::ofstream out(folder / (stem + "_" + k.name + (binary ? ".glb" : ".gltf")), std::ios::binary);
      out << encode_gltf(g, k.coding, binary, DracoOptions{k.lossless});
      if (!out) {
        std::cerr << "make_gltf_corpus: cannot write to " << folder << "\n";
        return 1;
      }
    }
  return 0;
}
