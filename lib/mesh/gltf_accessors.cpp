#include "mesh/gltf_accessors.h"

#include <algorithm>
#include <cstring>
#include <limits>

#include "common/errors.h"

namespace ffd {

namespace {

[[noreturn]] void bad_accessor(int index, const std::string& what, const std::string& message) {
  throw InputError("accessor " + std::to_string(index) + " (" + what + "): " + message);
}

int type_components(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    default: return 0;
  }
}

// The bytes of bufferView `view` as a checked range of its buffer.
unsigned char* view_bytes(tinygltf::Model& model, int view, std::size_t& length, int index,
                          const std::string& what) {
  if (view < 0 || static_cast<std::size_t>(view) >= model.bufferViews.size())
    bad_accessor(index, what, "bufferView " + std::to_string(view) + " does not exist");
  const tinygltf::BufferView& bv = model.bufferViews[view];
  if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= model.buffers.size())
    bad_accessor(index, what, "bufferView " + std::to_string(view) + " names a buffer that does not exist");
  std::vector<unsigned char>& data = model.buffers[bv.buffer].data;
  if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
    bad_accessor(index, what, "bufferView " + std::to_string(view) + " runs past the end of buffer " +
                                  std::to_string(bv.buffer) + " (" + std::to_string(data.size()) + " bytes)");
  length = bv.byteLength;
  return data.data() + bv.byteOffset;
}

// Element i of a sparse accessor's index list.
std::uint32_t sparse_index(const unsigned char* p, int type, std::size_t i) {
  if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) return p[i];
  if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
    std::uint16_t v;
    std::memcpy(&v, p + 2 * i, 2);
    return v;
  }
  std::uint32_t v;
  std::memcpy(&v, p + 4 * i, 4);
  return v;
}

// Component i of an element at p as a float: a float as it is, an integer component
// (KHR_mesh_quantization) as its value, or, `normalized`, mapped to [0, 1] or [-1, 1]
// (glTF 2.0 section 3.11).
float component_value(const unsigned char* p, int type, bool normalized, int i) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const auto v = static_cast<std::int8_t>(p[i]);
      return normalized ? std::max(v / 127.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[i] / 255.0f : p[i];
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      std::int16_t v;
      std::memcpy(&v, p + 2 * i, 2);
      return normalized ? std::max(v / 32767.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t v;
      std::memcpy(&v, p + 2 * i, 2);
      return normalized ? v / 65535.0f : v;
    }
    default: {
      float v;
      std::memcpy(&v, p + 4 * i, 4);
      return v;
    }
  }
}

// Element k of n components at p into out[0..n).
void read_element(const unsigned char* p, int type, bool normalized, int n, float* out) {
  if (type == TINYGLTF_COMPONENT_TYPE_FLOAT) {
    std::memcpy(out, p, 4 * static_cast<std::size_t>(n));
    return;
  }
  for (int i = 0; i < n; ++i) out[i] = component_value(p, type, normalized, i);
}

// Substitutes a sparse accessor's values into `out` (count elements of `n` values).
void apply_sparse(tinygltf::Model& model, int index, int n, std::vector<float>& out, const std::string& what) {
  const tinygltf::Accessor& a = model.accessors[index];
  if (!a.sparse.isSparse) return;
  const auto count = static_cast<std::size_t>(std::max(a.sparse.count, 0));
  const int itype = a.sparse.indices.componentType;
  const std::size_t isize = component_size(itype);
  if (itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    bad_accessor(index, what, "sparse indices must be unsigned byte, short or int");
  std::size_t ilen = 0, vlen = 0;
  const unsigned char* ip = view_bytes(model, a.sparse.indices.bufferView, ilen, index, what);
  const unsigned char* vp = view_bytes(model, a.sparse.values.bufferView, vlen, index, what);
  const auto ioff = static_cast<std::size_t>(std::max(a.sparse.indices.byteOffset, 0));
  const auto voff = static_cast<std::size_t>(std::max(a.sparse.values.byteOffset, 0));
  const std::size_t vsize = component_size(a.componentType) * static_cast<std::size_t>(n);
  if (ioff > ilen || count > (ilen - ioff) / isize || voff > vlen || count > (vlen - voff) / vsize)
    bad_accessor(index, what, "sparse indices or values run past their bufferView");
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t i = sparse_index(ip + ioff, itype, k);
    if (i >= a.count) bad_accessor(index, what, "sparse index " + std::to_string(i) + " is past the accessor's count");
    read_element(vp + voff + k * vsize, a.componentType, a.normalized, n, &out[std::size_t(i) * n]);
  }
}

// Whether `a` holds `n`-component floats, or the integers KHR_mesh_quantization allows in
// their place (signed or unsigned bytes and shorts).
bool float_like(const tinygltf::Accessor& a, int n) {
  const int t = a.componentType;
  return type_components(a.type) == n &&
         (t == TINYGLTF_COMPONENT_TYPE_FLOAT || t == TINYGLTF_COMPONENT_TYPE_BYTE ||
          t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || t == TINYGLTF_COMPONENT_TYPE_SHORT ||
          t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
}

bool exists(const tinygltf::Model& model, int index) {
  return index >= 0 && static_cast<std::size_t>(index) < model.accessors.size();
}

// A float (or quantized) accessor of `n` components as count · n floats, sparse values
// applied.
std::vector<float> read_floats(tinygltf::Model& model, int index, int n, const std::string& what) {
  int type = TINYGLTF_COMPONENT_TYPE_FLOAT;  // accessor_span names any other
  bool normalized = false;
  if (exists(model, index) && float_like(model.accessors[index], n)) {
    type = model.accessors[index].componentType;
    normalized = model.accessors[index].normalized;
  }
  const AccessorSpan span = accessor_span(model, index, type, n, what);
  std::vector<float> out(span.count * n, 0.0f);
  if (span.data)
    for (std::size_t i = 0; i < span.count; ++i) read_element(span.data + i * span.stride, type, normalized, n, &out[i * n]);
  apply_sparse(model, index, n, out, what);
  return out;
}

}  // namespace

std::size_t component_size(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

AccessorSpan accessor_span(tinygltf::Model& model, int index, int component_type, int components,
                           const std::string& what) {
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size())
    throw InputError("accessor " + std::to_string(index) + " (" + what + ") does not exist");
  const tinygltf::Accessor& a = model.accessors[index];
  if (a.componentType != component_type || type_components(a.type) != components)
    bad_accessor(index, what, "has the wrong component type or element type");
  AccessorSpan span;
  span.count = a.count;
  const std::size_t element = component_size(component_type) * components;
  if (a.bufferView < 0) {  // all zero (sparse values may follow)
    // Nothing in the file backs the zeros, so a count is held to the buffers' size: a
    // 60-byte file must not ask for gigabytes.
    std::size_t bytes = 0;
    for (const tinygltf::Buffer& b : model.buffers) bytes += b.data.size();
    if (a.count > bytes)
      bad_accessor(index, what, std::to_string(a.count) + " elements without a bufferView are more than the file's " +
                                    std::to_string(bytes) + " bytes of buffers can back");
    return span;
  }
  std::size_t length = 0;
  unsigned char* bytes = view_bytes(model, a.bufferView, length, index, what);
  const std::size_t given = model.bufferViews[a.bufferView].byteStride;
  span.stride = given ? given : element;
  if (span.stride < element) bad_accessor(index, what, "byteStride is smaller than an element");
  const bool fits = a.count == 0 || (a.byteOffset <= length && element <= length - a.byteOffset &&
                                     (a.count - 1) <= (length - a.byteOffset - element) / span.stride);
  if (!fits) bad_accessor(index, what, std::to_string(a.count) + " elements run past the end of its bufferView");
  span.data = bytes + a.byteOffset;
  return span;
}

std::vector<Eigen::Vector3f> read_vec3(tinygltf::Model& model, int index, const std::string& what) {
  const std::vector<float> f = read_floats(model, index, 3, what);
  std::vector<Eigen::Vector3f> out(f.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {f[3 * i], f[3 * i + 1], f[3 * i + 2]};
  return out;
}

std::vector<Eigen::Vector2f> read_vec2(tinygltf::Model& model, int index, const std::string& what) {
  if (!exists(model, index) || !float_like(model.accessors[index], 2)) return {};
  const std::vector<float> f = read_floats(model, index, 2, what);
  std::vector<Eigen::Vector2f> out(f.size() / 2);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {f[2 * i], f[2 * i + 1]};
  return out;
}

std::vector<std::uint32_t> read_indices(tinygltf::Model& model, int index, std::size_t vertices,
                                        const std::string& what) {
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size())
    throw InputError("accessor " + std::to_string(index) + " (" + what + ") does not exist");
  const int type = model.accessors[index].componentType;
  if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    bad_accessor(index, what, "indices must be unsigned byte, short or int");
  if (model.accessors[index].sparse.isSparse) bad_accessor(index, what, "sparse indices are not supported");
  const AccessorSpan span = accessor_span(model, index, type, 1, what);
  std::vector<std::uint32_t> out(span.count, 0);
  for (std::size_t i = 0; i < span.count && span.data; ++i) {
    out[i] = sparse_index(span.data + i * span.stride, type, 0);
    if (out[i] >= vertices)
      bad_accessor(index, what, "index " + std::to_string(out[i]) + " at " + std::to_string(i) +
                                    " is past the primitive's " + std::to_string(vertices) + " vertices");
  }
  return out;
}

void write_vec3(tinygltf::Model& model, int index, const std::vector<Eigen::Vector3f>& values) {
  const AccessorSpan span = accessor_span(model, index, TINYGLTF_COMPONENT_TYPE_FLOAT, 3, "write");
  for (std::size_t i = 0; i < span.count; ++i) std::memcpy(span.data + i * span.stride, values[i].data(), 12);
}

int append_view(tinygltf::Model& model, const void* data, std::size_t bytes, int target) {
  if (model.buffers.empty()) model.buffers.emplace_back();
  std::vector<unsigned char>& buffer = model.buffers[0].data;
  buffer.resize((buffer.size() + 3) / 4 * 4, 0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.size();
  view.byteLength = bytes;
  view.target = target;
  buffer.resize(buffer.size() + bytes);
  if (bytes) std::memcpy(buffer.data() + view.byteOffset, data, bytes);
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size() - 1);
}

int append_accessor(tinygltf::Model& model, const void* data, std::size_t bytes, int component_type, int type,
                    std::size_t count, int target) {
  tinygltf::Accessor accessor;
  accessor.bufferView = append_view(model, data, bytes, target);
  accessor.byteOffset = 0;
  accessor.componentType = component_type;
  accessor.count = count;
  accessor.type = type;
  model.accessors.push_back(accessor);
  return static_cast<int>(model.accessors.size() - 1);
}

int append_vec3(tinygltf::Model& model, const std::vector<Eigen::Vector3f>& values) {
  const int index = append_accessor(model, values.data(), 12 * values.size(), TINYGLTF_COMPONENT_TYPE_FLOAT,
                                    TINYGLTF_TYPE_VEC3, values.size(), TINYGLTF_TARGET_ARRAY_BUFFER);
  set_bounds(model.accessors[index], values);
  return index;
}

void set_bounds(tinygltf::Accessor& accessor, const std::vector<Eigen::Vector3f>& values) {
  if (values.empty()) return;
  Eigen::Vector3f lo = values[0], hi = values[0];
  for (const Eigen::Vector3f& v : values) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  accessor.minValues = {lo.x(), lo.y(), lo.z()};
  accessor.maxValues = {hi.x(), hi.y(), hi.z()};
}

}  // namespace ffd
