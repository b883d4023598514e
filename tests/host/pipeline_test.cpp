// run_pipeline's phase times: each sink's time is its own (the timer shares one clock reading
// between the end of one interval and the start of the next, and must not count anything
// twice), and a source that times itself gives the read time.
#include "pipeline/pipeline.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "phantom_factory.h"
#include "simulated_scanner.h"

namespace mvox {
namespace {

// Sleeps in the calls it is told to, so that its share of the time is known from below.
class SleepingSink final : public PolygonSink {
 public:
  SleepingSink(int polygons_ms, int geometry_ms)
      : polygons_ms_(polygons_ms), geometry_ms_(geometry_ms) {}
  Status consume_vertices(const Vertex*, std::size_t) override { return Status::ok; }
  Status consume_polygons(const Polygon*, std::size_t) override {
    ++polygon_calls;
    std::this_thread::sleep_for(std::chrono::milliseconds(polygons_ms_));
    return Status::ok;
  }
  Status consume_polygon_geometry(const PolygonGeometry*, std::size_t) override {
    ++geometry_calls;
    std::this_thread::sleep_for(std::chrono::milliseconds(geometry_ms_));
    return Status::ok;
  }
  int polygon_calls = 0;
  int geometry_calls = 0;

 private:
  int polygons_ms_;
  int geometry_ms_;
};

PipelineResult run_on_blobs(const PipelineSinks& sinks, const SourceSeconds& source_seconds = {}) {
  const auto phantom = sim::make_phantom("blobs", {24, 20, 8}, 8);
  sim::SimulatedScanner scanner(*phantom);
  const double threshold = sim::sample_threshold(0.5, sim::default_scan_options(SampleType::u8));
  return run_pipeline(scanner, threshold, EngineOptions(), sinks, "blobs", {}, source_seconds);
}

TEST(Pipeline, EachSinksTimeIsItsOwnAndNothingIsCountedTwice) {
  // The mesh sink sleeps in consume_polygons, the render sink in the consume_polygon_geometry
  // that follows it: were the geometry call timed from the start of consume_polygons, the mesh
  // sink's sleep would count twice and the phases would add up to more than the run.
  SleepingSink mesh(4, 0);
  SleepingSink render(0, 3);
  PipelineSinks sinks;
  sinks.mesh = &mesh;
  sinks.render = &render;
  const PipelineResult result = run_on_blobs(sinks);
  ASSERT_EQ(result.status, Status::ok);
  ASSERT_GT(mesh.polygon_calls, 2);
  EXPECT_EQ(render.geometry_calls, mesh.polygon_calls);
  const PhaseTimes& t = result.times;
  EXPECT_GE(t.write_s, mesh.polygon_calls * 0.004);
  EXPECT_GE(t.render_s, render.geometry_calls * 0.003);
  EXPECT_LE(t.read_s + t.write_s + t.render_s, t.total_s);
  EXPECT_GE(t.extract_s, 0.0);
}

TEST(Pipeline, ASourceThatTimesItselfGivesTheReadTime) {
  SleepingSink mesh(0, 0);
  PipelineSinks sinks;
  sinks.mesh = &mesh;
  int asked = 0;
  const PipelineResult result = run_on_blobs(sinks, [&] {
    ++asked;
    return 0.125;
  });
  EXPECT_EQ(asked, 1);  // once, at the end: not per slice
  EXPECT_EQ(result.times.read_s, 0.125);
}

}  // namespace
}  // namespace mvox
