// ZeroedArray: n values that start as zero bits without being written: calloc maps
// fresh pages, so only the pages a program writes or reads are ever faulted in. For large
// fields of which one step touches a small part (an octree level's subdivided
// displacements: a first move at level 5 writes a few thousand of its 490k slots).
#pragma once

#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>

namespace ffd {

template <class T>
class ZeroedArray {
  static_assert(std::is_trivially_copyable_v<T>, "zero bits must be a value of T");

public:
  ZeroedArray() = default;
  explicit ZeroedArray(std::size_t n) : data_(n ? static_cast<T*>(std::calloc(n, sizeof(T))) : nullptr), size_(n) {
    if (n && !data_) throw std::bad_alloc();
  }
  T* data() { return data_.get(); }
  const T* data() const { return data_.get(); }
  T& operator[](std::size_t i) { return data_.get()[i]; }
  const T& operator[](std::size_t i) const { return data_.get()[i]; }
  std::size_t size() const { return size_; }

private:
  struct Free {
    void operator()(T* p) const { std::free(p); }
  };
  std::unique_ptr<T, Free> data_;
  std::size_t size_ = 0;
};

}  // namespace ffd
