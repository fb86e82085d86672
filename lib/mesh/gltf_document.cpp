#include "mesh/gltf_document.h"

#include <cstdint>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>

#include "common/errors.h"

namespace ffd {

namespace {

// Key order as in the file, so that an untouched object is written back as read.
using Json = nlohmann::ordered_json;

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    default: return "MAT4";
  }
}

// Sets key to value, or erases it when value is the spec's default.
void set_or_erase(Json& object, const char* key, std::size_t value, std::size_t fallback) {
  if (value == fallback) object.erase(key);
  else object[key] = value;
}

Json accessor_json(const tinygltf::Accessor& a) {
  Json j = Json::object();
  j["bufferView"] = a.bufferView;
  if (a.byteOffset) j["byteOffset"] = a.byteOffset;
  j["componentType"] = a.componentType;
  j["count"] = a.count;
  j["type"] = type_name(a.type);
  if (!a.minValues.empty()) j["min"] = a.minValues;
  if (!a.maxValues.empty()) j["max"] = a.maxValues;
  return j;
}

Json buffer_view_json(const tinygltf::BufferView& v) {
  Json j = Json::object();
  j["buffer"] = v.buffer;
  if (v.byteOffset) j["byteOffset"] = v.byteOffset;
  j["byteLength"] = v.byteLength;
  if (v.byteStride) j["byteStride"] = v.byteStride;
  if (v.target) j["target"] = v.target;
  return j;
}

// Accessors the write rewrote: a sparse or view-less one made dense, new min and max.
void patch_accessors(Json& doc, const tinygltf::Model& source, const tinygltf::Model& model) {
  Json& accessors = doc["accessors"];
  for (std::size_t i = 0; i < source.accessors.size(); ++i) {
    const tinygltf::Accessor& a = model.accessors[i];
    const tinygltf::Accessor& s = source.accessors[i];
    Json& j = accessors.at(i);
    if (a.bufferView != s.bufferView || a.sparse.isSparse != s.sparse.isSparse) {
      j["bufferView"] = a.bufferView;
      set_or_erase(j, "byteOffset", a.byteOffset, 0);
      if (!a.sparse.isSparse) j.erase("sparse");
    }
    if (a.minValues != s.minValues) j["min"] = a.minValues;
    if (a.maxValues != s.maxValues) j["max"] = a.maxValues;
  }
  for (std::size_t i = source.accessors.size(); i < model.accessors.size(); ++i)
    accessors.push_back(accessor_json(model.accessors[i]));
  for (std::size_t i = source.bufferViews.size(); i < model.bufferViews.size(); ++i)
    doc["bufferViews"].push_back(buffer_view_json(model.bufferViews[i]));
}

// Nodes given their own copy of a mesh (a split instance): the copy is the source mesh's
// JSON with the primitives' POSITION and NORMAL accessors replaced.
void patch_meshes(Json& doc, const tinygltf::Model& source, const tinygltf::Model& model) {
  std::map<std::size_t, std::size_t> copied_from;  // new mesh -> source mesh
  for (std::size_t i = 0; i < source.nodes.size(); ++i) {
    if (model.nodes[i].mesh == source.nodes[i].mesh) continue;
    doc["nodes"].at(i)["mesh"] = model.nodes[i].mesh;
    copied_from[static_cast<std::size_t>(model.nodes[i].mesh)] = static_cast<std::size_t>(source.nodes[i].mesh);
  }
  const Json originals = doc["meshes"];
  for (std::size_t m = source.meshes.size(); m < model.meshes.size(); ++m) {
    Json copy = originals.at(copied_from.at(m));
    const std::vector<tinygltf::Primitive>& prims = model.meshes[m].primitives;
    for (std::size_t k = 0; k < prims.size(); ++k)
      for (const char* name : {"POSITION", "NORMAL"}) {
        const auto it = prims[k].attributes.find(name);
        if (it != prims[k].attributes.end()) copy["primitives"].at(k)["attributes"][name] = it->second;
      }
    doc["meshes"].push_back(std::move(copy));
  }
}

void patch_buffers(Json& doc, const tinygltf::Model& source, const tinygltf::Model& model,
                   const std::vector<BufferUri>& uris) {
  Json& buffers = doc["buffers"];
  for (std::size_t i = 0; i < model.buffers.size(); ++i) {
    if (i >= source.buffers.size()) buffers.push_back(Json::object());
    Json& j = buffers.at(i);
    if (i >= source.buffers.size() || model.buffers[i].data.size() != source.buffers[i].data.size())
      j["byteLength"] = model.buffers[i].data.size();
    if (uris[i].kind == BufferUri::Kind::Erase) j.erase("uri");
    if (uris[i].kind == BufferUri::Kind::Set) j["uri"] = uris[i].uri;
  }
}

void put_u32(std::ostream& os, std::uint32_t v) {
  const unsigned char b[4] = {static_cast<unsigned char>(v), static_cast<unsigned char>(v >> 8),
                              static_cast<unsigned char>(v >> 16), static_cast<unsigned char>(v >> 24)};
  os.write(reinterpret_cast<const char*>(b), 4);
}

std::uint32_t get_u32(std::string_view bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(bytes[at + k]);
  return v;
}

}  // namespace

std::string glb_json_chunk(std::string_view bytes) {
  if (bytes.size() < 20 || get_u32(bytes, 16) != 0x4E4F534Au) return {};
  const std::size_t length = get_u32(bytes, 12);
  return std::string(bytes.substr(20, std::min(length, bytes.size() - 20)));
}

std::string gltf_json_version(const std::string& json) {
  const Json doc = Json::parse(json, nullptr, false);
  if (!doc.is_object()) return {};
  const auto asset = doc.find("asset");
  if (asset != doc.end() && asset->is_object() && asset->contains("version") && (*asset)["version"].is_string())
    return (*asset)["version"].get<std::string>();
  for (const char* key : {"meshes", "accessors", "nodes", "buffers"})
    if (doc.contains(key) && doc[key].is_object()) return "1.0";
  return {};
}

std::string patched_gltf_json(const GltfScene& scene, const tinygltf::Model& model, const std::vector<BufferUri>& uris,
                              int indent) {
  Json doc = Json::parse(scene.json, nullptr, false);
  if (!doc.is_object()) throw IoError("the glTF source document no longer parses; cannot write it back");
  patch_accessors(doc, scene.model, model);
  patch_meshes(doc, scene.model, model);
  patch_buffers(doc, scene.model, model, uris);
  return doc.dump(indent);
}

void write_glb(std::ostream& os, const std::string& json, const std::vector<unsigned char>& bin) {
  const std::size_t json_padded = (json.size() + 3) / 4 * 4;
  const std::size_t bin_padded = (bin.size() + 3) / 4 * 4;
  const std::size_t total = 12 + 8 + json_padded + (bin.empty() ? 0 : 8 + bin_padded);
  if (total > 0xffffffffu) throw IoError("the GLB would exceed 4 GiB; write .gltf with external buffers instead");
  os.write("glTF", 4);
  put_u32(os, 2);
  put_u32(os, static_cast<std::uint32_t>(total));
  put_u32(os, static_cast<std::uint32_t>(json_padded));
  put_u32(os, 0x4E4F534Au);  // "JSON"
  os << json << std::string(json_padded - json.size(), ' ');
  if (bin.empty()) return;
  put_u32(os, static_cast<std::uint32_t>(bin_padded));
  put_u32(os, 0x004E4942u);  // "BIN\0"
  os.write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
  os << std::string(bin_padded - bin.size(), '\0');
}

std::string data_uri(const unsigned char* p, std::size_t n, const std::string& mime) {
  static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out = "data:" + mime + ";base64,";
  out.reserve(out.size() + (n + 2) / 3 * 4);
  for (std::size_t i = 0; i < n; i += 3) {
    const std::uint32_t v = (std::uint32_t(p[i]) << 16) | (i + 1 < n ? std::uint32_t(p[i + 1]) << 8 : 0) |
                            (i + 2 < n ? std::uint32_t(p[i + 2]) : 0);
    out += digits[(v >> 18) & 63];
    out += digits[(v >> 12) & 63];
    out += i + 1 < n ? digits[(v >> 6) & 63] : '=';
    out += i + 2 < n ? digits[v & 63] : '=';
  }
  return out;
}

}  // namespace ffd
