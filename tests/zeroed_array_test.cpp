// Zero bits without writing them: zero_bits over memory in use, and ZeroedArray.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
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

TEST(Prefault, KeepsEveryByteOfMemoryInUse) {
  // Faulting pages in for writing must not change what they hold: a range with written
  // bytes around and inside it, on and off page boundaries, small and large, and fresh
  // memory (reads as zeros after it).
  std::vector<unsigned char> bytes((std::size_t{2} << 20) + 3 * 4096);
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<unsigned char>(i * 7 + 1);
  const std::vector<unsigned char> before = bytes;
  for (const std::size_t offset : {std::size_t{1}, std::size_t{4093}})
    for (const std::size_t size : {std::size_t{100}, std::size_t{1} << 20, (std::size_t{2} << 20) + 5}) {
      prefault(bytes.data() + offset, size);
      ASSERT_TRUE(bytes == before) << offset << " " << size;
    }
  ZeroedArray<double> fresh(std::size_t{1} << 18);
  prefault(fresh.data(), fresh.size() * sizeof(double));
  EXPECT_TRUE(std::all_of(fresh.data(), fresh.data() + fresh.size(), [](double v) { return v == 0.0; }));
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
