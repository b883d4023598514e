// Proves the engine allocates nothing while slices are pushed: this binary replaces the global
// operator new and counts calls inside a window opened around push_slice() and finish().
#include <gtest/gtest.h>

#include <random>

#include "counting_allocator.h"
#include "mvox/counting_sink.h"
#include "mesh_capture.h"
#include "mvox/engine.h"

namespace mvox {
namespace {

using test::AllocationWindow;

TEST(EngineAllocation, TheCounterSeesAnAllocation) {
  AllocationWindow window;
  // The instrument works: otherwise the next test would prove nothing. A direct call, because
  // compilers may elide a new-expression whose result is unused.
  ::operator delete(::operator new(sizeof(int)));
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
