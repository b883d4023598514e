// STL faces formatted by the slab worker that extracted them, ahead of its turn to write
// (write/mesh/face_formatter.h, pipeline/slab_recorder.h): the recorder keeps the records and the
// vertex counts instead of the engine's batches, the writer appends them, and the file is the one
// a single engine writes, byte for byte. A batch the formatter refuses is recorded as the engine
// made it, so that the writer refuses it in the words of a one-thread run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <deque>
#include <regex>
#include <string>
#include <vector>

#include "command_runner.h"
#include "file_io.h"
#include "memory_slab_slices.h"
#include "mvox/engine.h"
#include "pipeline/blocking_queue.h"
#include "pipeline/pipeline.h"
#include "pipeline/slab_engine_run.h"
#include "pipeline/slab_extraction.h"
#include "pipeline/slab_recorder.h"
#include "read/memory/memory_volume_source.h"
#include "slab_run_checks.h"
#include "write/mesh/face_formatter.h"
#include "write/mesh/mesh_format.h"
#include "write/mesh/ply_writer.h"
#include "write/mesh/stl_writer.h"

namespace mvox {
namespace {

VolumeInfo noise_info(std::uint32_t depth) {
  VolumeInfo info;
  info.width = 19;
  info.height = 13;
  info.depth = depth;
  info.type = SampleType::u8;
  return info;
}

std::vector<std::uint8_t> noise(const VolumeInfo& info) {
  return test::noise_samples(std::size_t{info.width} * info.height * info.depth, 5);
}

// Scaled, shifted, and mirrored by a rotation with a reflection, so that the formatter has to
// place every corner and reverse every face's winding, as the writer does.
MeshWriterOptions mirrored_options() {
  MeshWriterOptions options;
  options.transform.spacing = {0.5, 1.25, 2.0};
  options.transform.origin = {-3.0, 7.5, 100.0};
  options.transform.axes = {{{0.0, 1.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}}};
  options.comments = {"slab face formatting"};
  return options;
}

EngineOptions with_geometry() {
  EngineOptions engine;
  engine.polygon_geometry = true;  // STL needs the polygons' corners
  return engine;
}

// Every chunk the recorder fills, kept; the writer's turn never comes while it records.
class KeepingHandover final : public SlabRecorder::Handover {
 public:
  SlabChunk* take() override {
    chunks.emplace_back();
    chunks.back().reserve(with_geometry(), StlWriter::kMostBytesPerPolygon);
    return &chunks.back();
  }
  void full(SlabChunk*) override {}
  std::deque<SlabChunk> chunks;
};

// The volume cut into slabs of `slab_slices`, each extracted as a slab worker extracts it
// (extract_slab) through a recorder with `writer`'s formatter whose turn never comes while it
// records; then every slab's chunks replayed into `writer`, in order.
void record_then_replay(const std::vector<std::uint8_t>& samples, const VolumeInfo& info,
                        std::uint32_t slab_slices, StlWriter& writer, KeepingHandover& handover) {
  const auto formatter = writer.face_formatter();
  ASSERT_NE(formatter, nullptr);
  SlabRecorder recorder(handover, &writer.placement(), nullptr, true, formatter.get());
  const EngineOptions engine = with_geometry();
  std::vector<std::uint64_t> workspace(engine_workspace_bytes(info.width, info.height, engine) / 8 +
                                       1);
  test::MemorySlabSlices slices(samples, info);
  Cancellation cancellation;
  for (std::uint32_t first = 0; first < info.depth; first += slab_slices) {
    const SlabSpan span =
        SlabSpan::of(first, std::min(info.depth, first + slab_slices), info.depth, false);
    ASSERT_TRUE(extract_slab(span, info, 128, engine, workspace.data(), workspace.size() * 8,
                             recorder, nullptr, nullptr, slices, cancellation, "noise"));
  }
  SlabReplay replay(&writer);
  for (SlabChunk& chunk : handover.chunks) ASSERT_EQ(replay.replay(chunk), Status::ok);
}

// Four slabs: the three after the first start with polygons that refer to the vertices of the
// slice before them (Engine::begin_slab), which the formatter must take as its own.
TEST(SlabFaceFormatting, RecordedFacesAreFormattedRecordsThatReplayAsOneEnginesFile) {
  const VolumeInfo info = noise_info(23);
  const auto samples = noise(info);
  test::ScratchDirectory dir;
  {
    MemoryVolumeSource source(samples.data(), info, std::ptrdiff_t{info.width} * info.height,
                              info.width);
    StlWriter writer(dir.file("one.stl"), mirrored_options());
    run_pipeline(source, 128, with_geometry(), writer, "noise");
    writer.finish();
  }
  KeepingHandover handover;
  StlWriter writer(dir.file("recorded.stl"), mirrored_options());
  record_then_replay(samples, info, 6, writer, handover);
  writer.finish();
  EXPECT_TRUE(test::read_bytes(dir.file("recorded.stl")) == test::read_bytes(dir.file("one.stl")));

  // What was recorded: formatted records and vertex counts, not the engine's batches, in every
  // slab, from its first layer on.
  std::size_t formatted = 0, counted = 0, other = 0, record_bytes = 0, slabs = 0;
  for (const SlabChunk& chunk : handover.chunks) {
    if (chunk.first) {
      ++slabs;
      EXPECT_EQ(chunk.shared_vertices > 0, slabs > 1) << "slab " << slabs;
      ASSERT_FALSE(chunk.calls.empty());
      EXPECT_EQ(chunk.calls.back().kind, SlabChunk::Kind::formatted_faces) << "slab " << slabs;
    }
    for (const SlabChunk::Call& call : chunk.calls) {
      if (call.kind == SlabChunk::Kind::formatted_faces)
        ++formatted;
      else if (call.kind == SlabChunk::Kind::vertex_count)
        ++counted;
      else
        ++other;
    }
    record_bytes += chunk.formatted.size();
    EXPECT_TRUE(chunk.polygons.empty());
    EXPECT_TRUE(chunk.geometry.empty());
    EXPECT_EQ(chunk.placed_count, 0u);
  }
  EXPECT_EQ(slabs, 4u);
  EXPECT_GT(formatted, 4u);
  EXPECT_GT(counted, 4u);
  EXPECT_EQ(other, 0u);
  EXPECT_EQ(record_bytes, writer.faces_written() * 50);
}

// A triangle of vertices 0, 1, 2 at (x, 0, 0), (x + 1, 0, 0), (x, 1, 0): its batch entry and
// its geometry.
void triangle_at(float x, Polygon* polygon, PolygonGeometry* geometry) {
  polygon->vertex_count = 3;
  geometry->vertex_count = 3;
  const float corners[3][2] = {{x, 0}, {x + 1, 0}, {x, 1}};
  for (int k = 0; k < 3; ++k) {
    polygon->vertices[k] = static_cast<std::uint32_t>(k);
    geometry->vertices[k].x = corners[k][0];
    geometry->vertices[k].y = corners[k][1];
    geometry->vertices[k].z = 0;
  }
}

// The recorder fed by hand, as an engine would call it, and the same calls made straight into
// a writer: what the recorded chunks replay must be refused in the same words.
struct HandFed {
  std::vector<Vertex> vertices;
  std::vector<Polygon> polygons;
  std::vector<PolygonGeometry> geometry;

  void feed(PolygonSink& sink) const {
    ASSERT_EQ(sink.consume_vertices(vertices.data(), vertices.size()), Status::ok);
    // Refused or not, the calls go on as an engine's would; the refusal is read afterwards.
    static_cast<void>(sink.consume_polygons(polygons.data(), polygons.size()));
    static_cast<void>(sink.consume_polygon_geometry(geometry.data(), geometry.size()));
  }
};

std::string refusal_straight(const HandFed& calls, const MeshWriterOptions& options,
                             const std::string& path) {
  StlWriter writer(path, options);
  // The refusal is read from error(), as finish() would throw it.
  static_cast<void>(writer.consume_vertices(calls.vertices.data(), calls.vertices.size()));
  static_cast<void>(writer.consume_polygons(calls.polygons.data(), calls.polygons.size()));
  static_cast<void>(writer.consume_polygon_geometry(calls.geometry.data(), calls.geometry.size()));
  return writer.error() ? writer.error()->what() : "";
}

std::string refusal_recorded(const HandFed& calls, const MeshWriterOptions& options,
                             const std::string& path, KeepingHandover& handover) {
  StlWriter writer(path, options);
  const auto formatter = writer.face_formatter();
  SlabRecorder recorder(handover, &writer.placement(), nullptr, true, formatter.get());
  if (!recorder.start(0)) return "cancelled";
  recorder.own_vertices_only();
  calls.feed(recorder);
  recorder.end(SlabSummary());
  SlabReplay replay(&writer);
  // A refused chunk's error is the writer's, read below.
  for (SlabChunk& chunk : handover.chunks) static_cast<void>(replay.replay(chunk));
  return writer.error() ? writer.error()->what() : "";
}

// 600 triangles, more than the writer formats in one run (128), the last one with a corner that
// leaves float's range only in its geometry: the formatter refuses the batch after it has
// formatted a run of it. Nothing of it is kept, and the writer, given the batch as the engine
// made it, refuses it as it refuses it straight.
TEST(SlabFaceFormatting, ABatchTheFormatterRefusesIsRecordedAsTheEngineMadeIt) {
  MeshWriterOptions options;
  options.transform.spacing = {1e36, 1.0, 1.0};  // x beyond 340 leaves float's range
  HandFed calls;
  calls.vertices.resize(3);
  calls.vertices[1].x = 1;
  calls.vertices[2].y = 1;
  calls.polygons.resize(600);
  calls.geometry.resize(600);
  for (std::size_t i = 0; i < 600; ++i)
    triangle_at(i + 1 < 600 ? 0.0f : 400.0f, &calls.polygons[i], &calls.geometry[i]);
  test::ScratchDirectory dir;
  const std::string straight = refusal_straight(calls, options, dir.file("a.stl"));
  EXPECT_NE(straight.find("lies outside the float range"), std::string::npos) << straight;
  KeepingHandover handover;
  EXPECT_EQ(refusal_recorded(calls, options, dir.file("b.stl"), handover),
            std::regex_replace(straight, std::regex("a\\.stl"), "b.stl"));
  ASSERT_EQ(handover.chunks.size(), 1u);
  const SlabChunk& chunk = handover.chunks.front();
  ASSERT_EQ(chunk.calls.size(), 3u);
  EXPECT_EQ(chunk.calls[0].kind, SlabChunk::Kind::vertex_count);
  EXPECT_EQ(chunk.calls[1].kind, SlabChunk::Kind::polygons);
  EXPECT_EQ(chunk.calls[2].kind, SlabChunk::Kind::geometry);
  EXPECT_EQ(chunk.formatted.size(), 0u) << "the refused batch's first run was kept";
}

// A vertex batch with a vertex beyond float's range: recorded whole, not counted, so that the
// writer names that vertex as one thread does, before any polygon refers to it.
TEST(SlabFaceFormatting, AVertexBeyondFloatsRangeIsRecordedForTheWriterToName) {
  MeshWriterOptions options;
  options.transform.spacing = {1e36, 1.0, 1.0};
  HandFed calls;
  calls.vertices.resize(3);
  calls.vertices[1].x = 400;  // vertex 1: beyond float's range once placed
  calls.vertices[2].y = 1;
  calls.polygons.resize(1);
  calls.geometry.resize(1);
  triangle_at(0, &calls.polygons[0], &calls.geometry[0]);
  test::ScratchDirectory dir;
  const std::string straight = refusal_straight(calls, options, dir.file("a.stl"));
  EXPECT_NE(straight.find("vertex 1 lies outside the float range"), std::string::npos) << straight;
  KeepingHandover handover;
  EXPECT_EQ(refusal_recorded(calls, options, dir.file("b.stl"), handover),
            std::regex_replace(straight, std::regex("a\\.stl"), "b.stl"));
  ASSERT_EQ(handover.chunks.size(), 1u);
  ASSERT_FALSE(handover.chunks.front().calls.empty());
  EXPECT_EQ(handover.chunks.front().calls[0].kind, SlabChunk::Kind::vertices);
}

// The memory plan's figure for each format (formatted_bytes_per_polygon, made before any
// writer) is what the format's writer says when the run asks it.
TEST(SlabFaceFormatting, ThePlanAndTheWriterAgreeOnTheFormattedRecords) {
  test::ScratchDirectory dir;
  for (const MeshFormat format :
       {MeshFormat::ply, MeshFormat::ply_ascii, MeshFormat::stl, MeshFormat::obj}) {
    SCOPED_TRACE(mesh_format_name(format));
    const auto writer = open_mesh_writer(dir.file("m"), format, MeshWriterOptions());
    const auto formatter = writer->face_formatter();
    EXPECT_EQ(formatted_bytes_per_polygon(format),
              formatter ? formatter->most_bytes_per_polygon() : 0);
  }
  EXPECT_EQ(formatted_bytes_per_polygon(MeshFormat::stl), 5u * 50u);
}

TEST(SlabFaceFormatting, OnlyAFormatWithoutIndicesInItsFaceRecordsHasAFormatter) {
  test::ScratchDirectory dir;
  EXPECT_EQ(PlyWriter(dir.file("m.ply")).face_formatter(), nullptr);
  EXPECT_NE(StlWriter(dir.file("m.stl")).face_formatter(), nullptr);
  // And a writer that writes vertex records refuses vertices counted without them.
  PlyWriter ply(dir.file("n.ply"));
  EXPECT_EQ(ply.consume_vertex_count(3), Status::sink_refused);
  ASSERT_NE(ply.error(), nullptr);
  EXPECT_NE(std::string(ply.error()->what()).find("internal error"), std::string::npos);
}

// Slab workers with their formatters, 2, 3 and 8 of them on 4-slice slabs, write one engine's
// file; and a vertex that leaves float's range in the middle of the volume is refused in the
// same words as one engine refuses it (the CLI refuses such a placement before the run, a
// library caller may not).
TEST(SlabFaceFormatting, SlabWorkersWriteOneEnginesStlAndRefuseWhatItRefuses) {
  for (const bool far : {false, true}) {
    SCOPED_TRACE(far ? "a vertex beyond float's range" : "every vertex in range");
    const VolumeInfo info = noise_info(far ? 400 : 41);
    const auto samples = noise(info);
    MeshWriterOptions options = mirrored_options();
    if (far) options.transform.spacing = {1.0, 1.0, 1e36};  // z beyond 340 leaves float's range
    test::ScratchDirectory dir;
    std::string one_error, one_bytes;
    {
      MemoryVolumeSource source(samples.data(), info, std::ptrdiff_t{info.width} * info.height,
                                info.width);
      StlWriter writer(dir.file("m.stl"), options);  // the same name: the same messages
      run_pipeline(source, 128, with_geometry(), writer, "noise");
      try {
        writer.finish();
        one_bytes = test::read_bytes(dir.file("m.stl"));
      } catch (const Error& error) {
        one_error = error.what();
      }
    }
    EXPECT_EQ(one_error.empty(), !far) << one_error;
    for (const unsigned threads : {2u, 3u, 8u}) {
      SCOPED_TRACE(std::to_string(threads) + " workers");
      MemoryVolumeSource source(samples.data(), info, std::ptrdiff_t{info.width} * info.height,
                                info.width);
      StlWriter writer(dir.file("m.stl"), options);
      SlabOptions slabs;
      slabs.threads = threads;
      slabs.slab_slices = 4;
      run_slab_pipeline(source, 128, with_geometry(), &writer, slabs, "noise");
      std::string error_text;
      try {
        writer.finish();
      } catch (const Error& error) {
        error_text = error.what();
      }
      EXPECT_EQ(error_text, one_error);
      if (!far) EXPECT_TRUE(test::read_bytes(dir.file("m.stl")) == one_bytes);
    }
  }
}

}  // namespace
}  // namespace mvox
