// The core's fixed-size sinks and its streaming loop (mvox/fan_out_sink.h, counting_sink.h,
// stream_volume.h): batches reach every sink in order until one refuses, an observer sees each
// call, and a host reader's exception passes through the loop, which is built without
// exceptions.
#include "mvox/fan_out_sink.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "mvox/counting_sink.h"
#include "mvox/stream_volume.h"
#include "mvox/workspace_buffer.h"
#include "phantom_factory.h"
#include "simulated_scanner.h"

namespace mvox {
namespace {

TEST(FanOutSink, EveryBatchReachesEverySinkInOrderUntilOneRefuses) {
  CountingSink first, second, third;
  second.refuse_batch = 3;
  FanOutSink fan_out;
  ASSERT_TRUE(fan_out.add(&first));
  ASSERT_TRUE(fan_out.add(nullptr));  // ignored
  ASSERT_TRUE(fan_out.add(&second));
  ASSERT_TRUE(fan_out.add(&third));
  EXPECT_EQ(fan_out.size(), 3);
  std::vector<std::pair<SinkCall, int>> seen;
  fan_out.set_observer(
      [](void* context, SinkCall call, int sink) {
        static_cast<std::vector<std::pair<SinkCall, int>>*>(context)->emplace_back(call, sink);
      },
      &seen);
  const Vertex vertices[2] = {};
  const Polygon polygons[1] = {};
  EXPECT_EQ(fan_out.consume_vertices(vertices, 2), Status::ok);
  EXPECT_EQ(fan_out.consume_polygons(polygons, 1), Status::ok);
  // The third batch is refused by the second sink: the third sink never sees it.
  EXPECT_EQ(fan_out.consume_vertices(vertices, 2), Status::sink_refused);
  EXPECT_EQ(first.vertices, 4u);
  EXPECT_EQ(second.vertices, 4u);
  EXPECT_EQ(third.vertices, 2u);
  EXPECT_EQ(third.polygons, 1u);
  const std::vector<std::pair<SinkCall, int>> expected = {
      {SinkCall::vertices, -1}, {SinkCall::vertices, 0},  {SinkCall::vertices, 1},
      {SinkCall::vertices, 2},  {SinkCall::polygons, -1}, {SinkCall::polygons, 0},
      {SinkCall::polygons, 1},  {SinkCall::polygons, 2},  {SinkCall::vertices, -1},
      {SinkCall::vertices, 0},  {SinkCall::vertices, 1}};
  EXPECT_EQ(seen, expected);
}

TEST(FanOutSink, HoldsAFixedNumberOfSinks) {
  CountingSink sink;
  FanOutSink fan_out;
  for (int i = 0; i < FanOutSink::kMaxSinks; ++i) EXPECT_TRUE(fan_out.add(&sink));
  EXPECT_FALSE(fan_out.add(&sink));
}

// A source that throws, as a host's file reader does on a corrupt slice.
class ThrowingSource final : public SliceSource {
 public:
  explicit ThrowingSource(SliceSource& inner) : inner_(inner) {}
  const VolumeInfo& info() const override { return inner_.info(); }
  bool next_slice(SliceView* slice) override {
    if (++calls_ == 4) throw std::runtime_error("slice 3 is corrupt");
    return inner_.next_slice(slice);
  }

 private:
  SliceSource& inner_;
  int calls_ = 0;
};

TEST(StreamVolume, AReadersExceptionPassesThroughTheCoresLoop) {
  const auto phantom = sim::make_phantom("sphere", {12, 10, 8}, 1);
  sim::SimulatedScanner scanner(*phantom);
  ThrowingSource source(scanner);
  CountingSink sink;
  WorkspaceBuffer workspace(engine_workspace_bytes(12, 10, {}));
  Engine engine;
  ASSERT_EQ(engine.init(workspace.data(), workspace.bytes(), 12, 10, 128, {}, &sink), Status::ok);
  std::uint32_t slices = 0;
  auto count = [&](std::uint32_t done) { slices = done; };
  try {
    // The source throws at slice 3, so no status ever comes back.
    (void)stream_volume(source, engine, SliceProgress::of(count));
    ADD_FAILURE() << "the exception was lost";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "slice 3 is corrupt");
  }
  EXPECT_EQ(slices, 3u);
}

}  // namespace
}  // namespace mvox
