// ZeroedArray: n values that start as zero bits without being written. A large array is
// its own anonymous mapping of fresh pages, so only the pages a program writes or reads
// are ever faulted in; a small one comes from calloc. For large fields of which one step
// touches a small part (an octree level's subdivided displacements: a first move at level
// 5 writes a few thousand of its 490k slots). Mapped rather than left to calloc, which
// gives fresh pages only while the allocator maps large blocks itself: ffdtool keeps freed
// memory for reuse (its main), and calloc must clear reused memory, every page of it.
#pragma once

#include <cstddef>
#include <memory>
#include <type_traits>

namespace ffd {

/// Whether reserving `bytes` more than a program writes costs it nothing but unused
/// addresses: on Linux, when no limit counts its address space or data (RLIMIT_AS,
/// RLIMIT_DATA), the kernel does not charge untouched memory (vm.overcommit_memory is not
/// 2, strict), and `bytes` is at most a quarter of the machine's memory. Elsewhere false.
bool reserving_is_free(std::size_t bytes);

/// Sets `bytes` at p (memory from malloc or new) to zero bits. Large ranges give their
/// whole pages back to the kernel instead of writing them, so that a zero array nobody
/// reads costs no memory and no page faults (a run's deferred normals: 48 MB on a
/// 1M-vertex mesh): they fault in as zero pages when touched.
void zero_bits(void* p, std::size_t bytes);

/// `bytes` of zero bits: fresh pages when large; free with free_zeroed.
void* allocate_zeroed(std::size_t bytes);
void free_zeroed(void* p, std::size_t bytes) noexcept;

/// Faults in the pages of [p, p + bytes) for writing in one system call
/// (MADV_POPULATE_WRITE, Linux 5.14), for memory the caller is about to write whole: here
/// 0.65 us a page against 1.2-1.9 us for a fault per page. Nothing for a small range, or
/// where the advice is refused (the writes then fault as before).
void prefault(void* p, std::size_t bytes);

/// Asks that the whole 2 MiB pages inside [p, p + bytes) be transparent huge pages
/// (MADV_HUGEPAGE), for a large array about to be written front to back: each of its
/// 2 MiB is then one fault instead of 512. Where faults are dear this is much of a job's
/// time: on a 2-core virtual machine that traps each (10 us a 4 KiB page, against the
/// 1.2-1.9 us above on another) the 1M-vertex sphere's run took 30k faults, 300 ms of its
/// 700. Call it before the first write: a 2 MiB page with a 4 KiB page already in it stays
/// small. Only for memory written whole, or nearly, from its start: an untouched 2 MiB page
/// costs nothing, but a touched one holds all of its 2 MiB. Nothing for less than 4 MiB,
/// where the kernel does without transparent huge pages, or where the advice is refused.
void advise_huge_pages(const void* p, std::size_t bytes);

/// `bytes` of fresh memory aligned to 2 MiB, in transparent huge pages where the kernel
/// gives them (MADV_HUGEPAGE), for arrays of 1 MiB or more that are written from their
/// start: the 2 MiB page that holds the end is faulted in whole. Smaller arrays, and all
/// of them in the sanitizers' build (whose ASan checks the bounds of operator new's blocks
/// only), come from operator new. Free with free_huge_pages, with the same `bytes`.
void* allocate_huge_pages(std::size_t bytes, std::size_t alignment);
void free_huge_pages(void* p, std::size_t bytes, std::size_t alignment) noexcept;

/// A std::vector allocator of allocate_huge_pages's memory: a large vector whose every
/// growth is written whole (an octree level's tags) faults its pages in 2 MiB at a time.
template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(allocate_huge_pages(n * sizeof(T), alignof(T))); }
  void deallocate(T* p, std::size_t n) noexcept { free_huge_pages(p, n * sizeof(T), alignof(T)); }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const { return true; }
  template <class U>
  bool operator!=(const HugePageAllocator<U>&) const { return false; }
};

/// advise_huge_pages over a vector's reserved room, all of its capacity.
template <class Vector>
void advise_huge_pages_reserved(const Vector& v) {
  advise_huge_pages(v.data(), v.capacity() * sizeof(*v.data()));
}

template <class T>
class ZeroedArray {
  static_assert(std::is_trivially_copyable_v<T>, "zero bits must be a value of T");

public:
  ZeroedArray() = default;
  explicit ZeroedArray(std::size_t n)
      : data_(n ? static_cast<T*>(allocate_zeroed(n * sizeof(T))) : nullptr, Free{n * sizeof(T)}), size_(n) {}
  T* data() { return data_.get(); }
  const T* data() const { return data_.get(); }
  T& operator[](std::size_t i) { return data_.get()[i]; }
  const T& operator[](std::size_t i) const { return data_.get()[i]; }
  std::size_t size() const { return size_; }

private:
  struct Free {
    std::size_t bytes = 0;
    void operator()(T* p) const { free_zeroed(p, bytes); }
  };
  std::unique_ptr<T, Free> data_;
  std::size_t size_ = 0;
};

}  // namespace ffd
