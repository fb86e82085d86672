// The io suite's glTF rows (bench_io.cpp): the same 1M-vertex grid as GLB in each coding
// ffdtool reads (tests/support/gltf_encode.h: plain float, Draco as gltf-transform writes
// it (edgebreaker, 14/10/12-bit quantization), meshopt, KHR_mesh_quantization), each
// read with read_mesh and written back as GLB (plain: ffdtool does not re-encode);
// medians over ctx.repeats, MB/s of the file's bytes and vertices per second, with each
// coding's times as ratios to plain glTF's measured in the same run.
#include <filesystem>

#include "bench.h"
#include "mesh/mesh_io.h"
#include "support/gltf_encode.h"

namespace ffd::bench {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

// The grid as the encoders take it: float positions, normals and UVs, fanned triangles.
test::PlainGeometry plain_geometry(const Mesh& mesh) {
  test::PlainGeometry g;
  const auto pos = mesh.positions();
  const auto nrm = mesh.normals();
  const Eigen::Vector3d lo = pos.rowwise().minCoeff(), hi = pos.rowwise().maxCoeff();
  for (Eigen::Index v = 0; v < pos.cols(); ++v) {
    for (int a = 0; a < 3; ++a) g.positions.push_back(static_cast<float>(pos(a, v)));
    for (int a = 0; a < 3; ++a) g.normals.push_back(static_cast<float>(nrm(a, v)));
    for (int a = 0; a < 2; ++a) g.uvs.push_back(static_cast<float>((pos(a, v) - lo[a]) / std::max(hi[a] - lo[a], 1e-30)));
  }
  std::vector<std::uint32_t> face;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    mesh.face_vertices(f, face);
    for (std::size_t k = 1; k + 1 < face.size(); ++k) g.triangles.insert(g.triangles.end(), {face[0], face[k], face[k + 1]});
  }
  return g;
}

json coding_row(test::GltfCoding coding, const test::PlainGeometry& g, const TempFolder& dir, int repeats) {
  const std::string name = test::coding_name(coding);
  const std::string path = dir.file("grid-" + name + ".glb"), out = dir.file("grid-" + name + "-out.glb");
  write_file(path, test::encode_gltf(g, coding, true, test::DracoOptions{false}));
  Mesh mesh;
  const double read_ms = median_ms(repeats, [&] { mesh = read_mesh(path); });
  const double write_ms = median_ms(repeats, [&] { write_mesh(out, mesh); });
  const double bytes = static_cast<double>(fs::file_size(path)), written = static_cast<double>(fs::file_size(out));
  const double vertices = static_cast<double>(mesh.num_vertices());
  return {{"coding", name},          {"vertices", mesh.num_vertices()},
          {"bytes", bytes},          {"read_ms", read_ms},
          {"read_mb_per_s", mb_per_s(bytes, read_ms)},
          {"read_mvertices_per_s", vertices / read_ms / 1e3},
          {"write_ms", write_ms},    {"write_bytes", written},
          {"write_mb_per_s", mb_per_s(written, write_ms)},
          {"write_mvertices_per_s", vertices / write_ms / 1e3}};
}

}  // namespace

json gltf_coding_rows(const Mesh& mesh, const TempFolder& dir, int repeats) {
  const test::PlainGeometry g = plain_geometry(mesh);
  json rows = json::array();
  for (const test::GltfCoding c : {test::GltfCoding::Plain, test::GltfCoding::Draco, test::GltfCoding::Meshopt,
                                   test::GltfCoding::Quantized}) {
    std::fprintf(stderr, "ffdbench: io: glTF %s, %zu vertices\n", test::coding_name(c), mesh.num_vertices());
    rows.push_back(coding_row(c, g, dir, repeats));
  }
  const double plain_read = rows[0]["read_ms"], plain_write = rows[0]["write_ms"];
  for (json& r : rows) {
    r["read_ms_vs_plain"] = r["read_ms"].get<double>() / plain_read;
    r["write_ms_vs_plain"] = r["write_ms"].get<double>() / plain_write;
  }
  return rows;
}

}  // namespace ffd::bench
