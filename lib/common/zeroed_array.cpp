#include "common/zeroed_array.h"

#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace ffd {
namespace {

// From here on an array is mapped: a few pages, where a mapping's cost (a system call,
// and a page per array at least) no longer matters beside what it saves.
constexpr std::size_t kMapped = std::size_t{64} << 10;

}  // namespace

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
