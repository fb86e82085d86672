// The glTF reader (gltf_io.h): tinygltf parses, this file walks the default scene.
#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <fstream>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <tuple>

#include "common/errors.h"
#include "common/numbers.h"
#include "mesh/build_mesh.h"
#include "mesh/gltf_accessors.h"
#include "mesh/gltf_decode.h"
#include "mesh/gltf_document.h"
#include "mesh/gltf_io.h"
#include "mesh/gltf_scene.h"

namespace ffd {

namespace {

// Images stay as they are in the file: never decoded, written back by reference. tinygltf
// keeps the URI of an external image and the bufferView of an embedded one, but a data
// URI only as its decoded bytes, so that URI is rebuilt from them.
bool keep_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int, const unsigned char* bytes,
                int size, void*) {
  if (image->uri.empty() && image->bufferView < 0 && bytes && size > 0)
    image->uri = data_uri(bytes, static_cast<std::size_t>(size),
                          image->mimeType.empty() ? std::string("application/octet-stream") : image->mimeType);
  return true;
}

// glTF 1.0 (its binary container KHR_binary_glTF, or JSON whose asset says 1.x or whose
// top-level collections are dictionaries) is refused by name.
void refuse_gltf_1(std::string_view bytes, const std::string& path, bool binary, const std::string& version) {
  const bool old_glb = binary && bytes.size() >= 8 && bytes.substr(0, 4) == "glTF" && bytes[4] == 1 &&
                       bytes[5] == 0 && bytes[6] == 0 && bytes[7] == 0;
  if (old_glb || (!version.empty() && version[0] == '1'))
    throw InputError(At{path}, "glTF 1.0 is not supported; ffdtool reads glTF 2.0 (convert the file first, "
                               "e.g. with gltf-pipeline or Blender)");
  if (!version.empty() && version.rfind("2.", 0) != 0)
    throw InputError(At{path}, "glTF " + version + " is not supported; ffdtool reads glTF 2.0");
}

// tinygltf's model of the file, with meshopt fallback buffers loadable (gltf_decode.h).
tinygltf::Model parse_model(std::string_view bytes, const std::string& path, bool binary, LoadFixes& fixes) {
  if (bytes.size() > 0xffffffffu) throw InputError(At{path}, "glTF files over 4 GiB are not supported");
  refuse_gltf_1(bytes, path, binary, "");
  const std::string loadable = loadable_gltf(bytes, binary, fixes);
  const std::string_view load = loadable.empty() ? bytes : std::string_view(loadable);
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(keep_image, nullptr);
  loader.SetStoreOriginalJSONForExtrasAndExtensions(false);
  tinygltf::Model model;
  std::string err, warn;
  const std::string base = std::filesystem::absolute(path).parent_path().string();
  const auto size = static_cast<unsigned int>(load.size());
  const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                                       reinterpret_cast<const unsigned char*>(load.data()), size, base)
                         : loader.LoadASCIIFromString(&model, &err, &warn, load.data(), size, base);
  if (!ok) {
    refuse_gltf_1(bytes, path, binary, gltf_json_version(binary ? glb_json_chunk(bytes) : std::string(bytes)));
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    for (char& c : err) c = c == '\n' ? ';' : c;
    throw InputError(At{path}, "not a valid glTF " + std::string(binary ? "binary (GLB)" : "file") + ": " +
                                   (err.empty() ? "unreadable" : err));
  }
  refuse_gltf_1(bytes, path, binary, model.asset.version);
  return model;
}

// Decodes Draco and meshopt data into plain accessors (gltf_decode.h) and says so.
void decode_compression(GltfScene& scene, const LoadFixes& fixes) {
  scene.decoded_extensions = decode_meshopt(scene.model, fixes.fallbacks);
  scene.decoded_accessors = decode_draco(scene.model, fixes.draco_indices);
  if (!scene.decoded_accessors.empty()) scene.decoded_extensions.push_back("KHR_draco_mesh_compression");
  for (const std::string& name : scene.decoded_extensions)
    scene.warnings.push_back(name + " is decoded on read; a glTF output holds the data uncompressed and no longer "
                                    "declares it (ffdtool does not re-encode)");
  const auto& used = scene.model.extensionsUsed;
  if (std::find(used.begin(), used.end(), "KHR_mesh_quantization") != used.end())
    scene.warnings.push_back("KHR_mesh_quantization: quantized attributes are read as float; a glTF output writes "
                             "the positions and normals a deformation changes as float, the rest as they were");
}

// A node's local matrix: `matrix` when given, else T · R · S.
Eigen::Matrix4d local_matrix(const tinygltf::Node& node) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (node.matrix.size() == 16) {
    for (int k = 0; k < 16; ++k) m(k % 4, k / 4) = node.matrix[k];  // column-major
    return m;
  }
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (node.translation.size() == 3) t.translate(Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4) {
    Eigen::Quaterniond q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // glTF: x y z w
    if (q.norm() > 0) t.rotate(q.normalized());
  }
  if (node.scale.size() == 3) t.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
  return t.matrix();
}

// The default scene's nodes with a mesh, depth first, with their world matrices.
std::vector<GltfInstance> scene_instances(const tinygltf::Model& model, const std::string& path) {
  std::vector<int> roots;
  if (!model.scenes.empty()) {
    const int s = model.defaultScene >= 0 && static_cast<std::size_t>(model.defaultScene) < model.scenes.size()
                      ? model.defaultScene : 0;
    roots = model.scenes[s].nodes;
  } else {  // no scene: every node that is nobody's child, as viewers show such files
    std::vector<char> child(model.nodes.size(), 0);
    for (const tinygltf::Node& n : model.nodes)
      for (int c : n.children)
        if (c >= 0 && static_cast<std::size_t>(c) < child.size()) child[c] = 1;
    for (std::size_t i = 0; i < child.size(); ++i)
      if (!child[i]) roots.push_back(static_cast<int>(i));
  }
  std::vector<GltfInstance> out;
  struct Frame { int node; Eigen::Matrix4d parent; };
  std::vector<Frame> stack;
  for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.push_back({*r, Eigen::Matrix4d::Identity()});
  std::size_t visits = 0;
  while (!stack.empty()) {
    const Frame f = stack.back();
    stack.pop_back();
    if (f.node < 0 || static_cast<std::size_t>(f.node) >= model.nodes.size())
      throw InputError(At{path}, "node " + std::to_string(f.node) + " does not exist");
    // Each node has at most one parent in valid glTF, so a walk longer than the node
    // list has met a cycle (or a node listed under two parents).
    if (++visits > model.nodes.size())
      throw InputError(At{path}, "node " + std::to_string(f.node) +
                                     " is reached twice: the node hierarchy has a cycle or a shared child");
    const tinygltf::Node& node = model.nodes[f.node];
    const Eigen::Matrix4d world = f.parent * local_matrix(node);
    if (node.mesh >= 0) {
      if (static_cast<std::size_t>(node.mesh) >= model.meshes.size())
        throw InputError(At{path}, "node " + std::to_string(f.node) + ": mesh " + std::to_string(node.mesh) + " does not exist");
      // glTF ignores a skinned node's transform: its vertices stay in bind pose (mesh space).
      out.push_back({f.node, node.mesh, node.skin >= 0 ? Eigen::Matrix4d::Identity() : world});
    }
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.push_back({*c, world});
  }
  return out;
}

}  // namespace

namespace {

// Where one run's vertices, UVs and normals start in the soup.
struct RunTables {
  std::size_t run = 0;
  std::int64_t uv_base = -1, normal_base = -1;
};

// A POSITION accessor's min and max must be its values' bounds (glTF 2.0 section
// 3.6.2.5). Viewers cull and fit by them, but ffdtool reads the data itself, so a file
// whose bounds disagree is read with a warning, and a write recomputes the bounds of
// every accessor it rewrites.
void check_bounds(const tinygltf::Accessor& a, const std::vector<Eigen::Vector3f>& p, GltfScene& scene,
                  const std::string& what) {
  // Quantized bounds are in the integers' units; only float bounds compare with the data.
  if (p.empty() || a.minValues.size() != 3 || a.maxValues.size() != 3 ||
      a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
    return;
  Eigen::Vector3f lo = p[0], hi = p[0];
  for (const Eigen::Vector3f& v : p) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  for (int k = 0; k < 3; ++k)
    if (static_cast<double>(lo[k]) != a.minValues[k] || static_cast<double>(hi[k]) != a.maxValues[k]) {
      const std::string note = what + ": its min and max are not its values' bounds; a write recomputes them";
      if (std::find(scene.warnings.begin(), scene.warnings.end(), note) == scene.warnings.end())
        scene.warnings.push_back(note);
      return;
    }
}

// A position that is not finite cannot be deformed or bounded: refused by element.
void refuse_non_finite(const std::vector<Eigen::Vector3f>& p, const std::string& what) {
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p[i].allFinite())
      throw InputError(what + ": element " + std::to_string(i) + " is not finite (" + format_number(p[i].x()) + " " +
                       format_number(p[i].y()) + " " + format_number(p[i].z()) + ")");
}

// Reads the vertices of (instance, POSITION, NORMAL) into the soup, in world space.
RunTables add_run(tinygltf::Model& model, GltfScene& scene, PolygonSoup& soup, std::size_t instance,
                  const tinygltf::Primitive& prim, const std::string& what) {
  const int pos = prim.attributes.at("POSITION");
  const auto n_it = prim.attributes.find("NORMAL");
  const int nrm = n_it == prim.attributes.end() ? -1 : n_it->second;
  const std::vector<Eigen::Vector3f> p = read_vec3(model, pos, "POSITION of " + what);
  std::vector<Eigen::Vector3f> n;
  if (nrm >= 0) n = read_vec3(model, nrm, "NORMAL of " + what);
  if (nrm >= 0 && n.size() != p.size())
    throw InputError("accessor " + std::to_string(nrm) + " (NORMAL of " + what + "): " + std::to_string(n.size()) +
                     " normals for " + std::to_string(p.size()) + " positions");
  const auto t_it = prim.attributes.find("TEXCOORD_0");
  std::vector<Eigen::Vector2f> uv;
  if (t_it != prim.attributes.end()) uv = read_vec2(model, t_it->second, "TEXCOORD_0 of " + what);
  if (soup.positions.size() + p.size() > 0xffffffffu) throw InputError("more than 2^32 - 1 vertices");
  const Eigen::Matrix4d& w = scene.instances[instance].world;
  // A node scaled to zero (a hidden part of a rig) flattens its vertices to a point; its
  // normals are kept as they are rather than divided by zero.
  const double det = w.topLeftCorner<3, 3>().determinant();
  const Eigen::Matrix3d normal_matrix = std::isfinite(det) && det != 0 ? Eigen::Matrix3d(w.topLeftCorner<3, 3>().inverse().transpose())
                                                                         : Eigen::Matrix3d::Identity();
  refuse_non_finite(p, "accessor " + std::to_string(pos) + " (POSITION of " + what + ")");
  check_bounds(model.accessors[pos], p, scene, "accessor " + std::to_string(pos) + " (POSITION of " + what + ")");
  RunTables t;
  t.run = scene.runs.size();
  scene.runs.push_back({instance, pos, nrm, static_cast<std::uint32_t>(soup.positions.size()),
                        static_cast<std::uint32_t>(p.size())});
  for (const Eigen::Vector3f& v : p) {
    soup.positions.push_back((w * v.cast<double>().homogeneous()).head<3>());
    if (!soup.positions.back().allFinite())
      throw InputError("node " + std::to_string(scene.instances[instance].node) + ": its transform takes " + what +
                       "'s vertices to non-finite positions");
  }
  if (nrm >= 0) {
    t.normal_base = static_cast<std::int64_t>(soup.normals.size());
    for (const Eigen::Vector3f& v : n) soup.normals.push_back((normal_matrix * v.cast<double>()).normalized());
  }
  if (uv.size() == p.size()) {
    t.uv_base = static_cast<std::int64_t>(soup.uvs.size());
    for (const Eigen::Vector2f& v : uv) soup.uvs.push_back(v.cast<double>());
  }
  return t;
}

// The primitive's elements: triangles (list, strip, fan) as polygons, lines as polylines,
// points as one point element.
void add_elements(PolygonSoup& soup, const GltfRun& run, const RunTables& t, const std::vector<std::uint32_t>& idx,
                  int mode, std::int32_t group, bool mirrored) {
  auto corner = [&](std::uint32_t i) {
    soup.elements.add_corner(run.first + i, t.uv_base < 0 ? -1 : static_cast<std::int32_t>(t.uv_base + i),
                             t.normal_base < 0 ? -1 : static_cast<std::int32_t>(t.normal_base + i));
  };
  // A node whose matrix mirrors (negative determinant) turns its triangles clockwise
  // (glTF 2.0 section 3.7.4): in world space their corners run the other way.
  auto triangle = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (mirrored) std::swap(b, c);
    corner(a), corner(b), corner(c);
    soup.elements.close(ElementKind::Polygon, group);
  };
  const std::size_t n = idx.size();
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (std::size_t i = 0; i + 2 < n; i += 3) triangle(idx[i], idx[i + 1], idx[i + 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {  // glTF 2.0 section 3.7.2.1
    for (std::size_t i = 0; i + 2 < n; ++i) triangle(idx[i], idx[i + 1 + i % 2], idx[i + 2 - i % 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (std::size_t i = 1; i + 1 < n; ++i) triangle(idx[i], idx[i + 1], idx[0]);
  } else if (mode == TINYGLTF_MODE_LINE) {
    for (std::size_t i = 0; i + 1 < n; i += 2) {
      corner(idx[i]), corner(idx[i + 1]);
      soup.elements.close(ElementKind::Line, group);
    }
  } else if (n > 0 && (mode == TINYGLTF_MODE_LINE_STRIP || mode == TINYGLTF_MODE_LINE_LOOP)) {
    for (std::uint32_t i : idx) corner(i);
    if (mode == TINYGLTF_MODE_LINE_LOOP) corner(idx[0]);
    soup.elements.close(ElementKind::Line, group);
  } else if (n > 0 && mode == TINYGLTF_MODE_POINTS) {
    for (std::uint32_t i : idx) corner(i);
    soup.elements.close(ElementKind::Point, group);
  }
}

// Room in the soup for every primitive's vertices and corners, so that a large file is
// not copied as its arrays grow. The counts are the file's, not yet checked: each is
// capped by what the buffers could hold (12 bytes a vertex, 1 byte an index).
void reserve_soup(const tinygltf::Model& model, const GltfScene& scene, PolygonSoup& soup) {
  std::size_t bytes = 0, vertices = 0, corners = 0;
  for (const tinygltf::Buffer& b : model.buffers) bytes += b.data.size();
  auto count = [&](int accessor) {
    return accessor >= 0 && static_cast<std::size_t>(accessor) < model.accessors.size() ? model.accessors[accessor].count
                                                                                        : std::size_t(0);
  };
  for (const GltfInstance& inst : scene.instances)
    for (const tinygltf::Primitive& prim : model.meshes[inst.mesh].primitives) {
      const auto pos = prim.attributes.find("POSITION");
      if (pos == prim.attributes.end()) continue;
      vertices += count(pos->second);
      corners += prim.indices >= 0 ? count(prim.indices) : count(pos->second);
    }
  vertices = std::min(vertices, bytes / 12);
  corners = std::min(corners, bytes + 3 * vertices);
  soup.positions.reserve(vertices);
  soup.normals.reserve(vertices);
  soup.uvs.reserve(vertices);
  soup.elements.reserve(corners / 3, 3);
  soup.elements.corner_uvs.reserve(corners);
  soup.elements.corner_normals.reserve(corners);
}

// Each primitive of each instance: its run (shared by primitives of one node that share
// POSITION and NORMAL accessors) and its elements.
void read_instances(tinygltf::Model& model, GltfScene& scene, PolygonSoup& soup) {
  reserve_soup(model, scene, soup);
  std::map<std::tuple<std::size_t, int, int>, RunTables> runs;
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const GltfInstance& inst = scene.instances[i];
    const tinygltf::Mesh& mesh = model.meshes[inst.mesh];
    for (std::size_t k = 0; k < mesh.primitives.size(); ++k) {
      const tinygltf::Primitive& prim = mesh.primitives[k];
      const auto pos = prim.attributes.find("POSITION");
      if (pos == prim.attributes.end()) continue;
      const std::string what = "mesh " + std::to_string(inst.mesh) + " primitive " + std::to_string(k);
      const auto nrm = prim.attributes.find("NORMAL");
      const auto key = std::make_tuple(i, pos->second, nrm == prim.attributes.end() ? -1 : nrm->second);
      auto it = runs.find(key);
      if (it == runs.end()) it = runs.emplace(key, add_run(model, scene, soup, i, prim, what)).first;
      const GltfRun& run = scene.runs[it->second.run];
      std::vector<std::uint32_t> idx;
      if (prim.indices >= 0) {
        idx = read_indices(model, prim.indices, run.count, "indices of " + what);
      } else {
        idx.resize(run.count);
        for (std::uint32_t v = 0; v < run.count; ++v) idx[v] = v;
      }
      ObjState state;
      state.object = model.nodes[inst.node].name.empty() ? "node" + std::to_string(inst.node) : model.nodes[inst.node].name;
      if (prim.material >= 0 && static_cast<std::size_t>(prim.material) < model.materials.size())
        state.material = model.materials[prim.material].name;
      soup.groups.push_back(state);
      const bool mirrored = inst.world.topLeftCorner<3, 3>().determinant() < 0;
      add_elements(soup, run, it->second, idx, prim.mode, static_cast<std::int32_t>(soup.groups.size() - 1), mirrored);
    }
  }
}

// Says which meshes are deformed in bind pose or base shape.
void add_notes(const tinygltf::Model& model, GltfScene& scene) {
  std::vector<char> seen(model.meshes.size(), 0);
  for (const GltfInstance& inst : scene.instances) {
    if (seen[inst.mesh]++) continue;
    const std::string name = "mesh " + std::to_string(inst.mesh);
    if (model.nodes[inst.node].skin >= 0)
      scene.notes.push_back(name + " is skinned: it is deformed in its bind pose");
    for (const tinygltf::Primitive& prim : model.meshes[inst.mesh].primitives)
      if (!prim.targets.empty()) {
        scene.notes.push_back(name + " has morph targets: its base shape is deformed, the targets' offsets are kept");
        break;
      }
  }
}

std::string decoded_uri(const std::string& uri);

// Which buffers came from files beside the glTF (a write must not replace them).
void record_buffers(const tinygltf::Model& model, GltfScene& scene, const std::string& path) {
  const std::filesystem::path base = std::filesystem::absolute(path).parent_path();
  for (const tinygltf::Buffer& b : model.buffers) {
    const bool embedded = b.uri.rfind("data:", 0) == 0;
    scene.buffer_embedded.push_back(embedded);
    if (!b.uri.empty() && !embedded) scene.buffer_files.push_back((base / decoded_uri(b.uri)).lexically_normal());
  }
}

}  // namespace

Mesh read_gltf(std::string_view bytes, const std::string& path, bool binary) {
  auto scene = std::make_shared<GltfScene>();
  LoadFixes fixes;
  scene->model = parse_model(bytes, path, binary, fixes);
  scene->binary = binary;
  scene->json = binary ? glb_json_chunk(bytes) : std::string(bytes);
  PolygonSoup soup;
  try {
    decode_compression(*scene, fixes);
    scene->instances = scene_instances(scene->model, path);
    read_instances(scene->model, *scene, soup);
  } catch (InputError& e) {
    if (!e.placed()) e.set_place(path);
    throw;
  }
  if (soup.positions.empty()) throw InputError(At{path}, "the default scene draws no mesh primitive with POSITION");
  add_notes(scene->model, *scene);
  record_buffers(scene->model, *scene, path);
  scene->folder = std::filesystem::absolute(path).parent_path().lexically_normal();
  scene->num_vertices = soup.positions.size();
  soup.binary = binary;
  Mesh mesh = build_mesh(std::move(soup), path);
  mesh.set_gltf_scene(std::move(scene));
  return mesh;
}

bool gltf_reads_file(const GltfScene& scene, const std::filesystem::path& file) {
  return std::find(scene.buffer_files.begin(), scene.buffer_files.end(), file) != scene.buffer_files.end();
}

namespace {

// A URI's path with %XX escapes decoded (RFC 3986), as tinygltf resolves it.
std::string decoded_uri(const std::string& uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// A URI's decoded path, or empty if it is not a plain relative path inside the folder.
std::string relative_uri_path(const std::string& uri) {
  if (uri.empty() || uri.rfind("data:", 0) == 0 || uri.find("://") != std::string::npos) return {};
  const std::string out = decoded_uri(uri);
  const std::filesystem::path p(out);
  if (p.is_absolute() || out.find('\0') != std::string::npos) return {};
  for (const auto& part : p.lexically_normal())
    if (part == "..") return {};
  return out;
}

}  // namespace

std::vector<CompanionFile> gltf_image_files(const Mesh& mesh) {
  std::vector<CompanionFile> out;
  const GltfScene* scene = mesh.gltf_scene();
  if (!scene) return out;
  for (const tinygltf::Image& image : scene->model.images) {
    const std::string rel = relative_uri_path(image.uri);
    if (rel.empty()) continue;
    std::ifstream in(scene->folder / rel, std::ios::binary);
    if (!in) continue;
    CompanionFile f{rel, std::vector<unsigned char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>())};
    out.push_back(std::move(f));
  }
  return out;
}

std::filesystem::path gltf_folder(const Mesh& mesh) {
  const GltfScene* scene = mesh.gltf_scene();
  return scene ? scene->folder : std::filesystem::path();
}

std::vector<std::string> gltf_warnings(const Mesh& mesh) {
  const GltfScene* scene = mesh.gltf_scene();
  return scene ? scene->warnings : std::vector<std::string>();
}

GltfSummary gltf_summary(const Mesh& mesh) {
  GltfSummary s;
  const GltfScene* scene = mesh.gltf_scene();
  if (!scene) return s;
  const tinygltf::Model& m = scene->model;
  s.nodes = m.nodes.size();
  s.meshes = m.meshes.size();
  for (const GltfInstance& inst : scene->instances) s.primitives += m.meshes[inst.mesh].primitives.size();
  s.instances = scene->instances.size();
  s.materials = m.materials.size();
  s.textures = m.textures.size();
  s.images = m.images.size();
  s.animations = m.animations.size();
  s.skins = m.skins.size();
  s.binary = scene->binary;
  s.notes = scene->notes;
  return s;
}

}  // namespace ffd
