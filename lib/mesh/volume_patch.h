// The two ways a volume file's node coordinates are rewritten in place (volume_mesh.h,
// VolumeFile): numbers in text, and fixed-size numbers in binary. Formats whose points
// are encoded further (a VTU's base64 or zlib blocks) write their own VolumeFile.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "mesh/volume_mesh.h"

namespace ffd {

/// Node coordinates written as text: node i's numbers are the bytes
/// [spans[2i], spans[2i + 1]) of the file (from its first number to the end of its last,
/// whatever separates them). A moved node's span becomes its `dimension` coordinates in
/// shortest round-trip form, separated by one space; the bytes between spans stay.
class TextPoints final : public VolumeFile {
public:
  /// \pre spans ascending, two per column of `as_read`; dimension 2 or 3.
  TextPoints(SharedBytes bytes, std::vector<std::uint64_t> spans, int dimension, Eigen::Matrix3Xd as_read);
  void write(std::ostream& os, const Eigen::Matrix3Xd& positions) const override;

private:
  SharedBytes bytes_;
  std::vector<std::uint64_t> spans_;
  int dimension_;
  Eigen::Matrix3Xd as_read_;
};

/// Whether a file's numbers in big-endian (else little-endian) order need their bytes
/// reversed on this machine.
inline bool swapped_order(bool big_endian) { return big_endian != (__BYTE_ORDER__ == __ORDER_BIG_ENDIAN__); }

/// A T stored at `at` (any alignment), its bytes reversed when `swap`: what every binary
/// volume reader reads numbers with.
template <class T>
T load_bytes(const char* at, bool swap) {
  char b[sizeof(T)];
  std::memcpy(b, at, sizeof b);
  if (swap) std::reverse(b, b + sizeof b);
  T value;
  std::memcpy(&value, b, sizeof value);
  return value;
}

/// Stores `value` at `at`, its bytes reversed when `swap`.
template <class T>
void store_bytes(char* at, T value, bool swap) {
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof b);
  if (swap) std::reverse(b, b + sizeof b);
  std::memcpy(at, b, sizeof b);
}

/// How a binary file stores one coordinate.
struct BinaryScalar {
  bool is_double = true;       // float64, else float32
  bool big_endian = false;
};

/// A run of nodes stored alike: node first + j's coordinate k at
/// offset + j * stride + k * (4 or 8 bytes).
struct BinaryBlock {
  std::uint64_t first = 0, count = 0;
  std::uint64_t offset = 0, stride = 0;
};

/// Node coordinates stored as fixed-size binary numbers: the file's bytes with each moved
/// node's `dimension` coordinates overwritten where they are (the size never changes).
class BinaryPoints final : public VolumeFile {
public:
  /// \pre the blocks cover nodes 0..n-1 in order and lie inside `bytes`.
  BinaryPoints(SharedBytes bytes, std::vector<BinaryBlock> blocks, BinaryScalar scalar, int dimension);
  void write(std::ostream& os, const Eigen::Matrix3Xd& positions) const override;

private:
  SharedBytes bytes_;
  std::vector<BinaryBlock> blocks_;
  BinaryScalar scalar_;
  int dimension_;
};

/// Reads coordinate k of a BinaryBlock's node j (widened to double), for readers that
/// describe their points as blocks.
double read_binary_scalar(const char* at, BinaryScalar scalar);
/// Writes x at `at` as `scalar` stores it (float32: rounded to nearest).
void write_binary_scalar(char* at, double x, BinaryScalar scalar);

/// Whether a node at `position` is still where it was read, as the file stores it: equal
/// doubles, or for float32 storage equal after rounding to float32.
inline bool unmoved(const Eigen::Vector3d& position, const Eigen::Vector3d& as_read, bool float32) {
  if (!float32) return position == as_read;
  return static_cast<float>(position.x()) == static_cast<float>(as_read.x()) &&
         static_cast<float>(position.y()) == static_cast<float>(as_read.y()) &&
         static_cast<float>(position.z()) == static_cast<float>(as_read.z());
}

}  // namespace ffd
