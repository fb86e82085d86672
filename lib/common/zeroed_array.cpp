#include "common/zeroed_array.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <fstream>
#endif

namespace ffd {
namespace {

// From here on an array is mapped: a few pages, where a mapping's cost (a system call,
// and a page per array at least) no longer matters beside what it saves.
constexpr std::size_t kMapped = std::size_t{64} << 10;
// A transparent huge page.
constexpr std::size_t kHugePage = std::size_t{2} << 20;

}  // namespace

bool reserving_is_free(std::size_t bytes) {
#if defined(__linux__)
  for (int resource : {RLIMIT_AS, RLIMIT_DATA}) {
    rlimit limit{};
    if (getrlimit(resource, &limit) != 0 || limit.rlim_cur != RLIM_INFINITY) return false;
  }
  int mode = -1;
  std::ifstream("/proc/sys/vm/overcommit_memory") >> mode;
  if (mode != 0 && mode != 1) return false;
  const double memory = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
  return static_cast<double>(bytes) <= memory / 4;
#else
  (void)bytes;
  return false;
#endif
}

void* allocate_zeroed(std::size_t bytes) {
#if defined(__linux__)
  if (bytes >= kMapped) {
    void* p = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    return p;
  }
#endif
  void* p = std::calloc(bytes, 1);
  if (!p) throw std::bad_alloc();
  return p;
}

void zero_bits(void* p, std::size_t bytes) {
#if defined(__linux__)
  if (bytes >= kMapped) {
    const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
    const auto first = reinterpret_cast<std::uintptr_t>(p), last = first + bytes;
    const std::uintptr_t inner_first = (first + page - 1) & ~(page - 1), inner_last = last & ~(page - 1);
    // Private anonymous memory (malloc's) reads as zero pages after MADV_DONTNEED. Where
    // the advice is refused (hugetlb pages, other mappings), the bytes are written.
    if (::madvise(reinterpret_cast<void*>(inner_first), inner_last - inner_first, MADV_DONTNEED) == 0) {
      std::memset(p, 0, inner_first - first);
      std::memset(reinterpret_cast<void*>(inner_last), 0, last - inner_last);
      return;
    }
  }
#endif
  std::memset(p, 0, bytes);
}

void prefault(void* p, std::size_t bytes) {
#if defined(__linux__)
#ifndef MADV_POPULATE_WRITE
  constexpr int MADV_POPULATE_WRITE = 23;  // Linux 5.14; older kernels refuse it (EINVAL)
#endif
  if (bytes < kMapped) return;
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const auto first = reinterpret_cast<std::uintptr_t>(p) & ~(page - 1);
  const auto last = (reinterpret_cast<std::uintptr_t>(p) + bytes + page - 1) & ~(page - 1);
  ::madvise(reinterpret_cast<void*>(first), last - first, MADV_POPULATE_WRITE);  // advice: failing it changes nothing
#else
  (void)p, (void)bytes;
#endif
}

void advise_huge_pages(const void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = kHugePage;
  if (bytes < 2 * kHuge) return;
  const auto first = (reinterpret_cast<std::uintptr_t>(p) + kHuge - 1) & ~(kHuge - 1);
  const auto last = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(kHuge - 1);
  if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);  // advice: failing it changes nothing
#else
  (void)p, (void)bytes;
#endif
}

// Not in the sanitizers' build: ASan checks the bounds of operator new's blocks, not of
// mappings.
#if defined(__linux__) && defined(MADV_HUGEPAGE) && !defined(FFD_SANITIZE)
#define FFD_HUGE_PAGE_ARRAYS 1
namespace {

// From here on an array gets whole huge pages: 2 MiB for 1 MiB or more of 4 KiB pages
// (256 faults at 6-10 us each on a 2-core virtual machine, against one).
constexpr std::size_t kHugeFrom = kHugePage / 2;

std::size_t huge_extent(std::size_t bytes) { return (bytes + kHugePage - 1) & ~(kHugePage - 1); }

}  // namespace
#endif

void* allocate_huge_pages(std::size_t bytes, std::size_t alignment) {
#ifdef FFD_HUGE_PAGE_ARRAYS
  if (bytes >= kHugeFrom) {
    // Map 2 MiB more than the extent, keep the aligned extent, give back the rest.
    const std::size_t extent = huge_extent(bytes);
    void* raw = ::mmap(nullptr, extent + kHugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const auto first = reinterpret_cast<std::uintptr_t>(raw);
    const std::uintptr_t aligned = (first + kHugePage - 1) & ~(kHugePage - 1);
    if (aligned > first) ::munmap(raw, aligned - first);
    if (const std::uintptr_t end = first + extent + kHugePage; end > aligned + extent)
      ::munmap(reinterpret_cast<void*>(aligned + extent), end - aligned - extent);
    ::madvise(reinterpret_cast<void*>(aligned), extent, MADV_HUGEPAGE);  // advice: failing it changes nothing
    return reinterpret_cast<void*>(aligned);
  }
#endif
  return ::operator new(bytes, std::align_val_t(alignment));
}

void free_huge_pages(void* p, std::size_t bytes, std::size_t alignment) noexcept {
  if (!p) return;
#ifdef FFD_HUGE_PAGE_ARRAYS
  if (bytes >= kHugeFrom) {
    ::munmap(p, huge_extent(bytes));
    return;
  }
#endif
  ::operator delete(p, std::align_val_t(alignment));
}

void free_zeroed(void* p, std::size_t bytes) noexcept {
  if (!p) return;
#if defined(__linux__)
  if (bytes >= kMapped) {
    ::munmap(p, bytes);
    return;
  }
#endif
  std::free(p);
}

}  // namespace ffd
