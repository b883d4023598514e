// Proves the engine allocates nothing while slices are pushed: this binary replaces the global
// operator new and counts calls inside a window opened around push_slice() and finish().
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>

#include "counting_sink.h"
#include "mesh_capture.h"
#include "mvox/engine.h"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<std::size_t> g_allocations{0};

void* counted_allocation(std::size_t bytes) {
  if (g_counting) ++g_allocations;
  if (void* p = std::malloc(bytes ? bytes : 1)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t bytes) { return counted_allocation(bytes); }
void* operator new[](std::size_t bytes) { return counted_allocation(bytes); }
void* operator new(std::size_t bytes, const std::nothrow_t&) noexcept {
  if (g_counting) ++g_allocations;
  return std::malloc(bytes ? bytes : 1);
}
void* operator new[](std::size_t bytes, const std::nothrow_t&) noexcept {
  if (g_counting) ++g_allocations;
  return std::malloc(bytes ? bytes : 1);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace mvox {
namespace {

class AllocationWindow {
 public:
  AllocationWindow() {
    g_allocations = 0;
    g_counting = true;
  }
  ~AllocationWindow() { g_counting = false; }
  std::size_t count() const { return g_allocations; }
};

TEST(EngineAllocation, TheCounterSeesAnAllocation) {
  AllocationWindow window;
  delete new int(1);  // the instrument works: otherwise the next test would prove nothing
  EXPECT_EQ(window.count(), 1u);
}

TEST(EngineAllocation, NothingIsAllocatedWhileSlicesArePushedOrTheVolumeFinished) {
  const std::uint32_t w = 97, h = 61, d = 40;
  std::vector<std::uint8_t> samples(std::size_t{w} * h * d);
  std::mt19937 generator(42);
  for (auto& s : samples) s = static_cast<std::uint8_t>(generator() >> 24);
  for (EngineKind kind : {EngineKind::fast, EngineKind::literal}) {
    for (SurfaceRule rule : {SurfaceRule::merge_rules, SurfaceRule::paper_table1}) {
      EngineOptions options;
      options.kind = kind;
      options.rule = rule;
      options.vertices_per_batch = 100;  // small batches: many flushes inside the window
      options.polygons_per_batch = 100;
      test::Workspace workspace(engine_workspace_bytes(w, h, options));
      CountingSink sink;  // allocates nothing itself: any count is the engine's
      Engine engine;
      ASSERT_EQ(engine.init(workspace.data(), workspace.bytes(), w, h, 128, options, &sink),
                Status::ok);
      std::size_t allocations = 0;
      {
        AllocationWindow window;
        for (std::uint32_t z = 0; z < d; ++z)
          ASSERT_EQ(engine.push_slice({&samples[std::size_t{z} * w * h], w, h, w, SampleType::u8}),
                    Status::ok);
        ASSERT_EQ(engine.finish(), Status::ok);
        allocations = window.count();
      }
      EXPECT_EQ(allocations, 0u);
      EXPECT_GT(sink.polygons, 1000u);
    }
  }
}

}  // namespace
}  // namespace mvox
