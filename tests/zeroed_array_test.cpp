// Zero bits without writing them: zero_bits over memory in use, and ZeroedArray.
#include <gtest/gtest.h>

#include <sys/mman.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/zeroed_array.h"

namespace ffd {
namespace {

// The first byte in [first, last) that is not `value`, or last - first when there is none.
std::size_t first_not(const std::vector<unsigned char>& bytes, std::size_t first, std::size_t last, unsigned char value) {
  for (std::size_t i = first; i < last; ++i)
    if (bytes[i] != value) return i - first;
  return last - first;
}

TEST(ZeroBits, ZeroesEveryByteOfTheRangeAndNoOtherAtAnyAlignment) {
  // Ranges below and above the size from which whole pages are given back, starting and
  // ending on and off page boundaries, in memory that has been written.
  std::vector<unsigned char> bytes((std::size_t{3} << 20) + 3 * 4096);
  const std::size_t page = 4096;
  const auto base = reinterpret_cast<std::uintptr_t>(bytes.data());
  const std::size_t aligned = (page - base % page) % page;  // offset of the first page boundary
  struct Range {
    std::size_t offset, size;
  };
  for (const Range r : {Range{1, 100}, Range{aligned, page}, Range{aligned + 7, (std::size_t{1} << 20) + 13},
                        Range{aligned, std::size_t{2} << 20}, Range{aligned + page - 1, (std::size_t{2} << 20) + 2},
                        Range{3, (std::size_t{3} << 20) - 5}}) {
    std::fill(bytes.begin(), bytes.end(), 0xab);
    zero_bits(bytes.data() + r.offset, r.size);
    ASSERT_EQ(first_not(bytes, 0, r.offset, 0xab), r.offset) << r.offset << " " << r.size;
    ASSERT_EQ(first_not(bytes, r.offset, r.offset + r.size, 0), r.size) << r.offset << " " << r.size;
    ASSERT_EQ(first_not(bytes, r.offset + r.size, bytes.size(), 0xab), bytes.size() - r.offset - r.size);
    // The memory is still the vector's: it takes writes and reads them back.
    bytes[r.offset + r.size / 2] = 0x5a;
    EXPECT_EQ(bytes[r.offset + r.size / 2], 0x5a);
  }
}

// Memory advice `advise(p, size)` over ranges of written memory (bytes around and inside
// them, starting on and off page boundaries, of each of `sizes`) changes none of its bytes.
void expect_advice_keeps_bytes(void (*advise)(void*, std::size_t), const std::vector<std::size_t>& sizes) {
  std::vector<unsigned char> bytes(*std::max_element(sizes.begin(), sizes.end()) + 3 * 4096);
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<unsigned char>(i * 7 + 1);
  const std::vector<unsigned char> before = bytes;
  for (const std::size_t offset : {std::size_t{1}, std::size_t{4093}})
    for (const std::size_t size : sizes) {
      advise(bytes.data() + offset, size);
      ASSERT_TRUE(bytes == before) << offset << " " << size;
    }
}

TEST(Prefault, KeepsEveryByteOfMemoryInUse) {
  // Faulting pages in for writing must not change what they hold, small ranges and large,
  // and fresh memory reads as zeros after it.
  expect_advice_keeps_bytes(prefault, {100, std::size_t{1} << 20, (std::size_t{2} << 20) + 5});
  ZeroedArray<double> fresh(std::size_t{1} << 18);
  prefault(fresh.data(), fresh.size() * sizeof(double));
  EXPECT_TRUE(std::all_of(fresh.data(), fresh.data() + fresh.size(), [](double v) { return v == 0.0; }));
}

// The kB of transparent huge pages in this process's mapping that holds p (smaps), or -1.
long huge_kb_at(const void* p) {
  std::ifstream smaps("/proc/self/smaps");
  const auto at = reinterpret_cast<std::uintptr_t>(p);
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
      inside = lo <= at && at < hi;
    } else if (inside && line.rfind("AnonHugePages:", 0) == 0) {
      return std::stol(line.substr(14));
    }
  }
  return -1;
}

// Whether the kernel gives huge pages to memory that asks for them ([always] or [madvise]).
bool huge_pages_on_advice() {
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string mode;
  std::getline(f, mode);
  return mode.find("[always]") != std::string::npos || mode.find("[madvise]") != std::string::npos;
}

TEST(HugePages, AdviceKeepsEveryByteAndFreshMemoryGetsHugePages) {
  // Advice over memory in use, below and above the 4 MiB it needs and off 2 MiB
  // boundaries, changes none of its bytes.
  expect_advice_keeps_bytes([](void* p, std::size_t size) { advise_huge_pages(p, size); },
                            {100, std::size_t{3} << 20, (std::size_t{8} << 20) + 5});
  // Fresh memory advised before its first write: the 2 MiB pages inside it are huge ones,
  // where the kernel gives them on advice (the point: one fault each instead of 512).
  const std::size_t size = std::size_t{10} << 20;
  void* fresh = mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(fresh, MAP_FAILED);
  advise_huge_pages(fresh, size);
  auto* values = static_cast<double*>(fresh);
  for (std::size_t i = 0; i < size / sizeof(double); ++i) values[i] = static_cast<double>(i);
  EXPECT_EQ(values[12345], 12345.0);
  if (huge_pages_on_advice())
    EXPECT_GE(huge_kb_at(fresh), 2048) << "no huge page in the advised mapping";
  else
    std::printf("transparent huge pages are off here: only the bytes were checked\n");
  munmap(fresh, size);
}

struct alignas(64) Line {
  double values[8];
};

TEST(HugePages, AVectorKeepsItsValuesAsItGrowsAndItsLargeBlocksGetHugePages) {
  // Grown one value at a time past 1 MiB and on to 5 MiB (blocks of operator new, then
  // mappings), the vector keeps every value and its alignment.
  std::vector<Line, HugePageAllocator<Line>> lines;
  const std::size_t n = (std::size_t{5} << 20) / sizeof(Line) + 3;
  for (std::size_t i = 0; i < n; ++i) {
    lines.push_back(Line{{static_cast<double>(i), 0, 0, 0, 0, 0, 0, -static_cast<double>(i)}});
    ASSERT_EQ(reinterpret_cast<std::uintptr_t>(lines.data()) % alignof(Line), 0u) << i;
  }
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < n; ++i)
    wrong += lines[i].values[0] != static_cast<double>(i) || lines[i].values[7] != -static_cast<double>(i);
  EXPECT_EQ(wrong, 0u);
  std::vector<Line, HugePageAllocator<Line>> copy = lines;  // and copies as any vector
  EXPECT_EQ(copy[n - 1].values[7], -static_cast<double>(n - 1));
#ifndef FFD_SANITIZE
  // A large block starts on a 2 MiB boundary and is written in huge pages (where the
  // kernel gives them on advice); the sanitizers' build keeps operator new's blocks.
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(lines.data()) % (std::uintptr_t{2} << 20), 0u);
  if (huge_pages_on_advice()) {
    EXPECT_GE(huge_kb_at(lines.data()), 2048) << "no huge page in the vector's block";
  }
#endif
}

TEST(ZeroedArray, StartsAsZerosSmallAndLarge) {
  for (std::size_t n : {std::size_t{10}, std::size_t{1} << 20}) {
    ZeroedArray<double> a(n);
    std::size_t nonzero = 0;
    for (std::size_t i = 0; i < n; ++i) nonzero += a[i] != 0.0;
    EXPECT_EQ(nonzero, 0u) << n;
    a[n - 1] = 2.5;
    EXPECT_EQ(a[n - 1], 2.5);
  }
}

}  // namespace
}  // namespace ffd
