// Read buffers (src/read/read_buffer.h): page-aligned, and inside a ReadBufferReuse scope the
// block a thread frees goes to its next buffer of that size, as a slab worker's readers need,
// one slab after another, instead of being mapped and unmapped each time.
#include "read/read_buffer.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <new>
#include <thread>

namespace mvox {
namespace {

bool page_aligned(const void* data) { return reinterpret_cast<std::uintptr_t>(data) % 4096 == 0; }

// A 256x256 slice of 16-bit samples: the size from which malloc maps a block of its own.
constexpr std::size_t kSliceBytes = 256 * 256 * 2;

TEST(ReadBuffer, InAReuseScopeTheNextBufferOfTheSameSizeGetsTheFreedBlock) {
  const ReadBufferReuse reuse;
  const unsigned char* first = nullptr;
  {
    ReadBuffer slab_one(kSliceBytes);
    first = slab_one.data();
    EXPECT_TRUE(page_aligned(first));
  }
  // An allocation of the same size and alignment in between, which the allocator would give the
  // freed block were it not kept.
  void* const in_between = ::operator new (kSliceBytes, std::align_val_t{4096});
  ReadBuffer slab_two(kSliceBytes);
  EXPECT_EQ(slab_two.data(), first) << "the second slab's reader did not get the first's block";
  EXPECT_NE(in_between, static_cast<const void*>(first));
  ::operator delete (in_between, std::align_val_t{4096});
  EXPECT_TRUE(page_aligned(slab_two.data()));
  // Taken: a second buffer alongside gets a block of its own, and so does another size.
  ReadBuffer alongside(kSliceBytes);
  EXPECT_NE(alongside.data(), slab_two.data());
  ReadBuffer other_size(kSliceBytes / 2);
  EXPECT_TRUE(page_aligned(other_size.data()));
}

// A request of another size returns the kept block before it takes its own, so that a reader
// whose buffers change size (an image stack's files) holds one buffer at a time, as planned.
TEST(ReadBuffer, ARequestOfAnotherSizeReturnsTheKeptBlockFirst) {
  const ReadBufferReuse reuse;
  EXPECT_EQ(reuse.kept_bytes(), 0u);
  { ReadBuffer first(kSliceBytes); }
  EXPECT_EQ(reuse.kept_bytes(), kSliceBytes);
  {
    ReadBuffer other_size(kSliceBytes + 4096);
    EXPECT_EQ(reuse.kept_bytes(), 0u) << "the kept block lies beside a new one";
  }
  EXPECT_EQ(reuse.kept_bytes(), kSliceBytes + 4096);
}

TEST(ReadBuffer, OnlyTheLatestBlockIsKeptAndOnlyInsideTheScope) {
  const unsigned char* latest = nullptr;
  {
    const ReadBufferReuse reuse;
    { ReadBuffer older(kSliceBytes); }
    {
      ReadBuffer newer(kSliceBytes * 2);
      latest = newer.data();
    }
    ReadBuffer again(kSliceBytes * 2);
    EXPECT_EQ(again.data(), latest);
  }
  // Outside any scope every block is returned as it is freed; nothing is handed on.
  { ReadBuffer freed(kSliceBytes); }
  ReadBuffer fresh(kSliceBytes);
  EXPECT_TRUE(page_aligned(fresh.data()));
}

TEST(ReadBuffer, ScopesBelongToTheirThreadAndNest) {
  const ReadBufferReuse outer;
  const unsigned char* outer_block = nullptr;
  {
    ReadBuffer buffer(kSliceBytes);
    outer_block = buffer.data();
  }
  {
    const ReadBufferReuse inner;  // the innermost scope keeps; the outer one still holds its block
    ReadBuffer from_inner(kSliceBytes);
    EXPECT_NE(from_inner.data(), outer_block);
  }
  // Another thread has no scope: its buffers neither take nor leave this thread's block.
  std::thread([outer_block] {
    ReadBuffer elsewhere(kSliceBytes);
    EXPECT_TRUE(page_aligned(elsewhere.data()));
    EXPECT_NE(elsewhere.data(), outer_block) << "another thread took this thread's block";
  }).join();
  ReadBuffer back_outside(kSliceBytes);
  EXPECT_EQ(back_outside.data(), outer_block);
}

}  // namespace
}  // namespace mvox
