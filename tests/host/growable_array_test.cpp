// The arrays a mesh is collected into for callers in memory (src/write/mesh/growable_array.h):
// they keep every number through growth from malloc's blocks to mappings and from mapping to
// larger mapping, grow large arrays without moving their pages by copying, and give memory back
// when trimmed, and the memory of one array given back serves the next.
#include "write/mesh/growable_array.h"

#include <gtest/gtest.h>
#include <sys/mman.h>

#include <cstdint>
#include <utility>

namespace mvox {
namespace {

// Fills [from, to) with a pattern of its positions, then checks [0, to) holds it.
void fill(GrowableArray<std::uint32_t>& array, std::size_t from, std::size_t to) {
  array.resize(to);
  for (std::size_t i = from; i < to; ++i) array[i] = static_cast<std::uint32_t>(i * 2654435761u);
}
bool holds_pattern(const GrowableArray<std::uint32_t>& array) {
  for (std::size_t i = 0; i < array.size(); ++i)
    if (array[i] != static_cast<std::uint32_t>(i * 2654435761u)) return false;
  return true;
}

TEST(GrowableArray, KeepsItsNumbersThroughEveryKindOfGrowth) {
  GrowableArray<std::uint32_t> array;
  EXPECT_TRUE(array.empty());
  std::size_t size = 0;
  // From a few numbers (malloc) past 1 MiB (its own mapping) to 100 MB (grown mapping), in
  // steps of different sizes.
  for (std::size_t next : {std::size_t{3}, std::size_t{1000}, std::size_t{200000},
                           std::size_t{300000}, std::size_t{5000000}, std::size_t{25000000}}) {
    fill(array, size, next);
    size = next;
    ASSERT_EQ(array.size(), size);
    ASSERT_GE(array.capacity(), size);
    ASSERT_TRUE(holds_pattern(array)) << "after growing to " << size;
  }
}

TEST(GrowableArray, ReserveGivesRoomWithoutChangingTheSize) {
  GrowableArray<float> array{1.5f, 2.5f};
  array.reserve(3000000);
  EXPECT_EQ(array.size(), 2u);
  EXPECT_GE(array.capacity(), 3000000u);
  EXPECT_EQ(array[0], 1.5f);
  EXPECT_EQ(array[1], 2.5f);
  const float* before = array.data();
  array.resize(3000000);  // within the room: no move
  EXPECT_EQ(array.data(), before);
}

TEST(GrowableArray, ShrinkingToFitKeepsTheNumbersAndFreesTheRest) {
  GrowableArray<std::uint32_t> array;
  array.reserve(10000000);
  fill(array, 0, 300000);
  array.shrink_to_fit();
  EXPECT_LT(array.capacity(), 400000u);
  EXPECT_GE(array.capacity(), 300000u);
  EXPECT_TRUE(holds_pattern(array));
  fill(array, 300000, 3000000);  // and it grows again from there
  EXPECT_TRUE(holds_pattern(array));
}

TEST(GrowableArray, MovesHandOverTheMemory) {
  GrowableArray<std::uint32_t> first;
  fill(first, 0, 2000000);
  const std::uint32_t* data = first.data();
  GrowableArray<std::uint32_t> second(std::move(first));
  EXPECT_EQ(second.data(), data);
  EXPECT_EQ(second.size(), 2000000u);
  EXPECT_TRUE(first.empty());
  EXPECT_EQ(first.capacity(), 0u);
  GrowableArray<std::uint32_t> third{7u};
  third = std::move(second);
  EXPECT_EQ(third.data(), data);
  EXPECT_TRUE(holds_pattern(third));
}

// A fresh mapping costs a fault and the kernel's zeroing per page; one given back is kept for
// the next array (a caller extracting mesh after mesh).
TEST(GrowableArray, TheNextLargeArrayReusesTheMappingOneGaveBack) {
  constexpr std::size_t kNumbers = 3333333;  // a size no other test here gives back
  const void* given_back = nullptr;
  {
    GrowableArray<std::uint32_t> first;
    first.reserve(kNumbers);
    fill(first, 0, kNumbers);
    given_back = first.data();
  }
  GrowableArray<std::uint32_t> next;
  next.reserve(kNumbers);
  EXPECT_EQ(next.data(), given_back);
  fill(next, 0, kNumbers);
  EXPECT_TRUE(holds_pattern(next));
}

// An array that cannot grow in place while a larger mapping is kept must still grow, twice:
// moving its pages over the start of the kept mapping left two mappings the next mremap could
// not take whole (std::bad_alloc).
TEST(GrowableArray, GrowsAgainAfterMovingWhileAMappingIsKept) {
  GrowableArray<std::uint32_t> array;
  fill(array, 0, 500000);  // 2 MB: its own mapping
  {
    GrowableArray<std::uint32_t> given_back;
    given_back.reserve(2000000);
  }  // 8 MB kept
  // The page after the array taken, so that it cannot grow in place.
  char* const after =
      reinterpret_cast<char*>(array.data()) + array.capacity() * sizeof(std::uint32_t);
  void* const block =
      ::mmap(after, 4096, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED_NOREPLACE, -1, 0);
  fill(array, 500000, 750000);   // 3 MB
  fill(array, 750000, 2250000);  // 9 MB
  EXPECT_TRUE(holds_pattern(array));
  if (block != MAP_FAILED) ::munmap(block, 4096);
}

// A size the kernel refuses to map (1 EiB): std::bad_alloc, with the size noted for the
// message (failed_allocation.h), and the array as it was.
TEST(GrowableArray, AnImpossibleSizeIsBadAllocWithItsSizeNoted) {
  GrowableArray<std::uint32_t> array;
  fill(array, 0, 10);
  note_failed_allocation(0);
  const std::size_t exbibyte = std::size_t{1} << 60;
  EXPECT_THROW(array.reserve(exbibyte / sizeof(std::uint32_t)), std::bad_alloc);
  EXPECT_EQ(failed_allocation_bytes(), exbibyte);
  EXPECT_EQ(array.size(), 10u);
  EXPECT_TRUE(holds_pattern(array));
}

}  // namespace
}  // namespace mvox
