// glTF 2.0 end to end (lib/mesh/gltf_*.cpp through read_mesh and `ffdtool run/info/compare`),
// checked with tinygltf as an independent reader of what ffdtool writes, against the
// Blender-made scene of test_data/gltf (its README.md: Root -> Body -> Nose, Root -> Body2,
// Body2 an instance of Body's mesh, Root's non-uniform scale giving the children shear).
#include <gtest/gtest.h>

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <sys/wait.h>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "mesh/mesh_io.h"
#include "test_meshes.h"

namespace ffd {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using test::expect_one_error_line;
using test::files_in;
using test::quoted;
using test::read_file;
using test::run_tool;
using test::script;
using test::temp_folder;
using test::write_file;

std::string gltf_data(const std::string& name) { return test::data("gltf/" + name); }

// The scene as ffdtool reads it, vertices in depth-first instance order (gltf_read.cpp):
// Body (node 1, 323), then its child Nose (node 0, 24), then Body2 (node 2, 323).
struct Range {
  const char* name;
  std::size_t first, count;
};
constexpr Range kBody{"Body", 0, 323}, kNose{"Nose", 323, 24}, kBody2{"Body2", 347, 323};
constexpr std::size_t kSceneVertices = 670, kSceneTriangles = 1068;

// A B-spline lattice over the scene and a move of its one movable point: every vertex
// moves, Body and Body2 (different places in world space) differently.
const char* const kLattice =
    R"({"op":"lattice","name":"L","basis":"bspline","degree":3,"box":{"fit":"aabb","padding":0.05},"cells":[4,4,4]})";
const char* const kMove =
    R"({"op":"move","lattice":"L","select":{"box":{"min":[0,0,-10],"max":[10,10,10]}},"transform":{"translate":[0.3,0.4,0.1]}})";

bool is_gltf_path(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  return ext == ".glb" || ext == ".gltf";
}

// The error codes Khronos' glTF-Validator reports for a file (tests/gltf/validate.js,
// with the validator scripts/setup.sh installs), each once.
std::set<std::string> validator_errors(const std::string& path) {
  const std::string dir = temp_folder("validator");
  const std::string command = "node " + quoted(std::string(FFD_SOURCE_DIR) + "/tests/gltf/validate.js") + " " +
                              quoted(path) + " >" + quoted(dir + "/report.json") + " 2>" + quoted(dir + "/err");
  const int status = std::system(command.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << path << ": " << read_file(dir + "/err");
  std::set<std::string> codes;
  const json report = json::parse(read_file(dir + "/report.json"), nullptr, false);
  if (report.is_discarded()) {
    ADD_FAILURE() << path << ": the validator printed no report";
    return codes;
  }
  for (const json& message : report["issues"]["messages"])
    if (message["severity"] == 0) codes.insert(message["code"].get<std::string>());
  return codes;
}

// Every glTF ffdtool writes passes the validator with no error its input did not have.
void expect_valid_output(const std::string& input, const std::string& output) {
  const std::set<std::string> out = validator_errors(output);
  if (out.empty()) return;
  const std::set<std::string> in = is_gltf_path(input) ? validator_errors(input) : std::set<std::string>();
  for (const std::string& code : out) EXPECT_TRUE(in.count(code)) << output << ": new validator error " << code;
}

// `ffdtool run MESH SCRIPT -o OUT --quiet`; returns the exit code. A glTF written is held
// against the validator.
int run_ffd(const std::string& mesh, const std::string& script_path, const std::string& out, std::string* err = nullptr,
            const std::string& extra = "--quiet") {
  const int code = run_tool("run " + quoted(mesh) + " " + quoted(script_path) + " -o " + quoted(out) + " " + extra, nullptr, err);
  if (code == 0 && is_gltf_path(out)) expect_valid_output(mesh, out);
  return code;
}

// ---------------------------------------------------------------------------------------
// tinygltf as the independent reader.

bool no_decode(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

tinygltf::Model load(const std::string& path) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(no_decode, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = fs::path(path).extension() == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                                                       : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  EXPECT_TRUE(ok) << "tinygltf cannot read " << path << ": " << err;
  return model;
}

// Substitutes a sparse accessor's values into its `element`-byte elements `out`.
void apply_sparse(const tinygltf::Model& m, const tinygltf::Accessor& a, std::size_t element, std::vector<unsigned char>& out) {
  const auto at = [&](int view, int offset) {
    const tinygltf::BufferView& v = m.bufferViews.at(view);
    return m.buffers.at(v.buffer).data.data() + v.byteOffset + offset;
  };
  const unsigned char* indices = at(a.sparse.indices.bufferView, a.sparse.indices.byteOffset);
  const unsigned char* values = at(a.sparse.values.bufferView, a.sparse.values.byteOffset);
  const std::size_t size = tinygltf::GetComponentSizeInBytes(a.sparse.indices.componentType);
  for (int k = 0; k < a.sparse.count; ++k) {
    std::uint32_t i = 0;
    std::memcpy(&i, indices + k * size, size);
    ASSERT_LT(i, a.count);
    std::memcpy(out.data() + i * element, values + k * element, element);
  }
}

// Accessor `index`'s elements packed one after another (stride removed; zeros when it
// has no bufferView, as glTF says; sparse values substituted).
std::vector<unsigned char> accessor_bytes(const tinygltf::Model& m, int index) {
  const tinygltf::Accessor& a = m.accessors.at(index);
  const std::size_t element = static_cast<std::size_t>(tinygltf::GetComponentSizeInBytes(a.componentType)) *
                              tinygltf::GetNumComponentsInType(a.type);
  std::vector<unsigned char> out(element * a.count, 0);
  if (a.sparse.isSparse && a.bufferView < 0) apply_sparse(m, a, element, out);
  if (a.bufferView < 0) return out;
  const tinygltf::BufferView& view = m.bufferViews.at(a.bufferView);
  const std::vector<unsigned char>& data = m.buffers.at(view.buffer).data;
  const std::size_t stride = view.byteStride ? view.byteStride : element, start = view.byteOffset + a.byteOffset;
  if (a.count && (a.byteOffset + (a.count - 1) * stride + element > view.byteLength ||
                  view.byteOffset + view.byteLength > data.size())) {
    ADD_FAILURE() << "accessor " << index << " runs past its bufferView or buffer";
    return {};
  }
  for (std::size_t i = 0; i < a.count; ++i) std::memcpy(out.data() + i * element, data.data() + start + i * stride, element);
  if (a.sparse.isSparse) apply_sparse(m, a, element, out);
  return out;
}

std::vector<float> accessor_floats(const tinygltf::Model& m, int index) {
  EXPECT_EQ(m.accessors.at(index).componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  const std::vector<unsigned char> bytes = accessor_bytes(m, index);
  std::vector<float> out(bytes.size() / 4);
  if (!out.empty()) std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

std::vector<std::uint32_t> accessor_indices(const tinygltf::Model& m, int index) {
  const int type = m.accessors.at(index).componentType;
  const std::vector<unsigned char> bytes = accessor_bytes(m, index);
  std::vector<std::uint32_t> out;
  const std::size_t size = static_cast<std::size_t>(std::max(0, tinygltf::GetComponentSizeInBytes(type)));
  if (size == 0) {
    ADD_FAILURE() << "accessor " << index << ": not an index type";
    return out;
  }
  for (std::size_t i = 0; i + size <= bytes.size(); i += size) {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + i, size);  // little-endian host, as glTF
    out.push_back(v);
  }
  return out;
}

// A node's local matrix: `matrix` (column-major) or T · R · S, R from the unit quaternion
// (x, y, z, w) written out by hand.
Eigen::Matrix4d node_matrix(const tinygltf::Node& n) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (n.matrix.size() == 16) {
    for (int k = 0; k < 16; ++k) m(k % 4, k / 4) = n.matrix[k];
    return m;
  }
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity(), r = Eigen::Matrix4d::Identity(), s = Eigen::Matrix4d::Identity();
  if (n.translation.size() == 3)
    for (int i = 0; i < 3; ++i) t(i, 3) = n.translation[i];
  if (n.rotation.size() == 4) {
    const double len = std::sqrt(n.rotation[0] * n.rotation[0] + n.rotation[1] * n.rotation[1] +
                                 n.rotation[2] * n.rotation[2] + n.rotation[3] * n.rotation[3]);
    const double x = n.rotation[0] / len, y = n.rotation[1] / len, z = n.rotation[2] / len, w = n.rotation[3] / len;
    r.topLeftCorner<3, 3>() << 1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),  //
        2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),                        //
        2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y);
  }
  if (n.scale.size() == 3)
    for (int i = 0; i < 3; ++i) s(i, i) = n.scale[i];
  return t * r * s;
}

struct Drawn {
  int node = -1, mesh = -1;
  Eigen::Matrix4d world;
};

void walk(const tinygltf::Model& m, int node, const Eigen::Matrix4d& parent, int depth, std::vector<Drawn>& out) {
  ASSERT_LT(depth, 64) << "node hierarchy too deep (a cycle?)";
  const tinygltf::Node& n = m.nodes.at(node);
  const Eigen::Matrix4d world = parent * node_matrix(n);
  if (n.mesh >= 0) out.push_back({node, n.mesh, n.skin >= 0 ? Eigen::Matrix4d::Identity() : world});
  for (int c : n.children) walk(m, c, world, depth + 1, out);
}

// The default scene's nodes with a mesh, depth first, with their world matrices.
std::vector<Drawn> drawn_nodes(const tinygltf::Model& m) {
  std::vector<Drawn> out;
  if (m.scenes.empty()) return out;
  for (int root : m.scenes.at(std::max(m.defaultScene, 0)).nodes) walk(m, root, Eigen::Matrix4d::Identity(), 0, out);
  return out;
}

// Every instance's vertices in world space (one set per distinct POSITION accessor of a
// node), with the triangles on them; `first[i]` is where instance i's vertices start.
struct World {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::size_t> first;
};

World world_scene(const tinygltf::Model& m) {
  World w;
  for (const Drawn& d : drawn_nodes(m)) {
    w.first.push_back(w.positions.size());
    std::map<int, std::size_t> base;  // POSITION accessor -> its first vertex
    for (const tinygltf::Primitive& prim : m.meshes.at(d.mesh).primitives) {
      const int pos = prim.attributes.at("POSITION");
      if (!base.count(pos)) {
        base[pos] = w.positions.size();
        const std::vector<float> f = accessor_floats(m, pos);
        for (std::size_t i = 0; i + 2 < f.size(); i += 3)
          w.positions.push_back((d.world * Eigen::Vector4d(f[i], f[i + 1], f[i + 2], 1.0)).head<3>());
      }
      if (prim.mode != TINYGLTF_MODE_TRIANGLES) continue;  // other modes: see PrimitiveModes
      std::vector<std::uint32_t> idx = prim.indices >= 0 ? accessor_indices(m, prim.indices) : std::vector<std::uint32_t>{};
      if (prim.indices < 0)
        for (std::uint32_t i = 0; i < m.accessors.at(pos).count; ++i) idx.push_back(i);
      for (std::size_t i = 0; i + 2 < idx.size(); i += 3) {
        const auto b = static_cast<std::uint32_t>(base[pos]);
        w.triangles.push_back({b + idx[i], b + idx[i + 1], b + idx[i + 2]});
      }
    }
  }
  return w;
}

// ---------------------------------------------------------------------------------------
// OBJ files, nearest neighbours, comparisons.

// The `v` lines of an OBJ, by `o` object (one unnamed object if there is none).
std::vector<std::pair<std::string, std::vector<Eigen::Vector3d>>> obj_objects(const std::string& path) {
  std::vector<std::pair<std::string, std::vector<Eigen::Vector3d>>> out;
  std::istringstream in(read_file(path));
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("o ", 0) == 0) out.emplace_back(line.substr(2), std::vector<Eigen::Vector3d>{});
    if (line.rfind("v ", 0) != 0) continue;
    if (out.empty()) out.emplace_back("", std::vector<Eigen::Vector3d>{});
    Eigen::Vector3d v;
    EXPECT_EQ(std::sscanf(line.c_str() + 2, "%lf %lf %lf", &v[0], &v[1], &v[2]), 3) << line;
    out.back().second.push_back(v);
  }
  return out;
}

std::vector<Eigen::Vector3d> obj_vertices(const std::string& path) {
  std::vector<Eigen::Vector3d> all;
  for (const auto& [name, v] : obj_objects(path)) all.insert(all.end(), v.begin(), v.end());
  return all;
}

void write_obj(const std::string& path, const World& w) {
  std::string s;
  char buf[128];
  for (const Eigen::Vector3d& p : w.positions) {
    std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    s += buf;
  }
  for (const auto& t : w.triangles)
    s += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
  write_file(path, s);
}

// The largest distance from a point of `from` to its nearest point of `to` (brute force).
double worst_nearest(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to) {
  double worst = 0;
  for (const Eigen::Vector3d& p : from) {
    double best = INFINITY;
    for (const Eigen::Vector3d& q : to) best = std::min(best, (p - q).squaredNorm());
    worst = std::max(worst, std::sqrt(best));
  }
  return worst;
}

std::vector<Eigen::Vector3d> mesh_positions(const Mesh& mesh, std::size_t first, std::size_t count) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t v = first; v < first + count && v < mesh.num_vertices(); ++v) out.push_back(mesh.positions().col(v));
  return out;
}

// Expects a and b equal in size and, vertex by vertex, within float32 rounding of a scene
// of extent `extent`: 4 · 2^-24 · (|coordinate| + extent) per coordinate.
void expect_float32_agreement(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                              double extent, std::size_t first = 0) {
  ASSERT_EQ(a.size(), b.size());
  double worst = 0;
  std::size_t bad = 0;
  for (std::size_t v = 0; v < a.size(); ++v)
    for (int k = 0; k < 3; ++k) {
      const double d = std::abs(a[v][k] - b[v][k]);
      worst = std::max(worst, d);
      if (d > 4 * std::ldexp(1.0, -24) * (std::abs(a[v][k]) + extent) && bad++ < 5)
        ADD_FAILURE() << "vertex " << first + v << " coordinate " << k << ": " << a[v][k] << " vs " << b[v][k];
    }
  EXPECT_EQ(bad, 0u) << "worst difference " << worst;
}

double extent(const std::vector<Eigen::Vector3d>& p) {
  Eigen::Vector3d lo = p.at(0), hi = p.at(0);
  for (const Eigen::Vector3d& v : p) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  return (hi - lo).maxCoeff();
}

// Every POSITION accessor's min and max are those of its data, exactly (as floats).
void expect_position_bounds(const tinygltf::Model& m) {
  std::set<int> positions;
  for (const tinygltf::Mesh& mesh : m.meshes)
    for (const tinygltf::Primitive& prim : mesh.primitives) positions.insert(prim.attributes.at("POSITION"));
  for (int acc : positions) {
    const std::vector<float> f = accessor_floats(m, acc);
    const tinygltf::Accessor& a = m.accessors[acc];
    ASSERT_EQ(a.minValues.size(), 3u) << "accessor " << acc;
    ASSERT_EQ(a.maxValues.size(), 3u) << "accessor " << acc;
    for (int k = 0; k < 3; ++k) {
      float lo = INFINITY, hi = -INFINITY;
      for (std::size_t i = k; i < f.size(); i += 3) lo = std::min(lo, f[i]), hi = std::max(hi, f[i]);
      EXPECT_EQ(a.minValues[k], static_cast<double>(lo)) << "accessor " << acc << " min[" << k << "]";
      EXPECT_EQ(a.maxValues[k], static_cast<double>(hi)) << "accessor " << acc << " max[" << k << "]";
    }
  }
}

// ---------------------------------------------------------------------------------------
// The FFD of the scene, and of an OBJ of its independently computed world positions.

struct FfdRun {
  std::string dir;  // move.json, world.obj, out.glb, out.obj
  int glb_code = -1, obj_code = -1;
  std::string glb_err, obj_err;
};

const FfdRun& ffd_run() {
  static const FfdRun run = [] {
    FfdRun r;
    r.dir = temp_folder("gltf_ffd");
    write_file(r.dir + "/move.json", script({kLattice, kMove}));
    write_obj(r.dir + "/world.obj", world_scene(load(gltf_data("scene.glb"))));
    r.glb_code = run_ffd(gltf_data("scene.glb"), r.dir + "/move.json", r.dir + "/out.glb", &r.glb_err);
    r.obj_code = run_ffd(r.dir + "/world.obj", r.dir + "/move.json", r.dir + "/out.obj", &r.obj_err);
    return r;
  }();
  EXPECT_EQ(run.glb_code, 0) << run.glb_err;
  EXPECT_EQ(run.obj_code, 0) << run.obj_err;
  return run;
}

// ---------------------------------------------------------------------------------------
// 1, 2: reading.

TEST(GltfRead, SceneGlbHasEveryInstanceAndMatchesBlendersWorldObj) {
  const tinygltf::Model model = load(gltf_data("scene.glb"));
  std::size_t drawn = 0;
  for (const Drawn& d : drawn_nodes(model))
    drawn += model.accessors.at(model.meshes.at(d.mesh).primitives.at(0).attributes.at("POSITION")).count;
  EXPECT_EQ(drawn, kSceneVertices) << "24 + 323 + 323: the shared mesh counts once per node";
  const Mesh mesh = read_mesh(gltf_data("scene.glb"));
  ASSERT_EQ(mesh.num_vertices(), kSceneVertices);
  EXPECT_EQ(mesh.num_faces(), kSceneTriangles);
  const auto objects = obj_objects(gltf_data("scene_world.obj"));
  ASSERT_EQ(objects.size(), 3u);
  for (const Range& r : {kBody, kNose, kBody2}) {
    SCOPED_TRACE(r.name);
    const auto it = std::find_if(objects.begin(), objects.end(), [&](const auto& o) { return o.first == r.name; });
    ASSERT_NE(it, objects.end());
    const std::vector<Eigen::Vector3d> ours = mesh_positions(mesh, r.first, r.count);
    EXPECT_LE(worst_nearest(ours, it->second), 1e-5) << "an ffdtool vertex far from every Blender vertex";
    EXPECT_LE(worst_nearest(it->second, ours), 1e-5) << "a Blender vertex far from every ffdtool vertex";
  }
}

// ffdtool's read of `path` against the independent composition of its nodes: the same
// vertices in the same order, to 1e-12 relative.
void expect_reads_as_composed(const std::string& path) {
  SCOPED_TRACE(path);
  const World w = world_scene(load(path));
  const Mesh mesh = read_mesh(path);
  ASSERT_EQ(mesh.num_vertices(), w.positions.size());
  double worst = 0;
  for (std::size_t v = 0; v < w.positions.size(); ++v) {
    const Eigen::Vector3d p = mesh.positions().col(v);
    const double scale = std::max(1.0, w.positions[v].cwiseAbs().maxCoeff());
    worst = std::max(worst, (p - w.positions[v]).cwiseAbs().maxCoeff() / scale);
  }
  EXPECT_LE(worst, 1e-12);
}

TEST(GltfRead, WorldPositionsMatchAnIndependentCompositionOfTheNodes) {
  const World w = world_scene(load(gltf_data("scene.glb")));
  EXPECT_EQ(w.first, (std::vector<std::size_t>{kBody.first, kNose.first, kBody2.first}));
  EXPECT_EQ(w.triangles.size(), kSceneTriangles);
  expect_reads_as_composed(gltf_data("scene.glb"));
  // The scene exercises shear: Body's world matrix is not a rotation times a scale.
  const Eigen::Matrix3d body = drawn_nodes(load(gltf_data("scene.glb"))).at(0).world.topLeftCorner<3, 3>();
  EXPECT_GT(std::abs(body.col(0).normalized().dot(body.col(1).normalized())), 1e-2);
  // ffdtool's faces are the glTF's triangles on the same vertex numbers.
  const auto faces = read_mesh(gltf_data("scene.glb")).faces();
  ASSERT_EQ(faces.size(), w.triangles.size());
  for (std::size_t f = 0; f < faces.size(); ++f)
    ASSERT_EQ(faces[f], std::vector<std::uint32_t>(w.triangles[f].begin(), w.triangles[f].end())) << "face " << f;
}

// ---------------------------------------------------------------------------------------
// 3 - 6: an FFD through the CLI, written back into the scene's structure.

TEST(GltfRun, DeformedGlbMatchesTheSameFfdOfAnObjOfTheWorldPositions) {
  const FfdRun& run = ffd_run();
  const World out = world_scene(load(run.dir + "/out.glb"));
  const std::vector<Eigen::Vector3d> obj = obj_vertices(run.dir + "/out.obj");
  ASSERT_EQ(out.positions.size(), kSceneVertices);
  ASSERT_EQ(obj.size(), kSceneVertices);
  expect_float32_agreement(out.positions, obj, extent(obj));
  // Not vacuous: every part of the scene moved.
  const World in = world_scene(load(gltf_data("scene.glb")));
  EXPECT_EQ(out.triangles, in.triangles);
  for (const Range& r : {kBody, kNose, kBody2}) {
    double moved = 0;
    for (std::size_t v = r.first; v < r.first + r.count; ++v) moved = std::max(moved, (out.positions[v] - in.positions[v]).norm());
    EXPECT_GT(moved, 1e-4) << r.name << " did not move";  // the Nose, near the lattice's edge: 4e-4
  }
}

void expect_same_materials(const tinygltf::Model& in, const tinygltf::Model& out) {
  ASSERT_EQ(out.materials.size(), in.materials.size());
  for (std::size_t i = 0; i < in.materials.size(); ++i) {
    SCOPED_TRACE("material " + std::to_string(i));
    const tinygltf::Material &a = in.materials[i], &b = out.materials[i];
    EXPECT_EQ(b.name, a.name);
    EXPECT_EQ(b.pbrMetallicRoughness.baseColorFactor, a.pbrMetallicRoughness.baseColorFactor);
    EXPECT_EQ(b.pbrMetallicRoughness.baseColorTexture.index, a.pbrMetallicRoughness.baseColorTexture.index);
    EXPECT_EQ(b.pbrMetallicRoughness.metallicFactor, a.pbrMetallicRoughness.metallicFactor);
    EXPECT_EQ(b.pbrMetallicRoughness.roughnessFactor, a.pbrMetallicRoughness.roughnessFactor);
    EXPECT_EQ(b.doubleSided, a.doubleSided);
  }
  EXPECT_EQ(in.materials.at(1).pbrMetallicRoughness.baseColorTexture.index, 0) << "the input is not the README's";
  ASSERT_EQ(out.textures.size(), in.textures.size());
  for (std::size_t i = 0; i < in.textures.size(); ++i) {
    EXPECT_EQ(out.textures[i].sampler, in.textures[i].sampler);
    EXPECT_EQ(out.textures[i].source, in.textures[i].source);
  }
  ASSERT_EQ(out.samplers.size(), in.samplers.size());
  for (std::size_t i = 0; i < in.samplers.size(); ++i) {
    EXPECT_EQ(out.samplers[i].magFilter, in.samplers[i].magFilter);
    EXPECT_EQ(out.samplers[i].minFilter, in.samplers[i].minFilter);
    EXPECT_EQ(out.samplers[i].wrapS, in.samplers[i].wrapS);
    EXPECT_EQ(out.samplers[i].wrapT, in.samplers[i].wrapT);
  }
}

// The bytes of image i's bufferView.
std::vector<unsigned char> image_bytes(const tinygltf::Model& m, std::size_t i) {
  const tinygltf::BufferView& v = m.bufferViews.at(m.images.at(i).bufferView);
  const auto& data = m.buffers.at(v.buffer).data;
  if (v.byteOffset + v.byteLength > data.size()) return {};
  return {data.begin() + v.byteOffset, data.begin() + v.byteOffset + v.byteLength};
}

void expect_same_nodes_and_images(const tinygltf::Model& in, const tinygltf::Model& out) {
  ASSERT_EQ(out.nodes.size(), in.nodes.size());
  for (std::size_t i = 0; i < in.nodes.size(); ++i) {
    SCOPED_TRACE("node " + std::to_string(i));
    const tinygltf::Node &a = in.nodes[i], &b = out.nodes[i];
    EXPECT_EQ(b.name, a.name);
    EXPECT_EQ(b.children, a.children);
    EXPECT_EQ(b.translation, a.translation);
    EXPECT_EQ(b.rotation, a.rotation);
    EXPECT_EQ(b.scale, a.scale);
    EXPECT_EQ(b.matrix, a.matrix);
  }
  ASSERT_TRUE(out.nodes[0].extras.Has("ffd_tag")) << "Nose's extras were lost";
  EXPECT_EQ(out.nodes[0].extras.Get("ffd_tag").Get<std::string>(), "nose");
  EXPECT_EQ(out.scenes.size(), in.scenes.size());
  EXPECT_EQ(out.scenes.at(0).nodes, in.scenes.at(0).nodes);
  ASSERT_EQ(out.images.size(), in.images.size());
  for (std::size_t i = 0; i < in.images.size(); ++i) {
    EXPECT_EQ(out.images[i].name, in.images[i].name);
    EXPECT_EQ(out.images[i].mimeType, in.images[i].mimeType);
    const auto bytes = image_bytes(out, i);
    EXPECT_EQ(bytes.size(), 122u);
    EXPECT_TRUE(bytes == image_bytes(in, i)) << "image " << i << "'s bytes changed";
  }
}

// Each output mesh's source: the input mesh of the same index, or (a split copy) the one
// with its name.
int source_mesh(const tinygltf::Model& in, const tinygltf::Model& out, std::size_t k) {
  if (k < in.meshes.size()) return static_cast<int>(k);
  for (std::size_t j = 0; j < in.meshes.size(); ++j)
    if (in.meshes[j].name == out.meshes[k].name) return static_cast<int>(j);
  return -1;
}

TEST(GltfRun, KeepsTheStructureBitForBit) {
  const tinygltf::Model in = load(gltf_data("scene.glb")), out = load(ffd_run().dir + "/out.glb");
  expect_same_nodes_and_images(in, out);
  expect_same_materials(in, out);
  EXPECT_EQ(out.asset.version, "2.0");
  for (std::size_t k = 0; k < out.meshes.size(); ++k) {
    SCOPED_TRACE("mesh " + std::to_string(k));
    const int s = source_mesh(in, out, k);
    ASSERT_GE(s, 0);
    ASSERT_EQ(out.meshes[k].primitives.size(), in.meshes[s].primitives.size());
    for (std::size_t p = 0; p < in.meshes[s].primitives.size(); ++p) {
      const tinygltf::Primitive &a = in.meshes[s].primitives[p], &b = out.meshes[k].primitives[p];
      EXPECT_EQ(b.material, a.material);
      EXPECT_EQ(b.mode, a.mode);
      EXPECT_TRUE(accessor_bytes(out, b.attributes.at("TEXCOORD_0")) == accessor_bytes(in, a.attributes.at("TEXCOORD_0")));
      EXPECT_TRUE(accessor_bytes(out, b.indices) == accessor_bytes(in, a.indices));
      EXPECT_EQ(out.accessors.at(b.indices).componentType, in.accessors.at(a.indices).componentType);
    }
  }
  expect_position_bounds(out);
}

TEST(GltfRun, ALatticeThatMovesNothingWritesTheInputsDataBackUnchanged) {
  const std::string dir = temp_folder("gltf_identity");
  write_file(dir + "/lattice.json", script({kLattice}));
  std::string err;
  ASSERT_EQ(run_ffd(gltf_data("scene.glb"), dir + "/lattice.json", dir + "/out.glb", &err), 0) << err;
  const tinygltf::Model in = load(gltf_data("scene.glb")), out = load(dir + "/out.glb");
  ASSERT_EQ(out.meshes.size(), in.meshes.size()) << "an unchanged instance was split";
  EXPECT_EQ(out.accessors.size(), in.accessors.size());
  EXPECT_EQ(out.nodes.at(1).mesh, 1);
  EXPECT_EQ(out.nodes.at(2).mesh, 1) << "Body and Body2 no longer share their mesh";
  for (std::size_t k = 0; k < in.meshes.size(); ++k)
    for (std::size_t p = 0; p < in.meshes[k].primitives.size(); ++p)
      for (const char* name : {"POSITION", "NORMAL"}) {
        const int a = in.meshes[k].primitives[p].attributes.at(name);
        ASSERT_EQ(out.meshes[k].primitives.at(p).attributes.at(name), a);
        EXPECT_TRUE(accessor_bytes(out, a) == accessor_bytes(in, a)) << "mesh " << k << " " << name << " changed";
      }
}

TEST(GltfRun, AnInstanceDeformedDifferentlyGetsItsOwnMesh) {
  const FfdRun& run = ffd_run();
  const tinygltf::Model out = load(run.dir + "/out.glb");
  ASSERT_EQ(out.meshes.size(), 3u);
  EXPECT_EQ(out.nodes.at(0).mesh, 0);
  EXPECT_EQ(out.nodes.at(1).mesh, 1);
  ASSERT_EQ(out.nodes.at(2).mesh, 2) << "Body2 should refer to a copy of BodyMesh";
  const tinygltf::Primitive &body = out.meshes[1].primitives.at(0), &copy = out.meshes[2].primitives.at(0);
  EXPECT_EQ(out.meshes[2].name, out.meshes[1].name);
  EXPECT_EQ(copy.material, body.material);
  EXPECT_EQ(copy.attributes.at("TEXCOORD_0"), body.attributes.at("TEXCOORD_0"));
  EXPECT_EQ(copy.indices, body.indices);
  EXPECT_NE(copy.attributes.at("POSITION"), body.attributes.at("POSITION"));
  EXPECT_NE(copy.attributes.at("NORMAL"), body.attributes.at("NORMAL"));
  EXPECT_EQ(out.accessors.at(copy.attributes.at("POSITION")).count, 323u);
  const World w = world_scene(out);
  const std::vector<Eigen::Vector3d> obj = obj_vertices(run.dir + "/out.obj");
  ASSERT_EQ(w.positions.size(), obj.size());
  for (const Range& r : {kBody, kBody2}) {
    SCOPED_TRACE(r.name);
    using Points = std::vector<Eigen::Vector3d>;
    expect_float32_agreement(Points(w.positions.begin() + r.first, w.positions.begin() + r.first + r.count),
                             Points(obj.begin() + r.first, obj.begin() + r.first + r.count), extent(obj), r.first);
  }
}

TEST(GltfRun, AnInstanceTheDeformationMissesKeepsItsOwnData) {
  // A lattice around Body and Nose only (Body2 lies at x <= -0.23): Body's mesh data is
  // replaced in place, and Body2, now disagreeing, must get a copy of the source's data.
  const std::string dir = temp_folder("gltf_missed_instance");
  write_file(dir + "/local.json",
             script({R"({"op":"lattice","name":"L","basis":"bspline","degree":3,"box":{"min":[0.1,-3,-3],"max":[3.5,3,3]},"cells":[4,4,4]})",
                     R"({"op":"move","lattice":"L","select":{"box":{"min":[-10,-10,-10],"max":[10,10,10]}},"transform":{"translate":[0.3,0.4,0.1]}})"}));
  std::string err;
  ASSERT_EQ(run_ffd(gltf_data("scene.glb"), dir + "/local.json", dir + "/out.glb", &err), 0) << err;
  const tinygltf::Model in = load(gltf_data("scene.glb")), out = load(dir + "/out.glb");
  ASSERT_EQ(out.meshes.size(), 3u);
  ASSERT_EQ(out.nodes.at(2).mesh, 2);
  const World a = world_scene(in), b = world_scene(out);
  ASSERT_EQ(b.positions.size(), kSceneVertices);
  EXPECT_NE(b.positions[kBody.first], a.positions[kBody.first]) << "Body did not move";
  for (std::size_t v = kBody2.first; v < kBody2.first + kBody2.count; ++v)
    ASSERT_EQ(b.positions[v], a.positions[v]) << "Body2 vertex " << v - kBody2.first << " moved, outside the lattice";
  for (const char* name : {"POSITION", "NORMAL"})
    EXPECT_TRUE(accessor_bytes(out, out.meshes[2].primitives.at(0).attributes.at(name)) ==
                accessor_bytes(in, in.meshes[1].primitives.at(0).attributes.at(name)))
        << "Body2's copy of " << name << " is not the source's data";
}

// ---------------------------------------------------------------------------------------
// 7: .gltf with an external buffer and image.

std::string copy_separate(const std::string& dir, const std::string& gltf_name = "scene_separate.gltf") {
  fs::copy_file(gltf_data("scene_separate.gltf"), dir + "/" + gltf_name);
  for (const char* f : {"scene_separate.bin", "checker.png"}) fs::copy_file(gltf_data(f), dir + "/" + f);
  return dir + "/" + gltf_name;
}

TEST(GltfRun, SeparateGltfReadsAsTheGlbAndWritesItsBufferAndImageBesideTheOutput) {
  const std::string in = temp_folder("gltf_sep_in"), other = temp_folder("gltf_sep_out");
  const std::string input = copy_separate(in);
  const Mesh a = read_mesh(input), b = read_mesh(gltf_data("scene.glb"));
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  EXPECT_TRUE(a.positions() == b.positions()) << "the .gltf and the .glb read differently";
  std::string err;
  ASSERT_EQ(run_ffd(input, ffd_run().dir + "/move.json", other + "/out.gltf", &err), 0) << err;
  EXPECT_EQ(files_in(other), (std::set<std::string>{"out.gltf", "out.bin", "checker.png"}));
  EXPECT_EQ(read_file(other + "/checker.png"), read_file(gltf_data("checker.png")));
  const json j = json::parse(read_file(other + "/out.gltf"));
  ASSERT_EQ(j.at("buffers").size(), 1u);
  EXPECT_EQ(j["buffers"][0].value("uri", ""), "out.bin");
  EXPECT_EQ(j["images"][0].value("uri", ""), "checker.png");
  EXPECT_EQ(files_in(in), (std::set<std::string>{"scene_separate.gltf", "scene_separate.bin", "checker.png"}));
  EXPECT_EQ(read_file(in + "/scene_separate.bin"), read_file(gltf_data("scene_separate.bin")));
  const World gltf = world_scene(load(other + "/out.gltf")), glb = world_scene(load(ffd_run().dir + "/out.glb"));
  ASSERT_EQ(gltf.positions.size(), kSceneVertices);
  EXPECT_TRUE(gltf.positions == glb.positions) << "out.gltf and out.glb hold different positions";
}

TEST(GltfRun, AnOutputWhoseBufferWouldReplaceTheInputsIsRefused) {
  const std::string dir = temp_folder("gltf_replace");
  const std::string input = copy_separate(dir, "a.gltf");
  std::string err;
  EXPECT_EQ(run_ffd(input, ffd_run().dir + "/move.json", dir + "/scene_separate.gltf", &err), 2);
  expect_one_error_line(err, {"would replace", "scene_separate.bin"});
  EXPECT_EQ(read_file(dir + "/scene_separate.bin"), read_file(gltf_data("scene_separate.bin")));
  EXPECT_EQ(files_in(dir), (std::set<std::string>{"a.gltf", "scene_separate.bin", "checker.png"}));
}

// ---------------------------------------------------------------------------------------
// 8: malformed input.

struct BadGltf {
  std::string name;
  std::function<std::string(const std::string& dir)> make;  // writes the input, returns its path
  std::vector<std::string> mentions;
};

using SceneEdit = std::function<void(json& j, std::string& bin)>;

// Writes DIR/NAME: the separate scene's JSON and its .bin (still named scene_separate.bin)
// after `edit`, with checker.png beside them; returns the path.
std::string edited_scene(const std::string& dir, const std::string& name, const SceneEdit& edit) {
  json j = json::parse(read_file(gltf_data("scene_separate.gltf")));
  std::string bin = read_file(gltf_data("scene_separate.bin"));
  edit(j, bin);
  write_file(dir + "/scene_separate.bin", bin);
  fs::copy_file(gltf_data("checker.png"), dir + "/checker.png", fs::copy_options::overwrite_existing);
  write_file(dir + "/" + name, j.dump(1));
  return dir + "/" + name;
}

std::function<std::string(const std::string&)> edited_gltf(const std::string& name, std::function<void(json&)> edit) {
  return [=](const std::string& dir) { return edited_scene(dir, name, [&](json& j, std::string&) { edit(j); }); };
}

// Appends `bytes` to the .bin as a new bufferView (4-byte aligned, `stride` if not 0);
// returns the view's index.
std::size_t append_view(json& j, std::string& bin, const std::string& bytes, std::size_t stride = 0) {
  bin.resize((bin.size() + 3) / 4 * 4, '\0');
  j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}});
  if (stride) j["bufferViews"].back()["byteStride"] = stride;
  bin += bytes;
  j["buffers"][0]["byteLength"] = bin.size();
  return j["bufferViews"].size() - 1;
}

template <typename T>
std::string bytes_of(const std::vector<T>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), sizeof(T) * values.size());
}

// Appends `values` as a new bufferView and a float accessor of `type` (`count`
// elements); returns the accessor's index.
std::size_t append_floats(json& j, std::string& bin, const std::vector<float>& values, const std::string& type,
                          std::size_t count) {
  const std::size_t view = append_view(j, bin, bytes_of(values));
  j["accessors"].push_back({{"bufferView", view}, {"componentType", TINYGLTF_COMPONENT_TYPE_FLOAT}, {"count", count}, {"type", type}});
  return j["accessors"].size() - 1;
}

// Appends unsigned short indices as a new bufferView and SCALAR accessor; returns its index.
std::size_t append_indices(json& j, std::string& bin, const std::vector<std::uint16_t>& values) {
  const std::size_t view = append_view(j, bin, bytes_of(values));
  j["accessors"].push_back({{"bufferView", view}, {"componentType", TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
                            {"count", values.size()}, {"type", "SCALAR"}});
  return j["accessors"].size() - 1;
}

std::function<std::string(const std::string&)> edited_glb(const std::string& name, std::function<void(std::string&)> edit) {
  return [=](const std::string& dir) {
    std::string bytes = read_file(gltf_data("scene.glb"));
    edit(bytes);
    write_file(dir + "/" + name, bytes);
    return dir + "/" + name;
  };
}

// In a GLB's bytes, sets index 0 of mesh 0's index accessor to `value` (UNSIGNED_SHORT).
void set_first_nose_index(std::string& glb, std::uint16_t value) {
  std::uint32_t json_length = 0;
  std::memcpy(&json_length, glb.data() + 12, 4);
  const json j = json::parse(glb.substr(20, json_length));
  const json& acc = j["accessors"][j["meshes"][0]["primitives"][0]["indices"].get<int>()];
  ASSERT_EQ(acc["componentType"], TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  const json& view = j["bufferViews"][acc["bufferView"].get<int>()];
  const std::size_t at = 20 + json_length + 8 + view.value("byteOffset", 0) + acc.value("byteOffset", 0);
  ASSERT_LE(at + 2, glb.size());
  std::memcpy(&glb[at], &value, 2);
}

std::vector<BadGltf> bad_inputs() {
  return {
      {"GLB cut to 100 bytes", edited_glb("cut100.glb", [](std::string& b) { b.resize(100); }),
       {"cut100.glb", "not a valid glTF binary"}},
      {"GLB without its last 1000 bytes", edited_glb("short.glb", [](std::string& b) { b.resize(b.size() - 1000); }),
       {"short.glb", "not a valid glTF binary"}},
      {"GLB JSON chunk not JSON", edited_glb("notjson.glb", [](std::string& b) { b[b.find('{', 20)] = 'x'; }),
       {"notjson.glb", "not a valid glTF binary"}},
      {"accessor count past its bufferView",
       edited_gltf("count.gltf", [](json& j) { j["accessors"][0]["count"] = 100000; }), {"count.gltf", "accessor 0", "run past"}},
      {"index out of range", edited_glb("index.glb", [](std::string& b) { set_first_nose_index(b, 60000); }),
       {"index.glb", "accessor 3", "past the primitive"}},
      {"Draco data that does not decode", edited_gltf("draco.gltf", [](json& j) {
         j["extensionsUsed"] = {"KHR_draco_mesh_compression"};
         j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
         j["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"] = {
             {"bufferView", 0}, {"attributes", {{"POSITION", 0}}}};
       }),
       {"draco.gltf", "mesh 0 primitive 0 (KHR_draco_mesh_compression)", "does not decode"}},
      {"node cycle", edited_gltf("cycle.gltf", [](json& j) { j["nodes"][0]["children"] = {3}; }),
       {"cycle.gltf", "reached twice"}},
  };
}

TEST(GltfRun, MalformedInputExitsTwoWithOneLineAndWritesNothing) {
  const std::string script_path = ffd_run().dir + "/move.json";
  for (const BadGltf& c : bad_inputs()) {
    SCOPED_TRACE(c.name);
    const std::string in = temp_folder("gltf_bad_in"), out = temp_folder("gltf_bad_out");
    const std::string input = c.make(in);
    std::string err;
    EXPECT_EQ(run_ffd(input, script_path, out + "/out.glb", &err, "--stats " + quoted(out + "/stats.json")), 2) << err;
    expect_one_error_line(err, c.mentions);
    EXPECT_NE(err.find(input), std::string::npos) << "the message does not name the file: " << err;
    EXPECT_TRUE(files_in(out).empty()) << "files were written";
    std::string info_err;
    EXPECT_EQ(run_tool("info " + quoted(input), nullptr, &info_err), 2);
    expect_one_error_line(info_err, c.mentions);
  }
}

// ---------------------------------------------------------------------------------------
// 9 - 11: other sources, info, remesh.

TEST(GltfRun, AnObjBecomesAOnePrimitiveGlb) {
  const std::string glb_dir = temp_folder("gltf_from_obj_glb"), obj_dir = temp_folder("gltf_from_obj_obj");
  std::string err;
  ASSERT_EQ(run_ffd(test::data("bunny.obj"), test::data("demo.json"), glb_dir + "/out.glb", &err), 0) << err;
  ASSERT_EQ(run_ffd(test::data("bunny.obj"), test::data("demo.json"), obj_dir + "/out.obj", &err), 0) << err;
  std::string report;
  EXPECT_EQ(run_tool("compare " + quoted(obj_dir + "/out.obj") + " " + quoted(glb_dir + "/out.glb") + " --tolerance 1e-5", &report), 0)
      << report;
  const tinygltf::Model m = load(glb_dir + "/out.glb");
  EXPECT_EQ(m.nodes.size(), 1u);
  ASSERT_EQ(m.meshes.size(), 1u);
  ASSERT_EQ(m.meshes[0].primitives.size(), 1u);
  const Mesh bunny = test::bunny();
  const tinygltf::Primitive& prim = m.meshes[0].primitives[0];
  EXPECT_EQ(m.accessors.at(prim.attributes.at("POSITION")).count, bunny.num_vertices());
  EXPECT_EQ(accessor_indices(m, prim.indices).size(), 3 * bunny.num_faces());
  expect_position_bounds(m);
  // And the bounds are the deformed bunny's.
  const std::vector<Eigen::Vector3d> obj = obj_vertices(obj_dir + "/out.obj");
  const tinygltf::Accessor& pos = m.accessors.at(prim.attributes.at("POSITION"));
  ASSERT_EQ(pos.minValues.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    double lo = INFINITY, hi = -INFINITY;
    for (const Eigen::Vector3d& v : obj) lo = std::min(lo, v[k]), hi = std::max(hi, v[k]);
    EXPECT_NEAR(pos.minValues[k], lo, 1e-5);
    EXPECT_NEAR(pos.maxValues[k], hi, 1e-5);
  }
}

TEST(GltfInfo, JsonHasTheScenesCounts) {
  std::string out, err;
  ASSERT_EQ(run_tool("info " + quoted(gltf_data("scene.glb")) + " --json", &out, &err), 0) << err;
  const json j = json::parse(out);
  ASSERT_TRUE(j.contains("gltf")) << out;
  const json& g = j["gltf"];
  EXPECT_EQ(g["nodes"], 4);
  EXPECT_EQ(g["meshes"], 2);
  EXPECT_EQ(g["instances"], 3);
  EXPECT_EQ(g["primitives"], 3);
  EXPECT_EQ(g["materials"], 2);
  EXPECT_EQ(g["textures"], 1);
  EXPECT_EQ(g["images"], 1);
  EXPECT_EQ(g["binary"], true);
  EXPECT_EQ(j["vertices"], kSceneVertices);
  ASSERT_EQ(run_tool("info " + quoted(gltf_data("scene_separate.gltf")) + " --json", &out, &err), 0) << err;
  EXPECT_EQ(json::parse(out)["gltf"]["binary"], false);
  ASSERT_EQ(run_tool("info " + quoted(test::data("bunny.obj")) + " --json", &out, &err), 0) << err;
  EXPECT_FALSE(json::parse(out).contains("gltf"));
}

TEST(GltfRun, RemeshWritesOnePlainPrimitiveAndWarns) {
  const std::string dir = temp_folder("gltf_remesh");
  write_file(dir + "/remesh.json", script({kLattice, kMove, R"({"op":"remesh"})"}));
  std::string err;
  ASSERT_EQ(run_ffd(gltf_data("scene.glb"), dir + "/remesh.json", dir + "/out.glb", &err, ""), 0) << err;
  EXPECT_NE(err.find("warning"), std::string::npos) << err;
  EXPECT_NE(err.find("connectivity"), std::string::npos) << err;
  const tinygltf::Model m = load(dir + "/out.glb");
  EXPECT_EQ(m.nodes.size(), 1u);
  ASSERT_EQ(m.meshes.size(), 1u);
  ASSERT_EQ(m.meshes[0].primitives.size(), 1u);
  const tinygltf::Primitive& prim = m.meshes[0].primitives[0];
  EXPECT_GT(m.accessors.at(prim.attributes.at("POSITION")).count, kSceneVertices) << "remesh refined nothing";
  EXPECT_GT(accessor_indices(m, prim.indices).size(), 3 * kSceneTriangles);
  expect_position_bounds(m);
  const Mesh written = read_mesh(dir + "/out.glb");
  EXPECT_EQ(written.num_vertices(), m.accessors.at(prim.attributes.at("POSITION")).count);
}

// ---------------------------------------------------------------------------------------
// Morph targets and skins: kept as data, the base shape / bind pose deformed.

// The separate scene with a morph target on the Nose (24 new float VEC3 offsets appended
// to the .bin) and its weight; returns the path, and the target's bytes in *target.
std::string morph_scene(const std::string& dir, std::string* target) {
  std::vector<float> offsets(72);
  for (std::size_t i = 0; i < offsets.size(); ++i) offsets[i] = 0.001f * static_cast<float>(i % 7) - 0.002f;
  *target = bytes_of(offsets);
  return edited_scene(dir, "morph.gltf", [&](json& j, std::string& bin) {
    const std::size_t acc = append_floats(j, bin, offsets, "VEC3", 24);
    j["accessors"][acc]["min"] = {-0.002f, -0.002f, -0.002f};
    j["accessors"][acc]["max"] = {0.004f, 0.004f, 0.004f};
    j["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", acc}}};
    j["meshes"][0]["weights"] = {0.5};
  });
}

TEST(GltfRun, MorphTargetsAreNotedAndKept) {
  const std::string dir = temp_folder("gltf_morph"), out_dir = temp_folder("gltf_morph_out");
  std::string target, out, err;
  const std::string input = morph_scene(dir, &target);
  ASSERT_EQ(run_tool("info " + quoted(input), &out, &err), 0) << err;
  EXPECT_NE(out.find("morph targets"), std::string::npos) << out;
  ASSERT_EQ(run_ffd(input, ffd_run().dir + "/move.json", out_dir + "/out.glb", &err, ""), 0) << err;
  EXPECT_NE(err.find("morph targets"), std::string::npos) << err;
  const tinygltf::Model m = load(out_dir + "/out.glb");
  ASSERT_EQ(m.meshes.at(0).primitives.at(0).targets.size(), 1u);
  const int acc = m.meshes[0].primitives[0].targets[0].at("POSITION");
  const std::vector<unsigned char> bytes = accessor_bytes(m, acc);
  EXPECT_EQ(std::string(bytes.begin(), bytes.end()), target) << "the target's offsets changed";
  EXPECT_EQ(m.meshes[0].weights, std::vector<double>{0.5});
  EXPECT_EQ(world_scene(m).positions.size(), kSceneVertices);
}

TEST(GltfRead, ASkinnedNodeIsReadInBindPoseAndItsSkinKept) {
  const std::string dir = temp_folder("gltf_skin"), out_dir = temp_folder("gltf_skin_out");
  const std::string input = edited_gltf("skin.gltf", [](json& j) {
    j["skins"] = {{{"joints", {3}}}};
    j["nodes"][0]["skin"] = 0;
  })(dir);
  const Mesh mesh = read_mesh(input);
  const tinygltf::Model in = load(input);
  const std::vector<float> local = accessor_floats(in, 0);  // the Nose's POSITION
  ASSERT_EQ(local.size(), 3 * kNose.count);
  for (std::size_t i = 0; i < kNose.count; ++i)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(mesh.positions()(k, kNose.first + i), static_cast<double>(local[3 * i + k])) << "vertex " << i;
  std::string out, err;
  ASSERT_EQ(run_tool("info " + quoted(input), &out, &err), 0) << err;
  EXPECT_NE(out.find("skinned"), std::string::npos) << out;
  ASSERT_EQ(run_ffd(input, ffd_run().dir + "/move.json", out_dir + "/out.glb", &err), 0) << err;
  const tinygltf::Model m = load(out_dir + "/out.glb");
  ASSERT_EQ(m.skins.size(), 1u);
  EXPECT_EQ(m.skins[0].joints, std::vector<int>{3});
  EXPECT_EQ(m.nodes.at(0).skin, 0);
}

// The separate scene with extensions, extras and an animation (Root's rotation over two
// keys, its data appended to the .bin) on objects the deformation does not touch.
std::string decorated_scene(const std::string& dir) {
  return edited_scene(dir, "decorated.gltf", [](json& j, std::string& bin) {
    j["extensionsUsed"] = {"KHR_materials_emissive_strength", "EXT_ffd_test_vendor"};
    j["materials"][0]["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", 2.5}}}};
    j["nodes"][3]["extensions"] = {{"EXT_ffd_test_vendor", {{"k", {1, 2, 3}}}}};
    j["scenes"][0]["extras"] = {{"author", "test"}, {"list", {1, 2.5, "x", {{"deep", true}}}}};
    j["meshes"][1]["extras"] = {{"lod", 0}};
    const std::size_t times = append_floats(j, bin, {0.0f, 1.0f}, "SCALAR", 2);
    j["accessors"][times]["min"] = {0.0};
    j["accessors"][times]["max"] = {1.0};
    const std::size_t poses = append_floats(j, bin, {0, 0, 0, 1, 0, 0.7071068f, 0, 0.7071068f}, "VEC4", 2);
    j["animations"] = {{{"name", "Spin"},
                        {"samplers", {{{"input", times}, {"output", poses}, {"interpolation", "LINEAR"}}}},
                        {"channels", {{{"sampler", 0}, {"target", {{"node", 3}, {"path", "rotation"}}}}}}}};
  });
}

// The JSON chunk of a GLB.
json glb_json(const std::string& path) {
  const std::string glb = read_file(path);
  std::uint32_t length = 0;
  if (glb.size() >= 20) std::memcpy(&length, glb.data() + 12, 4);
  return json::parse(glb.substr(20, length));
}

TEST(GltfRun, ExtensionsExtrasAndAnimationsAreKept) {
  const std::string dir = temp_folder("gltf_decorated"), out_dir = temp_folder("gltf_decorated_out");
  const std::string input = decorated_scene(dir);
  std::string out, err;
  ASSERT_EQ(run_tool("info " + quoted(input) + " --json", &out, &err), 0) << err;
  EXPECT_EQ(json::parse(out)["gltf"]["animations"], 1);
  ASSERT_EQ(run_ffd(input, ffd_run().dir + "/move.json", out_dir + "/out.glb", &err), 0) << err;
  const json a = json::parse(read_file(input)), b = glb_json(out_dir + "/out.glb");
  EXPECT_EQ(b["extensionsUsed"], a["extensionsUsed"]);
  EXPECT_EQ(b["materials"][0]["extensions"], a["materials"][0]["extensions"]);
  EXPECT_EQ(b["nodes"][3]["extensions"], a["nodes"][3]["extensions"]);
  EXPECT_EQ(b["scenes"][0]["extras"], a["scenes"][0]["extras"]);
  EXPECT_EQ(b["meshes"][1]["extras"], a["meshes"][1]["extras"]);
  EXPECT_EQ(b["animations"], a["animations"]);
  const tinygltf::Model in = load(input), m = load(out_dir + "/out.glb");
  ASSERT_EQ(m.animations.size(), 1u);
  for (const tinygltf::AnimationSampler& s : m.animations[0].samplers) {
    EXPECT_TRUE(accessor_bytes(m, s.input) == accessor_bytes(in, s.input));
    EXPECT_TRUE(accessor_bytes(m, s.output) == accessor_bytes(in, s.output));
  }
}

// ---------------------------------------------------------------------------------------
// Layouts and scenes the Blender file does not have, made by editing a copy of it.

// Runs `script_path` on `input` (-> DIR/out.glb) and on an OBJ of its independently
// composed world positions (-> DIR/out.obj); the two results agree to float32 precision.
void expect_same_ffd_as_obj(const std::string& input, const std::string& script_path, const std::string& dir) {
  SCOPED_TRACE(input);
  write_obj(dir + "/world.obj", world_scene(load(input)));
  std::string err;
  ASSERT_EQ(run_ffd(input, script_path, dir + "/out.glb", &err), 0) << err;
  ASSERT_EQ(run_ffd(dir + "/world.obj", script_path, dir + "/out.obj", &err), 0) << err;
  const std::vector<Eigen::Vector3d> obj = obj_vertices(dir + "/out.obj");
  const tinygltf::Model out = load(dir + "/out.glb");
  expect_float32_agreement(world_scene(out).positions, obj, extent(obj));
  expect_position_bounds(out);
}

World out_glb_world() { return world_scene(load(ffd_run().dir + "/out.glb")); }

TEST(GltfRun, PrimitivesSharingPositionsAreOneSetOfVertices) {
  const std::string dir = temp_folder("gltf_two_prims");
  const std::string input = edited_gltf("two.gltf", [](json& j) {  // BodyMesh's triangles in two primitives
    json& prims = j["meshes"][1]["primitives"];
    const int acc = prims[0]["indices"].get<int>(), count = j["accessors"][acc]["count"].get<int>(), half = count / 6 * 3;
    json second = j["accessors"][acc];
    second["byteOffset"] = second.value("byteOffset", 0) + 2 * half;
    second["count"] = count - half;
    j["accessors"][acc]["count"] = half;
    j["accessors"].push_back(second);
    prims.push_back(prims[0]);
    prims[1]["indices"] = j["accessors"].size() - 1;
  })(dir);
  const Mesh mesh = read_mesh(input);
  ASSERT_EQ(mesh.num_vertices(), kSceneVertices);
  EXPECT_EQ(mesh.num_faces(), kSceneTriangles);
  EXPECT_TRUE(mesh.positions() == read_mesh(gltf_data("scene.glb")).positions());
  std::string err;
  ASSERT_EQ(run_ffd(input, ffd_run().dir + "/move.json", dir + "/out.glb", &err), 0) << err;
  const tinygltf::Model out = load(dir + "/out.glb");
  ASSERT_EQ(out.meshes.size(), 3u);
  for (int k : {1, 2}) {
    ASSERT_EQ(out.meshes[k].primitives.size(), 2u);
    EXPECT_EQ(out.meshes[k].primitives[0].attributes, out.meshes[k].primitives[1].attributes) << "mesh " << k;
  }
  const World w = world_scene(out), base = out_glb_world();
  EXPECT_TRUE(w.positions == base.positions) << "not the deformation of the one-primitive scene";
  EXPECT_EQ(w.triangles, base.triangles);
}

// A sparse POSITION is read with its values substituted; a run that leaves it as it was
// writes it back sparse, as the file has it (a moved one is written dense).
TEST(GltfRun, SparsePositionsAreReadAndKeptSparseWhenUnmoved) {
  const std::string dir = temp_folder("gltf_sparse"), identity = temp_folder("gltf_sparse_identity");
  const std::string input = edited_scene(dir, "sparse.gltf", [](json& j, std::string& bin) {
    const std::size_t indices = append_view(j, bin, bytes_of(std::vector<std::uint16_t>{5}));
    const std::size_t values = append_view(j, bin, bytes_of(std::vector<float>{0.1f, -0.05f, 0.15f}));
    j["accessors"][0]["sparse"] = {{"count", 1},
                                   {"indices", {{"bufferView", indices}, {"componentType", TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT}}},
                                   {"values", {{"bufferView", values}}}};
  });
  expect_reads_as_composed(input);
  const Mesh mesh = read_mesh(input), plain = read_mesh(gltf_data("scene.glb"));
  EXPECT_NE(mesh.positions().col(kNose.first + 5), plain.positions().col(kNose.first + 5)) << "the sparse value was not applied";
  EXPECT_EQ(mesh.positions().col(kNose.first + 4), plain.positions().col(kNose.first + 4));
  write_file(dir + "/lattice.json", script({kLattice}));
  std::string err;
  ASSERT_EQ(run_ffd(input, dir + "/lattice.json", identity + "/out.glb", &err), 0) << err;
  const tinygltf::Model out = load(identity + "/out.glb");
  const int pos = out.meshes.at(0).primitives.at(0).attributes.at("POSITION");
  EXPECT_TRUE(out.accessors.at(pos).sparse.isSparse);
  EXPECT_TRUE(read_mesh(identity + "/out.glb").positions() == mesh.positions()) << "the resolved sparse data changed";
  expect_position_bounds(out);
  expect_same_ffd_as_obj(input, ffd_run().dir + "/move.json", dir);
}

TEST(GltfRun, InterleavedPositionsAndNormalsStayInterleaved) {
  const std::string dir = temp_folder("gltf_interleaved");
  const std::string input = edited_scene(dir, "interleaved.gltf", [](json& j, std::string& bin) {
    const auto data = [&](int acc) {  // accessor acc's 24 VEC3 (tightly packed in the export)
      const json& v = j["bufferViews"][j["accessors"][acc]["bufferView"].get<int>()];
      return bin.substr(v.value("byteOffset", 0) + j["accessors"][acc].value("byteOffset", 0), 12 * 24);
    };
    const std::string p = data(0), n = data(2);  // the Nose's POSITION and NORMAL
    std::string mixed;
    for (std::size_t i = 0; i < 24; ++i) mixed += p.substr(12 * i, 12) + n.substr(12 * i, 12);
    const std::size_t view = append_view(j, bin, mixed, 24);
    j["accessors"][0]["bufferView"] = j["accessors"][2]["bufferView"] = view;
    j["accessors"][0]["byteOffset"] = 0;
    j["accessors"][2]["byteOffset"] = 12;
  });
  EXPECT_TRUE(read_mesh(input).positions() == read_mesh(gltf_data("scene.glb")).positions());
  std::string err;
  ASSERT_EQ(run_ffd(input, ffd_run().dir + "/move.json", dir + "/out.glb", &err), 0) << err;
  const tinygltf::Model out = load(dir + "/out.glb"), base = load(ffd_run().dir + "/out.glb");
  EXPECT_TRUE(world_scene(out).positions == world_scene(base).positions);
  const tinygltf::Primitive& nose = out.meshes.at(0).primitives.at(0);
  const tinygltf::Accessor &p = out.accessors.at(nose.attributes.at("POSITION")), &n = out.accessors.at(nose.attributes.at("NORMAL"));
  EXPECT_EQ(p.bufferView, n.bufferView);
  EXPECT_EQ(out.bufferViews.at(p.bufferView).byteStride, 24);
  EXPECT_TRUE(accessor_bytes(out, nose.attributes.at("NORMAL")) ==
              accessor_bytes(base, base.meshes[0].primitives[0].attributes.at("NORMAL")));
}

TEST(GltfRun, ANodeMatrixIsComposedAndKept) {
  const std::string dir = temp_folder("gltf_matrix"), identity = temp_folder("gltf_matrix_identity");
  const Eigen::Matrix4d root = node_matrix(load(gltf_data("scene.glb")).nodes.at(3));
  const std::string input = edited_gltf("matrix.gltf", [&](json& j) {
    for (const char* key : {"translation", "rotation", "scale"}) j["nodes"][3].erase(key);
    j["nodes"][3]["matrix"] = std::vector<double>(root.data(), root.data() + 16);  // column-major
  })(dir);
  expect_reads_as_composed(input);
  const Mesh a = read_mesh(input), b = read_mesh(gltf_data("scene.glb"));
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  EXPECT_LE((a.positions() - b.positions()).cwiseAbs().maxCoeff(), 1e-12 * 8) << "the matrix is not Root's TRS";
  write_file(dir + "/lattice.json", script({kLattice}));
  std::string err;
  ASSERT_EQ(run_ffd(input, dir + "/lattice.json", identity + "/out.glb", &err), 0) << err;
  EXPECT_EQ(glb_json(identity + "/out.glb")["nodes"][3], json::parse(read_file(input))["nodes"][3]);
  expect_same_ffd_as_obj(input, ffd_run().dir + "/move.json", dir);
}

TEST(GltfRun, OnlyTheDefaultSceneIsReadAndDeformed) {
  const std::string dir = temp_folder("gltf_scenes");
  const std::string input = edited_gltf("scenes.gltf", [](json& j) {
    j["nodes"].push_back({{"name", "Extra"}, {"mesh", 0}, {"translation", {5, 0, 0}}});
    j["scenes"].push_back({{"name", "Second"}, {"nodes", {4}}});
    j["scene"] = 1;
  })(dir);
  const Mesh mesh = read_mesh(input);
  EXPECT_EQ(mesh.num_vertices(), kNose.count) << "only the Extra node's NoseMesh is in scene 1";
  expect_reads_as_composed(input);
  expect_same_ffd_as_obj(input, ffd_run().dir + "/move.json", dir);
  const tinygltf::Model in = load(input), out = load(dir + "/out.glb");
  EXPECT_EQ(out.defaultScene, 1);
  ASSERT_EQ(out.scenes.size(), 2u);
  EXPECT_EQ(out.meshes.size(), 2u);
  for (const char* name : {"POSITION", "NORMAL"}) {
    const int acc = in.meshes[1].primitives[0].attributes.at(name);
    EXPECT_TRUE(accessor_bytes(out, acc) == accessor_bytes(in, acc)) << "BodyMesh, drawn by no node of scene 1, changed";
  }
}

TEST(GltfRun, AGltfWrittenBesideItsInputNeedsNoImageCopy) {
  const std::string dir = temp_folder("gltf_beside");
  const std::string input = copy_separate(dir);
  std::string err;
  ASSERT_EQ(run_ffd(input, ffd_run().dir + "/move.json", dir + "/out.gltf", &err), 0) << err;
  EXPECT_EQ(files_in(dir), (std::set<std::string>{"scene_separate.gltf", "scene_separate.bin", "checker.png", "out.gltf", "out.bin"}));
  EXPECT_EQ(read_file(dir + "/scene_separate.bin"), read_file(gltf_data("scene_separate.bin")));
  EXPECT_TRUE(world_scene(load(dir + "/out.gltf")).positions == out_glb_world().positions);
}

// The Nose's mesh with one more primitive of each other mode on its vertices.
const std::vector<std::pair<int, std::vector<std::uint16_t>>> kModes = {
    {TINYGLTF_MODE_TRIANGLE_STRIP, {0, 1, 2, 3, 4}}, {TINYGLTF_MODE_TRIANGLE_FAN, {5, 6, 7, 8}},
    {TINYGLTF_MODE_LINE, {9, 10, 11, 12}},           {TINYGLTF_MODE_LINE_STRIP, {13, 14, 15}},
    {TINYGLTF_MODE_LINE_LOOP, {16, 17, 18}},         {TINYGLTF_MODE_POINTS, {19, 20, 21}}};

std::string modes_scene(const std::string& dir) {
  return edited_scene(dir, "modes.gltf", [](json& j, std::string& bin) {
    json& prims = j["meshes"][0]["primitives"];
    const json base = prims[0];
    for (const auto& [mode, idx] : kModes) {
      json p = base;
      p["mode"] = mode;
      p["indices"] = append_indices(j, bin, idx);
      prims.push_back(p);
    }
  });
}

// The elements of `kind` in `mesh`, as vertex lists in order.
std::vector<std::vector<std::uint32_t>> elements_of(const Mesh& mesh, ElementKind kind) {
  std::vector<std::vector<std::uint32_t>> out;
  const MeshElements& el = mesh.elements();
  for (std::size_t e = 0; e < el.size(); ++e)
    if (el.kinds[e] == kind) out.emplace_back(el.vertices(e), el.vertices(e) + el.degree(e));
  return out;
}

TEST(GltfRead, StripsFansLinesAndPoints) {
  const std::string dir = temp_folder("gltf_modes");
  const std::string input = modes_scene(dir);
  const Mesh mesh = read_mesh(input);
  ASSERT_EQ(mesh.num_vertices(), kSceneVertices) << "primitives sharing POSITION are one set of vertices";
  ASSERT_EQ(mesh.num_faces(), kSceneTriangles + 3 + 2);
  const std::uint32_t n = kNose.first;
  // glTF 2.0 section 3.7.2.1: strip triangle i = (v_i, v_i+1+i%2, v_i+2-i%2), fan i = (v_i+1, v_i+2, v_0).
  const std::vector<std::vector<std::uint32_t>> extra = {
      {n + 0, n + 1, n + 2}, {n + 1, n + 3, n + 2}, {n + 2, n + 3, n + 4}, {n + 6, n + 7, n + 5}, {n + 7, n + 8, n + 5}};
  const auto faces = mesh.faces();
  for (std::size_t f = 0; f < extra.size(); ++f) EXPECT_EQ(faces.at(528 + 12 + f), extra[f]) << "strip/fan face " << f;
  EXPECT_EQ(elements_of(mesh, ElementKind::Line),
            (std::vector<std::vector<std::uint32_t>>{
                {n + 9, n + 10}, {n + 11, n + 12}, {n + 13, n + 14, n + 15}, {n + 16, n + 17, n + 18, n + 16}}));
  EXPECT_EQ(elements_of(mesh, ElementKind::Point), (std::vector<std::vector<std::uint32_t>>{{n + 19, n + 20, n + 21}}));
  write_file(dir + "/move.json", script({kLattice, kMove}));
  std::string err;
  ASSERT_EQ(run_ffd(input, dir + "/move.json", dir + "/out.glb", &err), 0) << err;
  const tinygltf::Model in = load(input), out = load(dir + "/out.glb");
  ASSERT_EQ(out.meshes.at(0).primitives.size(), kModes.size() + 1);
  for (std::size_t k = 1; k <= kModes.size(); ++k) {
    const tinygltf::Primitive &a = in.meshes[0].primitives[k], &b = out.meshes[0].primitives[k];
    EXPECT_EQ(b.mode, kModes[k - 1].first);
    EXPECT_TRUE(accessor_bytes(out, b.indices) == accessor_bytes(in, a.indices));
    EXPECT_EQ(b.attributes, out.meshes[0].primitives[0].attributes);
  }
  EXPECT_EQ(run_ffd(input, dir + "/move.json", dir + "/out.obj", &err), 0) << err;
  const std::string obj = read_file(dir + "/out.obj");
  EXPECT_NE(obj.find("\nl "), std::string::npos);
  EXPECT_NE(obj.find("\np "), std::string::npos);
}

// ---------------------------------------------------------------------------------------
// Promises of gltf_io.h that the checks above do not reach. A test here that fails names
// the library bug it found ("BUG: ...").

std::string base64(const std::string& bytes) {
  static const char* const digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 2]);
    out += digits[v >> 18 & 63];
    out += digits[v >> 12 & 63];
    out += i + 1 < bytes.size() ? digits[v >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? digits[v & 63] : '=';
  }
  return out;
}

TEST(GltfRun, AnImageEmbeddedAsADataUriIsKept) {
  const std::string dir = temp_folder("gltf_data_image"), out_dir = temp_folder("gltf_data_image_out");
  const std::string png = read_file(gltf_data("checker.png"));
  const std::string input = edited_gltf("embedded.gltf", [&](json& j) {
    j["images"][0]["uri"] = "data:image/png;base64," + base64(png);
  })(dir);
  fs::remove(dir + "/checker.png");
  std::string err;
  ASSERT_EQ(run_ffd(input, ffd_run().dir + "/move.json", out_dir + "/out.glb", &err), 0) << err;
  const json image = glb_json(out_dir + "/out.glb")["images"][0];
  EXPECT_TRUE(image.contains("uri") || image.value("bufferView", -1) >= 0)
      << "BUG (gltf_read.cpp keep_image / gltf_write.cpp): an image given as a data URI is written with neither a uri "
         "nor a valid bufferView, so the texture is lost: "
      << image.dump();
  if (image.contains("uri")) {
    EXPECT_EQ(image["uri"], "data:image/png;base64," + base64(png));
  }
}

TEST(GltfRun, ADataUriBufferStaysEmbeddedBesideExternalOnes) {
  const std::string dir = temp_folder("gltf_mixed_buffers"), out_dir = temp_folder("gltf_mixed_buffers_out");
  const std::string extra = bytes_of(std::vector<float>{0.0f, 0.5f, 1.0f, 2.0f});
  const std::string input = edited_gltf("mixed.gltf", [&](json& j) {
    j["buffers"].push_back({{"byteLength", extra.size()}, {"uri", "data:application/octet-stream;base64," + base64(extra)}});
    j["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", 0}, {"byteLength", extra.size()}});
    j["accessors"].push_back({{"bufferView", j["bufferViews"].size() - 1}, {"componentType", TINYGLTF_COMPONENT_TYPE_FLOAT},
                              {"count", 4}, {"type", "SCALAR"}});
  })(dir);
  std::string err;
  ASSERT_EQ(run_ffd(input, ffd_run().dir + "/move.json", out_dir + "/out.gltf", &err), 0) << err;
  const tinygltf::Model out = load(out_dir + "/out.gltf");
  ASSERT_EQ(out.buffers.size(), 2u);
  EXPECT_EQ(std::string(out.buffers[1].data.begin(), out.buffers[1].data.end()), extra);
  const json j = json::parse(read_file(out_dir + "/out.gltf"));
  EXPECT_EQ(j["buffers"][0]["uri"], "out.bin");
  EXPECT_EQ(j["buffers"][1].value("uri", "").rfind("data:", 0), 0u)
      << "BUG (gltf_write.cpp write_with_companions): gltf_io.h says buffers that were data URIs stay embedded, but "
         "buffer 1 was written as " << j["buffers"][1].value("uri", "");
  EXPECT_EQ(files_in(out_dir), (std::set<std::string>{"out.gltf", "out.bin", "checker.png"}));
}

TEST(GltfRun, APercentEncodedBufferUriIsProtectedFromReplacement) {
  const std::string dir = temp_folder("gltf_percent");
  const std::string input = edited_gltf("a.gltf", [](json& j) { j["buffers"][0]["uri"] = "my%20scene.bin"; })(dir);
  fs::rename(dir + "/scene_separate.bin", dir + "/my scene.bin");
  ASSERT_EQ(read_mesh(input).num_vertices(), kSceneVertices) << "the URI is read decoded";
  std::string err;
  const int code = run_ffd(input, ffd_run().dir + "/move.json", dir + "/my scene.gltf", &err);
  const bool replaced = read_file(dir + "/my scene.bin") != read_file(gltf_data("scene_separate.bin"));
  EXPECT_FALSE(replaced) << "BUG (gltf_read.cpp record_buffers): the buffer URI 'my%20scene.bin' is recorded undecoded, "
                            "so the write of 'my scene.gltf' replaced the input's buffer 'my scene.bin' (exit "
                         << code << ")";
  EXPECT_EQ(code, 2);
  if (code == 2) expect_one_error_line(err, {"would replace"});
}

// The polygons among vertices [first, first + count) whose winding (right hand) points
// against their corners' file normals, and all such polygons.
std::pair<std::size_t, std::size_t> faces_against_normals(const Mesh& mesh, std::size_t first, std::size_t count) {
  const MeshElements& el = mesh.elements();
  std::size_t against = 0, all = 0;
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.kinds[e] != ElementKind::Polygon || el.corners[el.begin(e)] < first || el.corners[el.begin(e)] >= first + count) continue;
    const std::uint32_t c = el.begin(e);
    const Eigen::Vector3d a = mesh.positions().col(el.corners[c]), b = mesh.positions().col(el.corners[c + 1]),
                          d = mesh.positions().col(el.corners[c + 2]);
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for (std::uint32_t k = c; k < el.end(e); ++k)
      if (el.normal(k) >= 0) n += mesh.file_normals()[el.normal(k)];
    against += (b - a).cross(d - a).dot(n) < 0;
    ++all;
  }
  return {against, all};
}

TEST(GltfRead, AMirroredNodesTrianglesStillFaceOutward) {
  const auto plain = faces_against_normals(read_mesh(gltf_data("scene.glb")), kBody2.first, kBody2.count);
  EXPECT_EQ(plain, std::make_pair(std::size_t{0}, std::size_t{528})) << "Blender's windings and normals agree";
  // glTF 2.0 section 3.7.2.1: a node whose world matrix has a negative determinant draws
  // its triangles clockwise; in world space they must be turned to keep facing outward.
  const std::string dir = temp_folder("gltf_mirror");
  const std::string input = edited_gltf("mirror.gltf", [](json& j) { j["nodes"][2]["scale"][0] = -0.8; })(dir);
  const Mesh mesh = read_mesh(input);
  const auto mirrored = faces_against_normals(mesh, kBody2.first, kBody2.count);
  EXPECT_EQ(mirrored.first, 0u) << "BUG (gltf_read.cpp add_elements): the mirrored Body2 (negative determinant) keeps its "
                                   "counter-clockwise winding in world space, so " << mirrored.first << " of its "
                                << mirrored.second << " faces point inward against their normals (an OBJ of it is inside out)";
  EXPECT_EQ(faces_against_normals(mesh, kBody.first, kBody.count).first, 0u);
}

}  // namespace
}  // namespace ffd

namespace ffd {
namespace {

// A node scaled to zero (a hidden part of a rig) has no inverse: it is read flat, its
// normals are kept finite, and it is written back as it was while the rest deforms.
TEST(GltfRun, ANodeScaledToZeroIsWrittenBackAsItWas) {
  const std::string dir = temp_folder("gltf_zero_scale"), out = temp_folder("gltf_zero_scale_out");
  const std::string input = edited_gltf("zero.gltf", [](json& j) { j["nodes"][0]["scale"] = {0, 0, 0}; })(dir);
  const Mesh mesh = read_mesh(input);
  EXPECT_TRUE(mesh.normals().allFinite());
  EXPECT_TRUE(mesh.positions().allFinite());
  write_file(dir + "/move.json", script({kLattice, kMove}));
  std::string err;
  ASSERT_EQ(run_ffd(input, dir + "/move.json", out + "/out.glb", &err), 0) << err;
  const tinygltf::Model in = load(input), written = load(out + "/out.glb");
  const tinygltf::Primitive& nose = written.meshes.at(written.nodes.at(0).mesh).primitives.at(0);
  const tinygltf::Primitive& source = in.meshes.at(in.nodes.at(0).mesh).primitives.at(0);
  for (const char* attribute : {"POSITION", "NORMAL"}) {
    const std::vector<float> a = accessor_floats(in, source.attributes.at(attribute));
    const std::vector<float> b = accessor_floats(written, nose.attributes.at(attribute));
    EXPECT_EQ(a, b) << attribute;
    for (float x : b) EXPECT_TRUE(std::isfinite(x)) << attribute;
  }
}

}  // namespace
}  // namespace ffd
