#include "mesh/gltf_decode.h"

#include <cstdint>
#include <cstring>
#include <map>
#include <memory>

#include <draco/compression/decode.h>
#include <meshoptimizer.h>

#include "common/errors.h"
#include "mesh/gltf_accessors.h"

namespace ffd {

namespace {

const char* const kDraco = "KHR_draco_mesh_compression";

// The checked bytes of bufferView `view` (what names it in errors).
std::pair<const unsigned char*, std::size_t> view_range(const tinygltf::Model& model, int view, const std::string& what) {
  if (view < 0 || static_cast<std::size_t>(view) >= model.bufferViews.size())
    throw InputError(what + ": bufferView " + std::to_string(view) + " does not exist");
  const tinygltf::BufferView& v = model.bufferViews[view];
  if (v.buffer < 0 || static_cast<std::size_t>(v.buffer) >= model.buffers.size())
    throw InputError(what + ": bufferView " + std::to_string(view) + " names a buffer that does not exist");
  const std::vector<unsigned char>& data = model.buffers[v.buffer].data;
  if (v.byteOffset > data.size() || v.byteLength > data.size() - v.byteOffset)
    throw InputError(what + ": bufferView " + std::to_string(view) + " runs past the end of its buffer");
  return {data.data() + v.byteOffset, v.byteLength};
}

// Values of point attribute `att` for every point, converted to T, n components each.
template <typename T>
void convert_points(const draco::PointAttribute& att, std::size_t points, int n, std::vector<unsigned char>& out) {
  out.resize(points * n * sizeof(T));
  std::vector<T> element(static_cast<std::size_t>(n));
  for (std::size_t p = 0; p < points; ++p) {
    if (!att.ConvertValue<T>(att.mapped_index(draco::PointIndex(static_cast<std::uint32_t>(p))),
                             static_cast<std::int8_t>(n), element.data()))
      throw InputError("a Draco attribute's values cannot be converted to its accessor's component type");
    std::memcpy(out.data() + p * n * sizeof(T), element.data(), n * sizeof(T));
  }
}

// Attribute `att` as the bytes accessor `a` declares.
std::vector<unsigned char> attribute_bytes(const draco::PointAttribute& att, const tinygltf::Accessor& a, std::size_t points) {
  const int n = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
  std::vector<unsigned char> out;
  switch (a.componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: convert_points<std::int8_t>(att, points, n, out); break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: convert_points<std::uint8_t>(att, points, n, out); break;
    case TINYGLTF_COMPONENT_TYPE_SHORT: convert_points<std::int16_t>(att, points, n, out); break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: convert_points<std::uint16_t>(att, points, n, out); break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: convert_points<std::uint32_t>(att, points, n, out); break;
    default: convert_points<float>(att, points, n, out); break;
  }
  return out;
}

// The decoded geometry of one Draco primitive: a mesh, or a point cloud (mode POINTS).
std::unique_ptr<draco::PointCloud> decode_geometry(const unsigned char* data, std::size_t size, bool points,
                                                   const std::string& what) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(data), size);
  draco::Decoder decoder;
  std::unique_ptr<draco::PointCloud> out;
  std::string error;
  if (points) {
    auto cloud = decoder.DecodePointCloudFromBuffer(&buffer);
    if (cloud.ok()) out = std::move(cloud).value();
    else error = cloud.status().error_msg_string();
  } else {
    auto mesh = decoder.DecodeMeshFromBuffer(&buffer);
    if (mesh.ok()) out = std::move(mesh).value();
    else error = mesh.status().error_msg_string();
  }
  if (!out) throw InputError(what + ": the Draco data does not decode (" + error + ")");
  return out;
}

// Gives accessor `index` the decoded bytes as a new view (if it has none yet).
void place(tinygltf::Model& model, int index, const std::vector<unsigned char>& bytes, std::size_t count, int target,
           const std::string& what, std::vector<int>& placed) {
  tinygltf::Accessor& a = model.accessors.at(static_cast<std::size_t>(index));
  if (a.bufferView >= 0) return;  // another primitive decoded it already
  placed.push_back(index);
  if (a.count != count)
    throw InputError(what + ": accessor " + std::to_string(index) + " declares " + std::to_string(a.count) +
                     " elements, the Draco data holds " + std::to_string(count));
  a.bufferView = append_view(model, bytes.data(), bytes.size(), target);
  a.byteOffset = 0;
}

// The triangle corners of a decoded mesh as accessor `a`'s index type.
std::vector<unsigned char> index_bytes(const draco::Mesh& mesh, const tinygltf::Accessor& a) {
  // An index type that is not an integer one is refused by the reader afterwards.
  const std::size_t size = component_size(a.componentType) ? component_size(a.componentType) : 4;
  std::vector<unsigned char> out(static_cast<std::size_t>(mesh.num_faces()) * 3 * size);
  std::size_t at = 0;
  for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k, at += size) {
      const std::uint32_t v = mesh.face(f)[k].value();
      if (size == 1) out[at] = static_cast<unsigned char>(v);
      else if (size == 2) {
        const auto s = static_cast<std::uint16_t>(v);
        std::memcpy(&out[at], &s, 2);
      } else {
        std::memcpy(&out[at], &v, 4);
      }
    }
  return out;
}

void decode_primitive(tinygltf::Model& model, tinygltf::Primitive& prim, const std::string& what,
                      std::vector<int>& placed) {
  const tinygltf::Value& ext = prim.extensions.at(kDraco);
  const int view = ext.Get("bufferView").IsNumber() ? ext.Get("bufferView").GetNumberAsInt() : -1;
  const auto [data, size] = view_range(model, view, what);
  const std::vector<unsigned char> bytes(data, data + size);  // appending views may move the buffer
  const std::unique_ptr<draco::PointCloud> geometry =
      decode_geometry(bytes.data(), bytes.size(), prim.mode == TINYGLTF_MODE_POINTS, what);
  const std::size_t points = geometry->num_points();
  const tinygltf::Value& ids = ext.Get("attributes");
  for (const auto& [name, accessor] : prim.attributes) {
    if (!ids.Has(name)) continue;  // not compressed: a plain accessor
    const draco::PointAttribute* att = geometry->GetAttributeByUniqueId(static_cast<std::uint32_t>(ids.Get(name).GetNumberAsInt()));
    if (!att) throw InputError(what + ": the Draco data has no attribute " + std::to_string(ids.Get(name).GetNumberAsInt()) + " for " + name);
    place(model, accessor, attribute_bytes(*att, model.accessors.at(accessor), points), points, TINYGLTF_TARGET_ARRAY_BUFFER, what, placed);
  }
  const auto* mesh = dynamic_cast<const draco::Mesh*>(geometry.get());
  if (mesh && prim.indices >= 0) {
    const tinygltf::Accessor& a = model.accessors.at(static_cast<std::size_t>(prim.indices));
    place(model, prim.indices, index_bytes(*mesh, a), static_cast<std::size_t>(mesh->num_faces()) * 3,
          TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, what, placed);
  }
  prim.extensions.erase(kDraco);
}

}  // namespace

std::vector<int> decode_draco(tinygltf::Model& model, const std::vector<DracoIndices>& indices) {
  for (const DracoIndices& d : indices) model.meshes.at(d.mesh).primitives.at(d.primitive).indices = d.accessor;
  std::vector<int> placed;
  for (std::size_t m = 0; m < model.meshes.size(); ++m)
    for (std::size_t k = 0; k < model.meshes[m].primitives.size(); ++k) {
      tinygltf::Primitive& prim = model.meshes[m].primitives[k];
      if (!prim.extensions.count(kDraco)) continue;
      const std::string what = "mesh " + std::to_string(m) + " primitive " + std::to_string(k) + " (" + kDraco + ")";
      for (const auto& [name, accessor] : prim.attributes)
        if (accessor < 0 || static_cast<std::size_t>(accessor) >= model.accessors.size())
          throw InputError(what + ": " + name + " accessor " + std::to_string(accessor) + " does not exist");
      if (prim.indices >= static_cast<int>(model.accessors.size()))
        throw InputError(what + ": indices accessor " + std::to_string(prim.indices) + " does not exist");
      decode_primitive(model, prim, what, placed);
    }
  return placed;
}

namespace {

// One meshopt-compressed view decoded into its place (EXT_meshopt_compression spec).
void decode_meshopt_view(tinygltf::Model& model, std::size_t index, const tinygltf::Value& ext) {
  const std::string what = "bufferView " + std::to_string(index) + " (meshopt)";
  auto number = [&](const char* key, int fallback) {
    return ext.Has(key) && ext.Get(key).IsNumber() ? ext.Get(key).GetNumberAsInt() : fallback;
  };
  const int source = number("buffer", -1);
  if (source < 0 || static_cast<std::size_t>(source) >= model.buffers.size())
    throw InputError(what + ": its compressed buffer " + std::to_string(source) + " does not exist");
  const auto offset = static_cast<std::size_t>(std::max(number("byteOffset", 0), 0));
  const auto length = static_cast<std::size_t>(std::max(number("byteLength", 0), 0));
  const auto stride = static_cast<std::size_t>(std::max(number("byteStride", 0), 0));
  const auto count = static_cast<std::size_t>(std::max(number("count", 0), 0));
  const std::vector<unsigned char>& src = model.buffers[source].data;
  if (offset > src.size() || length > src.size() - offset)
    throw InputError(what + ": its compressed bytes run past the end of buffer " + std::to_string(source));
  const tinygltf::BufferView& view = model.bufferViews[index];
  std::vector<unsigned char>& dst = model.buffers.at(static_cast<std::size_t>(view.buffer)).data;
  if (stride == 0 || count > view.byteLength / stride || count * stride != view.byteLength ||
      view.byteOffset > dst.size() || view.byteLength > dst.size() - view.byteOffset)
    throw InputError(what + ": count " + std::to_string(count) + " × byteStride " + std::to_string(stride) +
                     " does not fill the view's " + std::to_string(view.byteLength) + " bytes in its buffer");
  const std::string mode = ext.Has("mode") && ext.Get("mode").IsString() ? ext.Get("mode").Get<std::string>() : "";
  // meshoptimizer asserts these rather than failing: the spec's limits, checked first.
  if (mode == "ATTRIBUTES" && (stride % 4 != 0 || stride > 256))
    throw InputError(what + ": ATTRIBUTES need a byteStride divisible by 4 and at most 256, not " + std::to_string(stride));
  if (mode == "TRIANGLES" && count % 3 != 0)
    throw InputError(what + ": TRIANGLES need a count divisible by 3, not " + std::to_string(count));
  const std::string filter =
      ext.Has("filter") && ext.Get("filter").IsString() ? ext.Get("filter").Get<std::string>() : "NONE";
  std::vector<unsigned char> compressed(src.begin() + static_cast<std::ptrdiff_t>(offset),
                                        src.begin() + static_cast<std::ptrdiff_t>(offset + length));
  unsigned char* out = dst.data() + view.byteOffset;
  int status = -1;
  if (mode == "ATTRIBUTES") status = meshopt_decodeVertexBuffer(out, count, stride, compressed.data(), length);
  else if (mode == "TRIANGLES" && (stride == 2 || stride == 4))
    status = meshopt_decodeIndexBuffer(out, count, stride, compressed.data(), length);
  else if (mode == "INDICES" && (stride == 2 || stride == 4))
    status = meshopt_decodeIndexSequence(out, count, stride, compressed.data(), length);
  else throw InputError(what + ": mode '" + mode + "' with byteStride " + std::to_string(stride) + " is not meshopt's");
  if (status != 0) throw InputError(what + ": the " + mode + " data does not decode (meshoptimizer error " + std::to_string(status) + ")");
  if (filter == "OCTAHEDRAL" && (stride == 4 || stride == 8)) meshopt_decodeFilterOct(out, count, stride);
  else if (filter == "QUATERNION" && stride == 8) meshopt_decodeFilterQuat(out, count, stride);
  else if (filter == "EXPONENTIAL" && stride % 4 == 0) meshopt_decodeFilterExp(out, count, stride);
  else if (filter != "NONE") throw InputError(what + ": filter '" + filter + "' with byteStride " + std::to_string(stride) + " is not meshopt's");
}

}  // namespace

std::vector<std::string> decode_meshopt(tinygltf::Model& model, const std::vector<FallbackBuffer>& fallbacks) {
  for (const FallbackBuffer& f : fallbacks) {
    tinygltf::Buffer& b = model.buffers.at(static_cast<std::size_t>(f.index));
    b.uri.clear();  // the empty data URI the loader was given in its place
    b.data.assign(f.byte_length, 0);
  }
  std::vector<std::string> names;
  for (const char* name : {"EXT_meshopt_compression", "KHR_meshopt_compression"}) {
    bool used = false;
    for (std::size_t i = 0; i < model.bufferViews.size(); ++i) {
      const auto it = model.bufferViews[i].extensions.find(name);
      if (it == model.bufferViews[i].extensions.end()) continue;
      decode_meshopt_view(model, i, it->second);
      used = true;
    }
    if (used) names.push_back(name);
  }
  return names;
}

}  // namespace ffd
