// Reading and writing glTF accessors with every offset checked against its buffer: a
// malformed file gets an InputError naming the accessor, never an out-of-bounds read.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/gltf_scene.h"

namespace ffd {

/// Where an accessor's elements are: element i starts at data + i · stride.
struct AccessorSpan {
  unsigned char* data = nullptr;  // null for an accessor without a bufferView (all zero)
  std::size_t stride = 0;
  std::size_t count = 0;
};

/// The bytes of one component of TINYGLTF_COMPONENT_TYPE_* `type` (0 for an unknown one).
std::size_t component_size(int type);

/// The checked span of accessor `index` holding `components` values of `component_type`
/// each. `what` names it in errors ("POSITION of mesh 0 primitive 1").
/// \throw InputError ("accessor 3 (what): ...") for a wrong type or an out-of-range view.
AccessorSpan accessor_span(tinygltf::Model& model, int index, int component_type, int components,
                           const std::string& what);

/// A float VEC3 accessor's values, sparse substitution applied. Integer components
/// (KHR_mesh_quantization: signed or unsigned bytes and shorts) are dequantized: their
/// value, or, normalized, mapped to [0, 1] or [-1, 1].
std::vector<Eigen::Vector3f> read_vec3(tinygltf::Model& model, int index, const std::string& what);
/// A float (or quantized) VEC2 accessor's values (TEXCOORD_n), or empty for another
/// component type.
std::vector<Eigen::Vector2f> read_vec2(tinygltf::Model& model, int index, const std::string& what);
/// An index accessor's values (unsigned byte, short or int SCALAR), each < `vertices`.
std::vector<std::uint32_t> read_indices(tinygltf::Model& model, int index, std::size_t vertices,
                                        const std::string& what);

/// Overwrites a dense float VEC3 accessor's values in their buffer (strides kept).
/// \pre the accessor is not sparse, has a bufferView and values.size() == count.
void write_vec3(tinygltf::Model& model, int index, const std::vector<Eigen::Vector3f>& values);
/// Appends `bytes` bytes at `data` to buffer 0 (4-byte aligned) as a new bufferView
/// (`target`: TINYGLTF_TARGET_*, 0 for none); returns its index.
int append_view(tinygltf::Model& model, const void* data, std::size_t bytes, int target);
/// Appends `bytes` bytes at `data` to buffer 0 (4-byte aligned) as a new bufferView
/// (`target`: TINYGLTF_TARGET_*) and a new accessor of `count` elements of `type`
/// (TINYGLTF_TYPE_*) and `component_type`; returns the accessor's index.
int append_accessor(tinygltf::Model& model, const void* data, std::size_t bytes, int component_type, int type,
                    std::size_t count, int target);
/// append_accessor of float VEC3 values, with min and max set.
int append_vec3(tinygltf::Model& model, const std::vector<Eigen::Vector3f>& values);
/// Sets a VEC3 accessor's min and max to those of `values` (POSITION needs them).
void set_bounds(tinygltf::Accessor& accessor, const std::vector<Eigen::Vector3f>& values);

}  // namespace ffd
