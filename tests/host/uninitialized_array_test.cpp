// UninitializedArray (src/write/mesh/uninitialized_array.h): growing keeps the values written
// before, in place or moved, and a moved-from array is empty; the room past size() is never
// read by it, so a sanitizer or valgrind run sees no read of an unwritten value here.
#include "write/mesh/uninitialized_array.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <utility>

namespace mvox {
namespace {

TEST(UninitializedArray, GrowingKeepsWhatWasWritten) {
  UninitializedArray<std::uint32_t> values;
  EXPECT_EQ(values.size(), 0u);
  EXPECT_EQ(values.data(), nullptr);
  // Grown one value at a time past several reallocations, each value written after its growth.
  for (std::uint32_t i = 0; i < 10000; ++i) {
    values.resize(i + 1);
    values[i] = i * 7 + 1;
  }
  ASSERT_EQ(values.size(), 10000u);
  EXPECT_GE(values.capacity(), 10000u);
  for (std::uint32_t i = 0; i < 10000; ++i) ASSERT_EQ(values[i], i * 7 + 1) << i;
  // Reserving more moves them, shrinking the size keeps the room.
  values.reserve(1 << 20);
  EXPECT_EQ(values.capacity(), std::size_t{1} << 20);
  values.resize(5);
  EXPECT_EQ(values.capacity(), std::size_t{1} << 20);
  for (std::uint32_t i = 0; i < 5; ++i) EXPECT_EQ(values[i], i * 7 + 1);
}

TEST(UninitializedArray, MovingHandsTheValuesOver) {
  UninitializedArray<std::uint64_t> values;
  values.resize(3);
  values[0] = 1;
  values[1] = 2;
  values[2] = 3;
  UninitializedArray<std::uint64_t> taken(std::move(values));
  EXPECT_EQ(values.size(), 0u);
  EXPECT_EQ(values.data(), nullptr);
  ASSERT_EQ(taken.size(), 3u);
  EXPECT_EQ(taken[2], 3u);
  UninitializedArray<std::uint64_t> other;
  other.resize(1);
  other[0] = 9;
  other = std::move(taken);
  ASSERT_EQ(other.size(), 3u);
  EXPECT_EQ(other[0], 1u);
}

// Too many values for the address space, and a size malloc refuses (1 EiB): std::bad_alloc,
// with the size noted for main()'s "out of memory" line (failed_allocation.h).
TEST(UninitializedArray, AnImpossibleSizeIsBadAllocWithItsSizeNoted) {
  UninitializedArray<std::uint64_t> values;
  note_failed_allocation(0);
  EXPECT_THROW(values.reserve(static_cast<std::size_t>(-1) / 4), std::bad_alloc);
  EXPECT_EQ(failed_allocation_bytes(), static_cast<std::size_t>(-1));
  EXPECT_EQ(values.capacity(), 0u);
  const std::size_t exbibyte = std::size_t{1} << 60;
  EXPECT_THROW(values.reserve(exbibyte / sizeof(std::uint64_t)), std::bad_alloc);
  EXPECT_EQ(failed_allocation_bytes(), exbibyte);
  EXPECT_EQ(values.capacity(), 0u);
}

}  // namespace
}  // namespace mvox
