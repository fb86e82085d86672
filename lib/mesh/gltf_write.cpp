// The glTF writer (gltf_io.h): the source document patched with new positions and
// normals (gltf_document.h), or a plain one-primitive file for a mesh without a glTF
// source.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>
#include <nlohmann/json.hpp>

#include "common/errors.h"
#include "mesh/gltf_accessors.h"
#include "mesh/gltf_document.h"
#include "mesh/gltf_io.h"
#include "mesh/gltf_repack.h"
#include "mesh/gltf_scene.h"

namespace ffd {

namespace {

// One run's data in its node's local space. A vertex the deformation left where the
// reader put it keeps the file's float bits exactly.
struct LocalRun {
  std::vector<Eigen::Vector3f> positions, normals;
  bool positions_changed = false, normals_changed = false;
};

LocalRun local_run(const Mesh& mesh, const GltfScene& scene, const GltfRun& run, const VertexFileNormals& vn) {
  // The source's values as read (an earlier instance may have replaced the copy's); the
  // accessor functions take a mutable model but only read here.
  tinygltf::Model& model = const_cast<tinygltf::Model&>(scene.model);
  const Eigen::Matrix4d& w = scene.instances[run.instance].world;
  const Eigen::Matrix4d inv = w.inverse();
  const Eigen::Matrix3d wt = w.topLeftCorner<3, 3>().transpose();
  LocalRun out;
  out.positions = read_vec3(model, run.position, "POSITION");
  if (run.normal >= 0) out.normals = read_vec3(model, run.normal, "NORMAL");
  const double det = w.topLeftCorner<3, 3>().determinant();
  if (!std::isfinite(det) || det == 0) return out;  // a node scaled to zero: no local space to go back to
  for (std::uint32_t i = 0; i < run.count; ++i) {
    const Eigen::Vector3d p = mesh.positions().col(run.first + i);
    const Eigen::Vector3d read = (w * out.positions[i].cast<double>().homogeneous()).head<3>();
    if (p == read) continue;
    out.positions[i] = (inv * p.homogeneous()).head<3>().cast<float>();
    out.positions_changed = true;
  }
  if (run.normal < 0) return out;
  for (std::uint32_t i = 0; i < run.count; ++i) {
    const std::uint32_t v = run.first + i;
    if (!vn.has[v] || !vn.moved[v]) continue;
    out.normals[i] = (wt * vn.value[v]).normalized().cast<float>();
    out.normals_changed = true;
  }
  return out;
}

// Puts `values` into accessor `index`: in place when it is dense float, else as new float
// data the accessor then points at (a sparse accessor becomes dense, a quantized one
// float: KHR_mesh_quantization's integers cannot hold a deformation's new range).
void store_vec3(tinygltf::Model& model, int index, const std::vector<Eigen::Vector3f>& values, bool bounds) {
  tinygltf::Accessor& a = model.accessors[index];
  if (a.bufferView >= 0 && !a.sparse.isSparse && a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
    write_vec3(model, index, values);
  } else {
    const int fresh = append_vec3(model, values);
    tinygltf::Accessor moved = model.accessors[fresh];
    model.accessors.pop_back();
    moved.name = model.accessors[index].name;
    moved.extensions = model.accessors[index].extensions;
    moved.extras = model.accessors[index].extras;
    model.accessors[index] = moved;
  }
  if (bounds) set_bounds(model.accessors[index], values);
}

// Gives node `node` its own copy of its mesh, whose primitives use new POSITION and
// NORMAL accessors holding `data` (by old accessor).
void split_instance(tinygltf::Model& model, int node, const std::map<int, const std::vector<Eigen::Vector3f>*>& data) {
  tinygltf::Mesh copy = model.meshes[model.nodes[node].mesh];
  std::map<int, int> fresh;
  for (tinygltf::Primitive& prim : copy.primitives)
    for (const char* name : {"POSITION", "NORMAL"}) {
      auto it = prim.attributes.find(name);
      if (it == prim.attributes.end() || !data.count(it->second)) continue;
      auto [f, inserted] = fresh.try_emplace(it->second, -1);
      if (inserted) f->second = append_vec3(model, *data.at(it->second));
      it->second = f->second;
    }
  model.meshes.push_back(std::move(copy));
  model.nodes[node].mesh = static_cast<int>(model.meshes.size() - 1);
}

// The source model with every run's positions and normals replaced (gltf_io.h).
tinygltf::Model deformed_model(const Mesh& mesh, const GltfScene& scene, const NormalTransform& transform) {
  tinygltf::Model model = scene.model;
  const VertexFileNormals vn = vertex_file_normals(mesh, transform);
  std::map<int, std::vector<Eigen::Vector3f>> written;  // accessor -> values stored
  std::size_t r = 0;
  while (r < scene.runs.size()) {
    const std::size_t instance = scene.runs[r].instance;
    std::vector<std::pair<int, std::vector<Eigen::Vector3f>>> values;  // (accessor, data)
    std::vector<int> positions;  // the accessors that are POSITION (min and max required)
    std::vector<int> unchanged;  // the accessors whose values are the file's
    for (; r < scene.runs.size() && scene.runs[r].instance == instance; ++r) {
      LocalRun local = local_run(mesh, scene, scene.runs[r], vn);
      values.emplace_back(scene.runs[r].position, std::move(local.positions));
      positions.push_back(scene.runs[r].position);
      if (!local.positions_changed) unchanged.push_back(scene.runs[r].position);
      if (scene.runs[r].normal < 0) continue;
      values.emplace_back(scene.runs[r].normal, std::move(local.normals));
      if (!local.normals_changed) unchanged.push_back(scene.runs[r].normal);
    }
    bool agree = true;
    for (const auto& [acc, data] : values) {
      auto it = written.find(acc);
      if (it != written.end() && it->second != data) agree = false;
    }
    if (agree) {
      for (auto& [acc, data] : values) {
        if (written.count(acc)) continue;
        // What the deformation left as it was stays as the file has it: its data, its
        // layout (sparse, quantized) and its bounds.
        // Decoded data is written plain whatever moved, with bounds of its own.
        const bool keep = std::find(unchanged.begin(), unchanged.end(), acc) != unchanged.end() &&
                          std::find(scene.decoded_accessors.begin(), scene.decoded_accessors.end(), acc) ==
                              scene.decoded_accessors.end();
        if (keep) {
          written.emplace(acc, std::move(data));
          continue;
        }
        const bool bounds = std::find(positions.begin(), positions.end(), acc) != positions.end() ||
                            model.accessors[acc].minValues.size() == 3;
        store_vec3(model, acc, data, bounds);
        written.emplace(acc, std::move(data));
      }
    } else {
      std::map<int, const std::vector<Eigen::Vector3f>*> data;
      for (const auto& [acc, d] : values) data[acc] = &d;
      split_instance(model, scene.instances[instance].node, data);
    }
  }
  return model;
}

}  // namespace

namespace {

// A plain model of `mesh`: one buffer, one node, one primitive of triangles (polygons
// fanned from their first corner) with POSITION and NORMAL.
tinygltf::Model plain_model(const Mesh& mesh, const NormalTransform& transform) {
  std::vector<Eigen::Vector3f> p(mesh.num_vertices()), n(mesh.num_vertices());
  const VertexFileNormals vn = vertex_file_normals(mesh, transform);
  for (std::size_t v = 0; v < p.size(); ++v) {
    p[v] = mesh.positions().col(v).cast<float>();
    const Eigen::Vector3d normal = vn.has[v] ? vn.value[v] : Eigen::Vector3d(mesh.normals().col(v));
    n[v] = normal.cast<float>();
  }
  const std::vector<std::array<std::uint32_t, 3>> tris = fan_triangles(mesh.elements());
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "ffdtool";
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.attributes["POSITION"] = append_vec3(model, p);
  prim.attributes["NORMAL"] = append_vec3(model, n);
  if (!tris.empty()) {
    prim.indices = append_accessor(model, tris.data(), 12 * tris.size(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                   TINYGLTF_TYPE_SCALAR, 3 * tris.size(), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  } else {
    prim.mode = TINYGLTF_MODE_POINTS;
  }
  tinygltf::Mesh m;
  m.primitives.push_back(prim);
  model.meshes.push_back(m);
  tinygltf::Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes = {0};
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  return model;
}

// Serializes the plain `model` (one buffer) as .gltf JSON to `os`, its buffer in a
// companion file named after `stem` when `companions` is given, else as a data URI
// (tinygltf's stream writer embeds it; the file writer cannot name the companion).
void write_plain_json(std::ostream& os, tinygltf::Model& model, const std::string& stem,
                      std::vector<CompanionFile>* companions) {
  std::vector<unsigned char> held;
  if (companions) held = std::move(model.buffers[0].data), model.buffers[0].data.clear();
  tinygltf::TinyGLTF writer;
  std::ostringstream text;
  if (!writer.WriteGltfSceneToStream(&model, text, false, false)) throw IoError("tinygltf could not write the glTF file");
  nlohmann::json j = nlohmann::json::parse(text.str());
  if (companions) {
    j["buffers"][0]["uri"] = stem + ".bin";
    j["buffers"][0]["byteLength"] = held.size();
    companions->push_back({stem + ".bin", std::move(held)});
  }
  os << j.dump(2) << "\n";
}

}  // namespace

namespace {

// How each buffer of the deformed model goes out (gltf_document.h); `origin` is each
// buffer's index in the source (empty: the same). A GLB's buffer 0 is its BIN chunk. A
// buffer that was a data URI and is unchanged keeps its URI as read; with companions, a
// .gltf's other buffers go to files named after `stem`; the rest are embedded as data
// URIs. (Decoding may have written into a data-URI buffer: then none is kept.)
std::vector<BufferUri> buffer_uris(const GltfScene& scene, const tinygltf::Model& model, const std::vector<int>& origin,
                                   bool binary, const std::string& stem, std::vector<CompanionFile>* companions) {
  std::vector<BufferUri> uris(model.buffers.size());
  std::size_t files = 0;
  for (std::size_t i = 0; i < uris.size(); ++i) {
    const std::vector<unsigned char>& data = model.buffers[i].data;
    const std::size_t source = origin.empty() ? i : static_cast<std::size_t>(origin[i]);
    const bool was_embedded = source < scene.buffer_embedded.size() && scene.buffer_embedded[source];
    if (binary && i == 0) {
      uris[i].kind = BufferUri::Kind::Erase;
    } else if (was_embedded && scene.decoded_extensions.empty() && data == scene.model.buffers[source].data) {
      uris[i].kind = BufferUri::Kind::Keep;
    } else if (!binary && companions && !was_embedded) {
      const std::string name = stem + (files++ == 0 ? "" : "_" + std::to_string(files - 1)) + ".bin";
      uris[i] = {BufferUri::Kind::Set, name, -1};
      companions->push_back({name, data});
    } else {
      uris[i] = {BufferUri::Kind::Set, data_uri(data.data(), data.size(), "application/octet-stream")};
    }
    uris[i].source = static_cast<int>(source);
  }
  return uris;
}

// The source document patched with the deformed model (gltf_document.h).
void write_source_gltf(std::ostream& os, const Mesh& mesh, const GltfScene& scene, const NormalTransform& transform,
                       bool binary, const std::string& stem, std::vector<CompanionFile>* companions) {
  tinygltf::Model model = deformed_model(mesh, scene, transform);
  const std::vector<int> origin = repack_meshopt_buffers(model, binary);
  const std::vector<BufferUri> uris = buffer_uris(scene, model, origin, binary, stem, companions);
  if (!binary) {
    os << patched_gltf_json(scene, model, uris, 2) << "\n";
    return;
  }
  static const std::vector<unsigned char> none;
  write_glb(os, patched_gltf_json(scene, model, uris, -1), model.buffers.empty() ? none : model.buffers[0].data);
}

}  // namespace

void write_gltf(std::ostream& os, const Mesh& mesh, const NormalTransform& transform_normal, bool binary,
                const std::string& stem, std::vector<CompanionFile>* companions) {
  const GltfScene* scene = mesh.gltf_scene();
  if (scene && scene->num_vertices == mesh.num_vertices())
    return write_source_gltf(os, mesh, *scene, transform_normal, binary, stem, companions);
  tinygltf::Model model = plain_model(mesh, transform_normal);
  if (!binary) return write_plain_json(os, model, stem, companions);
  // The stream writer embeds the buffer as the BIN chunk (it has no uri).
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, os, false, true)) throw IoError("tinygltf could not write the glTF file");
}

}  // namespace ffd
