#include "mesh/volume_patch.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "common/numbers.h"

namespace ffd {

TextPoints::TextPoints(SharedBytes bytes, std::vector<std::uint64_t> spans, int dimension, Eigen::Matrix3Xd as_read)
    : bytes_(std::move(bytes)), spans_(std::move(spans)), dimension_(dimension), as_read_(std::move(as_read)) {}

void TextPoints::write(std::ostream& os, const Eigen::Matrix3Xd& positions) const {
  const std::string_view text = bytes_->view();
  std::string chunk;
  std::uint64_t kept = 0;  // text[kept, ...) is not yet written
  auto flush = [&] {
    os.write(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    chunk.clear();
  };
  for (Eigen::Index i = 0; i < positions.cols(); ++i) {
    const Eigen::Vector3d p = positions.col(i);
    if (p == as_read_.col(i)) continue;
    const std::uint64_t begin = spans_[2 * i], end = spans_[2 * i + 1];
    chunk.append(text.substr(kept, begin - kept));
    for (int k = 0; k < dimension_; ++k) {
      if (k) chunk += ' ';
      append_number(chunk, p[k]);
    }
    kept = end;
    if (chunk.size() > (1u << 20)) flush();
  }
  flush();
  os.write(text.data() + kept, static_cast<std::streamsize>(text.size() - kept));
}

double read_binary_scalar(const char* at, BinaryScalar scalar) {
  const bool swap = swapped_order(scalar.big_endian);
  return scalar.is_double ? load_bytes<double>(at, swap) : load_bytes<float>(at, swap);
}

void write_binary_scalar(char* at, double x, BinaryScalar scalar) {
  const bool swap = swapped_order(scalar.big_endian);
  if (scalar.is_double)
    store_bytes<double>(at, x, swap);
  else
    store_bytes<float>(at, static_cast<float>(x), swap);
}

BinaryPoints::BinaryPoints(SharedBytes bytes, std::vector<BinaryBlock> blocks, BinaryScalar scalar, int dimension)
    : bytes_(std::move(bytes)), blocks_(std::move(blocks)), scalar_(scalar), dimension_(dimension) {}

void BinaryPoints::write(std::ostream& os, const Eigen::Matrix3Xd& positions) const {
  // The file's bytes go out as they are up to each moved node, then that node's
  // coordinates: no copy of the whole file.
  const std::string_view bytes = bytes_->view();
  const std::size_t size = scalar_.is_double ? 8 : 4;
  std::uint64_t kept = 0;  // bytes[kept, ...) is not yet written
  char patched[3 * 8];
  for (const BinaryBlock& block : blocks_)
    for (std::uint64_t j = 0; j < block.count; ++j) {
      const Eigen::Vector3d p = positions.col(static_cast<Eigen::Index>(block.first + j));
      const std::uint64_t at = block.offset + j * block.stride;
      Eigen::Vector3d stored(0, 0, 0);
      for (int k = 0; k < dimension_; ++k) stored[k] = read_binary_scalar(bytes.data() + at + k * size, scalar_);
      Eigen::Vector3d compared = p;
      if (dimension_ == 2) compared.z() = 0;
      if (unmoved(compared, stored, !scalar_.is_double)) continue;
      for (int k = 0; k < dimension_; ++k) write_binary_scalar(patched + k * size, p[k], scalar_);
      os.write(bytes.data() + kept, static_cast<std::streamsize>(at - kept));
      os.write(patched, static_cast<std::streamsize>(dimension_ * size));
      kept = at + dimension_ * size;
    }
  os.write(bytes.data() + kept, static_cast<std::streamsize>(bytes.size() - kept));
}

}  // namespace ffd
