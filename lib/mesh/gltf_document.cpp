#include "mesh/gltf_document.h"

#include <cstdint>
#include <cstring>
#include <map>
#include <sstream>
#include <nlohmann/json.hpp>

#include "common/base64.h"
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

// The array at `key` of the document, made when absent (only when something goes in it:
// an absent optional array stays absent).
Json& array_at(Json& doc, const char* key) {
  Json& a = doc[key];
  if (!a.is_array()) a = Json::array();
  return a;
}

std::size_t count_of(const Json& doc, const char* key) {
  const auto it = doc.find(key);
  return it != doc.end() && it->is_array() ? it->size() : 0;
}

// The number at `key` of a JSON object, or `fallback` when it has none.
long long number_or(const Json& object, const char* key, long long fallback) {
  const auto it = object.find(key);
  return it != object.end() && it->is_number() ? it->get<long long>() : fallback;
}

std::vector<double> numbers_or_empty(const Json& object, const char* key) {
  std::vector<double> out;
  const auto it = object.find(key);
  if (it != object.end() && it->is_array())
    for (const Json& x : *it) out.push_back(x.is_number() ? x.get<double>() : 0.0);
  return out;
}

// Accessors whose data the read or the write moved (a Draco primitive decoded, a sparse or
// quantized accessor made dense float) and whose bounds changed, against the document's
// own values; appended accessors and views.
void patch_accessors(Json& doc, const tinygltf::Model& model) {
  Json& accessors = array_at(doc, "accessors");
  const std::size_t known = accessors.size();
  for (std::size_t i = 0; i < known; ++i) {
    const tinygltf::Accessor& a = model.accessors[i];
    Json& j = accessors.at(i);
    const bool moved = number_or(j, "bufferView", -1) != a.bufferView ||
                       number_or(j, "byteOffset", 0) != static_cast<long long>(a.byteOffset) ||
                       number_or(j, "componentType", 0) != a.componentType || j.contains("sparse") != a.sparse.isSparse;
    if (moved) {
      j["bufferView"] = a.bufferView;
      set_or_erase(j, "byteOffset", a.byteOffset, 0);
      j["componentType"] = a.componentType;
      if (!a.normalized) j.erase("normalized");
      if (!a.sparse.isSparse) j.erase("sparse");
    }
    if (numbers_or_empty(j, "min") != a.minValues) j["min"] = a.minValues;
    if (numbers_or_empty(j, "max") != a.maxValues) j["max"] = a.maxValues;
  }
  for (std::size_t i = known; i < model.accessors.size(); ++i) accessors.push_back(accessor_json(model.accessors[i]));
  if (model.bufferViews.size() <= count_of(doc, "bufferViews")) return;
  Json& views = array_at(doc, "bufferViews");
  for (std::size_t i = views.size(); i < model.bufferViews.size(); ++i) views.push_back(buffer_view_json(model.bufferViews[i]));
}

// Nodes given their own copy of a mesh (a split instance): the copy is the source mesh's
// JSON with the primitives' POSITION and NORMAL accessors replaced.
void patch_meshes(Json& doc, const tinygltf::Model& model) {
  if (model.meshes.size() <= count_of(doc, "meshes")) return;  // no split instance
  const Json originals = array_at(doc, "meshes");
  std::map<std::size_t, std::size_t> copied_from;  // new mesh -> source mesh
  Json& nodes = array_at(doc, "nodes");
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const long long was = number_or(nodes[i], "mesh", -1);
    if (was == model.nodes[i].mesh) continue;
    nodes[i]["mesh"] = model.nodes[i].mesh;
    copied_from[static_cast<std::size_t>(model.nodes[i].mesh)] = static_cast<std::size_t>(was);
  }
  for (std::size_t m = originals.size(); m < model.meshes.size(); ++m) {
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

// Views the write re-pointed (a repack, gltf_repack.h): their buffer and offset.
void patch_views(Json& doc, const tinygltf::Model& model) {
  Json& views = array_at(doc, "bufferViews");
  for (std::size_t i = 0; i < views.size() && i < model.bufferViews.size(); ++i) {
    const tinygltf::BufferView& v = model.bufferViews[i];
    Json& j = views.at(i);
    if (number_or(j, "buffer", -1) != v.buffer) j["buffer"] = v.buffer;
    if (number_or(j, "byteOffset", 0) != static_cast<long long>(v.byteOffset)) set_or_erase(j, "byteOffset", v.byteOffset, 0);
  }
}

void patch_buffers(Json& doc, const tinygltf::Model& model, const std::vector<BufferUri>& uris) {
  if (model.buffers.empty() && count_of(doc, "buffers") == 0) return;
  const Json source = array_at(doc, "buffers");
  Json& buffers = doc["buffers"];
  buffers = Json::array();
  for (std::size_t i = 0; i < model.buffers.size(); ++i) {
    const int from = uris[i].source;
    buffers.push_back(from >= 0 && static_cast<std::size_t>(from) < source.size() ? source.at(from) : Json::object());
    Json& j = buffers.back();
    if (number_or(j, "byteLength", -1) != static_cast<long long>(model.buffers[i].data.size()))
      j["byteLength"] = model.buffers[i].data.size();
    if (uris[i].kind == BufferUri::Kind::Erase) j.erase("uri");
    if (uris[i].kind == BufferUri::Kind::Set) j["uri"] = uris[i].uri;
  }
  if (buffers.empty()) doc.erase("buffers");
}

// Removes extension `name` from `object`'s "extensions" (and that, once empty).
void erase_extension(Json& object, const std::string& name) {
  if (!object.is_object()) return;
  const auto it = object.find("extensions");
  if (it == object.end() || !it->is_object()) return;
  it->erase(name);
  if (it->empty()) object.erase("extensions");
}

// An extension the reader decoded (Draco, meshopt) no longer describes the written data:
// it goes from the declarations and from every primitive, view and buffer.
void erase_decoded_extension(Json& doc, const std::string& name) {
  for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
    if (!doc.contains(list) || !doc[list].is_array()) continue;
    Json kept = Json::array();
    for (const Json& e : doc[list])
      if (e != name) kept.push_back(e);
    if (kept.empty()) doc.erase(list);
    else doc[list] = std::move(kept);
  }
  if (doc.contains("meshes"))
    for (Json& mesh : doc["meshes"])
      if (mesh.is_object() && mesh.contains("primitives"))
        for (Json& prim : mesh["primitives"]) erase_extension(prim, name);
  for (const char* array : {"bufferViews", "buffers"})
    if (doc.contains(array))
      for (Json& item : doc[array]) erase_extension(item, name);
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

namespace {

// Marks the meshopt fallback buffers of `doc` loadable.
void mark_fallbacks(Json& doc, bool binary, std::vector<FallbackBuffer>& fallbacks) {
  if (!doc.contains("buffers") || !doc["buffers"].is_array()) return;
  Json& buffers = doc["buffers"];
  for (std::size_t i = binary ? 1 : 0; i < buffers.size(); ++i) {
    Json& b = buffers[i];
    if (!b.is_object() || b.contains("uri") || !b.contains("extensions") || !b["extensions"].is_object()) continue;
    bool fallback = false;
    for (const char* name : {"EXT_meshopt_compression", "KHR_meshopt_compression"})
      if (b["extensions"].contains(name) && b["extensions"][name].is_object())
        fallback = fallback || b["extensions"][name].value("fallback", false);
    if (!fallback) continue;
    fallbacks.push_back({static_cast<int>(i), static_cast<std::size_t>(std::max(number_or(b, "byteLength", 0), 0LL))});
    b["uri"] = "data:application/octet-stream;base64,AA==";
    b["byteLength"] = 1;
  }
}

// Takes the view-less indices out of Draco primitives.
void take_draco_indices(Json& doc, std::vector<DracoIndices>& out) {
  if (!doc.contains("meshes") || !doc["meshes"].is_array() || !doc.contains("accessors")) return;
  const Json& accessors = doc["accessors"];
  for (std::size_t m = 0; m < doc["meshes"].size(); ++m) {
    Json& mesh = doc["meshes"][m];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (std::size_t k = 0; k < mesh["primitives"].size(); ++k) {
      Json& prim = mesh["primitives"][k];
      if (!prim.is_object() || !prim.contains("extensions") || !prim["extensions"].is_object() ||
          !prim["extensions"].contains("KHR_draco_mesh_compression"))
        continue;
      const long long index = number_or(prim, "indices", -1);
      if (index < 0 || static_cast<std::size_t>(index) >= accessors.size() || !accessors[index].is_object() ||
          accessors[index].contains("bufferView"))
        continue;
      out.push_back({static_cast<int>(m), static_cast<int>(k), static_cast<int>(index)});
      prim.erase("indices");
    }
  }
}

}  // namespace

std::string loadable_gltf(std::string_view bytes, bool binary, LoadFixes& fixes) {
  const std::string json = binary ? glb_json_chunk(bytes) : std::string(bytes);
  if (json.find("_meshopt_compression") == std::string::npos && json.find("KHR_draco_mesh_compression") == std::string::npos)
    return {};
  Json doc = Json::parse(json, nullptr, false);
  if (!doc.is_object()) return {};
  mark_fallbacks(doc, binary, fixes.fallbacks);
  take_draco_indices(doc, fixes.draco_indices);
  if (fixes.fallbacks.empty() && fixes.draco_indices.empty()) return {};
  if (!binary) return doc.dump();
  // The same GLB with the new JSON chunk: its BIN chunk follows the old JSON chunk.
  const std::size_t after_json = 20 + (static_cast<std::size_t>(get_u32(bytes, 12)) + 3) / 4 * 4;
  std::vector<unsigned char> bin;
  if (bytes.size() >= after_json + 8 && get_u32(bytes, after_json + 4) == 0x004E4942u) {
    const std::size_t n = std::min<std::size_t>(get_u32(bytes, after_json), bytes.size() - after_json - 8);
    bin.assign(bytes.begin() + static_cast<std::ptrdiff_t>(after_json + 8),
               bytes.begin() + static_cast<std::ptrdiff_t>(after_json + 8 + n));
  }
  std::ostringstream out;
  write_glb(out, doc.dump(), bin);
  return out.str();
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
  patch_accessors(doc, model);
  patch_views(doc, model);
  patch_meshes(doc, model);
  patch_buffers(doc, model, uris);
  for (const std::string& name : scene.decoded_extensions) erase_decoded_extension(doc, name);
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
  std::string out = "data:" + mime + ";base64,";
  append_base64(std::string_view(reinterpret_cast<const char*>(p), n), out);
  return out;
}

}  // namespace ffd
