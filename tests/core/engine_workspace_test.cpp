// The engine's workspace and lifecycle (mvox/engine.h): the workspace bound (every smaller size
// refused, the bound itself enough for a run, README's formula, the polygon-geometry batch),
// invalid arguments, calls out of order, and a sink that refuses.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "mesh_capture.h"
#include "mvox/counting_sink.h"
#include "mvox/engine.h"

namespace mvox {
namespace {

using test::BinaryVolume;
using test::extract;
using test::noise_volume;
using test::slice_of;
using test::Workspace;

TEST(EngineWorkspace, EverySizeBelowTheBoundIsRefusedAndTheBoundItselfWorks) {
  const std::uint32_t sizes[][2] = {{1, 1}, {3, 2}, {7, 5}, {62, 3}, {63, 2}, {64, 1}, {130, 4}};
  for (EngineKind kind : {EngineKind::fast, EngineKind::literal}) {
    EngineOptions options;
    options.kind = kind;
    options.vertices_per_batch = 7;
    options.polygons_per_batch = 5;
    for (const auto& size : sizes) {
      const std::size_t bound = engine_workspace_bytes(size[0], size[1], options);
      ASSERT_GT(bound, 0u);
      Workspace workspace(bound);
      CountingSink sink;
      Engine engine;
      for (std::size_t bytes = 0; bytes < bound; ++bytes)
        ASSERT_EQ(engine.init(workspace.data(), bytes, size[0], size[1], 1, options, &sink),
                  Status::workspace_too_small)
            << size[0] << "x" << size[1] << " with " << bytes << " of " << bound << " bytes";
      ASSERT_EQ(engine.init(workspace.data(), bound, size[0], size[1], 1, options, &sink),
                Status::ok);
      // The bound is enough for a real run, not just for init(): a full slice then finish.
      std::vector<std::uint8_t> full(std::size_t{size[0]} * size[1], 1);
      SliceView slice{full.data(), size[0], size[1], size[0], SampleType::u8};
      EXPECT_EQ(engine.push_slice(slice), Status::ok);
      EXPECT_EQ(engine.finish(), Status::ok);
      EXPECT_EQ(sink.polygons, engine.counters().polygons);
      EXPECT_GT(sink.polygons, 0u);
    }
  }
}

TEST(EngineWorkspace, BoundGrowsWithTheSlice) {
  const EngineOptions options;
  const std::size_t small = engine_workspace_bytes(256, 256, options);
  EXPECT_LT(small, engine_workspace_bytes(512, 256, options));
  EXPECT_LT(small, engine_workspace_bytes(256, 512, options));
  // About 0.25 bytes per pixel plus the batch buffers: a 2048x2048 micro-CT slice needs < 2 MiB.
  EXPECT_LT(engine_workspace_bytes(2048, 2048, options), std::size_t{2} << 20);
  EngineOptions literal = options;
  literal.kind = EngineKind::literal;
  EXPECT_GT(engine_workspace_bytes(256, 256, literal), small);
}

// README.md states the workspace as a formula; keep the two in step. The remainder is the
// engine's state struct and the 16-byte alignment of each buffer.
TEST(EngineWorkspace, MatchesTheFormulaInTheReadme) {
  EngineOptions options;
  EngineOptions literal;
  literal.kind = EngineKind::literal;
  const std::uint32_t sizes[][2] = {{1, 1}, {7, 5}, {256, 256}, {513, 300}, {2048, 2048}};
  for (const auto& size : sizes) {
    const std::size_t w = size[0], h = size[1];
    const std::size_t words = (w + 2 + 63) / 64;
    const std::size_t formula = words * (16 * h + 8) + 2 * h + 16 * 4096 + 32 * 4096;
    const std::size_t actual = engine_workspace_bytes(size[0], size[1], options);
    EXPECT_GE(actual, formula) << w << "x" << h;
    EXPECT_LE(actual, formula + 512) << w << "x" << h;
    // The literal engine adds its edge planes (60 bytes per 64 voxels of a row, plus the extra
    // row of y-edges) and 2 * 49 bytes per cube of a layer for its merge state.
    const std::size_t literal_extra = engine_workspace_bytes(size[0], size[1], literal) - actual;
    const std::size_t literal_formula = words * (60 * h + 24) + 98 * (w + 1) * (h + 1);
    EXPECT_GE(literal_extra, literal_formula) << w << "x" << h;
    EXPECT_LE(literal_extra, literal_formula + 64) << w << "x" << h;
  }
}

TEST(EngineWorkspace, InvalidArgumentsAreRefused) {
  EngineOptions options;
  EXPECT_EQ(engine_workspace_bytes(0, 5, options), 0u);
  EXPECT_EQ(engine_workspace_bytes(5, 0, options), 0u);
  EXPECT_EQ(engine_workspace_bytes(100000, 100000, options), 0u);  // plane counters would overflow
  // Dimensions whose +1 or +2 wraps in 32 bits must not slip through as small workspaces.
  const std::uint32_t most = 0xFFFFFFFFu;
  for (const auto& size : {std::pair{most, 1u}, std::pair{most - 1, 3u}, std::pair{1u, most},
                           std::pair{most, most}, std::pair{3u, most - 1}})
    EXPECT_EQ(engine_workspace_bytes(size.first, size.second, options), 0u)
        << size.first << "x" << size.second;
  Workspace workspace(engine_workspace_bytes(4, 4, options) + 64);
  CountingSink sink;
  Engine engine;
  EXPECT_EQ(engine.init(nullptr, 1 << 20, 4, 4, 1, options, &sink), Status::invalid_argument);
  EXPECT_EQ(engine.init(workspace.data(), workspace.bytes(), 4, 4, 1, options, nullptr),
            Status::invalid_argument);
  EXPECT_EQ(engine.init(workspace.data(), workspace.bytes(), 4, 4, std::nan(""), options, &sink),
            Status::invalid_argument);
  char* misaligned = static_cast<char*>(workspace.data()) + kWorkspaceAlignment / 2;
  EXPECT_EQ(
      engine.init(misaligned, workspace.bytes() - kWorkspaceAlignment, 4, 4, 1, options, &sink),
      Status::workspace_misaligned);
  options.polygons_per_batch = 0;
  EXPECT_EQ(engine_workspace_bytes(4, 4, options), 0u);
  EXPECT_EQ(engine.init(workspace.data(), workspace.bytes(), 4, 4, 1, options, &sink),
            Status::invalid_argument);
}

TEST(EngineWorkspace, PolygonGeometryAddsOneBatchOfPolygonsByValue) {
  EXPECT_EQ(sizeof(PolygonGeometry), 116u);  // as engine.h states
  const std::uint32_t sizes[][2] = {{1, 1}, {7, 5}, {64, 3}, {513, 300}};
  for (const auto& size : sizes)
    for (EngineKind kind : {EngineKind::fast, EngineKind::literal})
      for (std::uint32_t batch : {1u, 2u, 3u, 5u, 7u, 4096u}) {
        EngineOptions off;
        off.kind = kind;
        off.polygons_per_batch = batch;
        EngineOptions on = off;
        on.polygon_geometry = true;
        // Every buffer starts on kWorkspaceAlignment (8): odd batches of 116 bytes round up by 4.
        const std::size_t expected_extra = (batch * sizeof(PolygonGeometry) + 7) / 8 * 8;
        EXPECT_EQ(engine_workspace_bytes(size[0], size[1], on) -
                      engine_workspace_bytes(size[0], size[1], off),
                  expected_extra)
            << size[0] << "x" << size[1] << " batch " << batch;
      }
  // And init() asks for all of it.
  EngineOptions on;
  on.polygon_geometry = true;
  on.vertices_per_batch = 4;
  on.polygons_per_batch = 3;
  const std::size_t bound = engine_workspace_bytes(7, 5, on);
  Workspace workspace(bound);
  CountingSink sink;
  Engine engine;
  for (std::size_t bytes = 0; bytes < bound; ++bytes)
    ASSERT_EQ(engine.init(workspace.data(), bytes, 7, 5, 1, on, &sink), Status::workspace_too_small)
        << bytes << " of " << bound;
  EXPECT_EQ(engine.init(workspace.data(), bound, 7, 5, 1, on, &sink), Status::ok);
}

TEST(EngineLifecycle, CallsOutOfOrderAndWrongSlicesAreRefusedWithAStatus) {
  const BinaryVolume volume = test::volume_from_bits(3, 2, 2, 0b101101011011);
  const EngineOptions options;
  Workspace workspace(engine_workspace_bytes(3, 2, options));
  CountingSink sink;
  Engine engine;
  EXPECT_EQ(engine.push_slice(slice_of(volume, 0)), Status::not_initialised);
  EXPECT_EQ(engine.finish(), Status::not_initialised);
  ASSERT_EQ(engine.init(workspace.data(), workspace.bytes(), 3, 2, 1, options, &sink), Status::ok);

  SliceView wrong = slice_of(volume, 0);
  wrong.width = 2;
  wrong.row_stride_bytes = 3;
  EXPECT_EQ(engine.push_slice(wrong), Status::slice_size_mismatch);
  SliceView short_stride = slice_of(volume, 0);
  short_stride.row_stride_bytes = 2;
  EXPECT_EQ(engine.push_slice(short_stride), Status::invalid_argument);
  SliceView null_samples = slice_of(volume, 0);
  null_samples.samples = nullptr;
  EXPECT_EQ(engine.push_slice(null_samples), Status::invalid_argument);
  SliceView unknown_type = slice_of(volume, 0);
  unknown_type.type = static_cast<SampleType>(9);
  EXPECT_EQ(engine.push_slice(unknown_type), Status::invalid_argument);
  EXPECT_EQ(engine.counters().slices, 0u);  // refused slices leave the engine as it was

  EXPECT_EQ(engine.push_slice(slice_of(volume, 0)), Status::ok);
  EXPECT_EQ(engine.push_slice(slice_of(volume, 1)), Status::ok);
  EXPECT_EQ(engine.finish(), Status::ok);
  EXPECT_EQ(engine.push_slice(slice_of(volume, 0)), Status::already_finished);
  EXPECT_EQ(engine.finish(), Status::already_finished);
  // The refused calls changed nothing: the output equals a clean run's.
  EXPECT_EQ(sink.polygons, extract(volume, 1).polygons.size());

  // init() starts a new volume on the same workspace.
  CountingSink second;
  ASSERT_EQ(engine.init(workspace.data(), workspace.bytes(), 3, 2, 1, options, &second),
            Status::ok);
  EXPECT_EQ(engine.push_slice(slice_of(volume, 0)), Status::ok);
  EXPECT_EQ(engine.push_slice(slice_of(volume, 1)), Status::ok);
  EXPECT_EQ(engine.finish(), Status::ok);
  EXPECT_EQ(second.polygons, sink.polygons);
  EXPECT_EQ(second.vertices, sink.vertices);
}

TEST(EngineLifecycle, ASinkThatRefusesStopsTheEngineAndReceivesNothingMore) {
  const auto volume = noise_volume(20, 17, 9, 7);
  EngineOptions options;
  options.vertices_per_batch = 16;
  options.polygons_per_batch = 16;
  for (std::size_t refuse_at : {1, 2, 5, 40}) {
    Workspace workspace(engine_workspace_bytes(20, 17, options));
    CountingSink sink;
    sink.refuse_batch = refuse_at;
    Engine engine;
    ASSERT_EQ(engine.init(workspace.data(), workspace.bytes(), 20, 17, 128, options, &sink),
              Status::ok);
    Status last = Status::ok;
    for (std::uint32_t z = 0; z < 9 && last == Status::ok; ++z) {
      SliceView slice{volume.samples.data() + z * 20 * 17, 20, 17, 20, SampleType::u8};
      last = engine.push_slice(slice);
    }
    if (last == Status::ok) last = engine.finish();
    EXPECT_EQ(last, Status::sink_refused) << "refusing batch " << refuse_at;
    EXPECT_EQ(sink.batches, refuse_at) << "batches arrived after the refusal";
    SliceView slice{volume.samples.data(), 20, 17, 20, SampleType::u8};
    EXPECT_EQ(engine.push_slice(slice), Status::sink_refused);
    EXPECT_EQ(engine.finish(), Status::sink_refused);
    EXPECT_EQ(sink.batches, refuse_at);
  }
}

}  // namespace
}  // namespace mvox
