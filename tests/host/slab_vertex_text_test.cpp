// The text formats' vertex lines formatted by the slab worker that placed the vertices, ahead
// of its turn to write (write/mesh/vertex_text_formatter.h, pipeline/slab_recorder.h): the
// recorder keeps the lines instead of the placed vertices, the writer appends them, and the
// file is the one a single engine writes, byte for byte. A batch with a vertex beyond float's
// range is recorded as the engine made it, so that the writer names that vertex as one thread
// does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <deque>
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include "command_runner.h"
#include "file_io.h"
#include "memory_slab_slices.h"
#include "mvox/engine.h"
#include "pipeline/pipeline.h"
#include "pipeline/slab_engine_run.h"
#include "pipeline/slab_recorder.h"
#include "read/memory/memory_volume_source.h"
#include "slab_run_checks.h"
#include "write/mesh/mesh_format.h"
#include "write/mesh/vertex_text_formatter.h"

namespace mvox {
namespace {

// Scaled, shifted and rotated with a reflection, so that every coordinate is a float of its
// own making, as the writer places it.
MeshWriterOptions placed_options() {
  MeshWriterOptions options;
  options.transform.spacing = {0.7, 1.25, 0.3};
  options.transform.origin = {-3.1, 7.5, 100.0};
  options.transform.axes = {{{0.0, 1.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}}};
  options.comments = {"slab vertex text"};
  return options;
}

// Every chunk the recorder fills, kept, reserved as the run reserves them for this format; the
// writer's turn never comes while it records.
class KeepingHandover final : public SlabRecorder::Handover {
 public:
  explicit KeepingHandover(std::size_t bytes_per_vertex) : bytes_per_vertex_(bytes_per_vertex) {}
  SlabChunk* take() override {
    chunks.emplace_back();
    chunks.back().reserve(EngineOptions(), 0, bytes_per_vertex_);
    return &chunks.back();
  }
  void full(SlabChunk*) override {}
  std::deque<SlabChunk> chunks;

 private:
  std::size_t bytes_per_vertex_;
};

struct TextFormat {
  MeshFormat format;
  const char* file;
};
const TextFormat kTextFormats[] = {{MeshFormat::obj, "m.obj"}, {MeshFormat::ply_ascii, "m.ply"}};

// Five slabs of a noise volume: every slab after the first starts with polygons that refer to
// the vertices of the slice before it, and each slab's vertex lines are recorded by a worker
// whose turn never comes, then replayed in order.
TEST(SlabVertexText, RecordedVertexLinesReplayAsOneEnginesFile) {
  const VolumeInfo info = test::u8_volume(21, 17, 29);
  const auto samples = test::noise_samples(info, 9);
  for (const TextFormat& text : kTextFormats) {
    SCOPED_TRACE(mesh_format_name(text.format));
    test::ScratchDirectory one_dir, recorded_dir;
    {
      MemoryVolumeSource source(samples.data(), info, std::ptrdiff_t{info.width} * info.height,
                                info.width);
      const auto writer = open_mesh_writer(one_dir.file(text.file), text.format, placed_options());
      run_pipeline(source, 128, EngineOptions(), *writer, "noise");
      writer->finish();
    }
    const auto writer =
        open_mesh_writer(recorded_dir.file(text.file), text.format, placed_options());
    const auto lines = writer->vertex_text_formatter();
    ASSERT_NE(lines, nullptr);
    KeepingHandover handover(lines->most_bytes_per_vertex());
    SlabRecorder recorder(handover, &writer->placement(), nullptr, false, nullptr, lines.get());
    const EngineOptions engine;
    std::vector<std::uint64_t> workspace(
        engine_workspace_bytes(info.width, info.height, engine) / 8 + 1);
    test::MemorySlabSlices slices(samples, info);
    Cancellation cancellation;
    for (std::uint32_t first = 0; first < info.depth; first += 6) {
      const SlabSpan span = SlabSpan::of(first, std::min(info.depth, first + 6), info.depth, false);
      ASSERT_TRUE(extract_slab(span, info, 128, engine, workspace.data(), workspace.size() * 8,
                               recorder, nullptr, nullptr, slices, cancellation, "noise"));
    }
    SlabReplay replay(writer.get());
    for (SlabChunk& chunk : handover.chunks) ASSERT_EQ(replay.replay(chunk), Status::ok);
    writer->finish();
    EXPECT_TRUE(test::read_bytes(recorded_dir.file(text.file)) ==
                test::read_bytes(one_dir.file(text.file)));

    // What was recorded: vertex lines and the engine's polygons, no placed vertices.
    std::size_t lines_calls = 0, polygon_calls = 0, other = 0, slabs = 0;
    for (const SlabChunk& chunk : handover.chunks) {
      slabs += chunk.first ? 1 : 0;
      for (const SlabChunk::Call& call : chunk.calls) {
        if (call.kind == SlabChunk::Kind::formatted_vertices)
          ++lines_calls;
        else if (call.kind == SlabChunk::Kind::polygons)
          ++polygon_calls;
        else
          ++other;
      }
      EXPECT_EQ(chunk.placed_count, 0u);
      EXPECT_TRUE(chunk.vertices.empty());
    }
    EXPECT_EQ(slabs, 5u);
    EXPECT_GE(lines_calls, 5u);
    EXPECT_GE(polygon_calls, 5u);
    EXPECT_EQ(other, 0u);
  }
}

// Vertex 1 of a batch leaves float's range once placed: the batch is recorded as the engine
// made it, and the writer refuses it in the words of a one-thread run, naming vertex 1.
TEST(SlabVertexText, AVertexBeyondFloatsRangeIsRecordedForTheWriterToName) {
  MeshWriterOptions options;
  options.transform.spacing = {1e36, 1.0, 1.0};  // x beyond 340 leaves float's range
  std::vector<Vertex> vertices(3);
  vertices[1].x = 400;
  vertices[2].y = 1;
  for (const TextFormat& text : kTextFormats) {
    SCOPED_TRACE(mesh_format_name(text.format));
    test::ScratchDirectory dir;
    const auto straight =
        open_mesh_writer(dir.file(std::string("a") + text.file), text.format, options);
    EXPECT_EQ(straight->consume_vertices(vertices.data(), vertices.size()), Status::sink_refused);
    ASSERT_NE(straight->error(), nullptr);
    const std::string words = straight->error()->what();
    EXPECT_NE(words.find("vertex 1 lies outside the float range"), std::string::npos) << words;

    const auto writer =
        open_mesh_writer(dir.file(std::string("b") + text.file), text.format, options);
    const auto lines = writer->vertex_text_formatter();
    KeepingHandover handover(lines->most_bytes_per_vertex());
    SlabRecorder recorder(handover, &writer->placement(), nullptr, false, nullptr, lines.get());
    ASSERT_TRUE(recorder.start(0));
    EXPECT_EQ(recorder.consume_vertices(vertices.data(), vertices.size()), Status::ok);
    recorder.end(SlabSummary());
    ASSERT_EQ(handover.chunks.size(), 1u);
    ASSERT_EQ(handover.chunks.front().calls.size(), 1u);
    EXPECT_EQ(handover.chunks.front().calls[0].kind, SlabChunk::Kind::vertices);
    EXPECT_EQ(handover.chunks.front().formatted.size(), 0u);
    SlabReplay replay(writer.get());
    EXPECT_EQ(replay.replay(handover.chunks.front()), Status::sink_refused);
    ASSERT_NE(writer->error(), nullptr);
    EXPECT_EQ(writer->error()->what(),
              std::regex_replace(words, std::regex("a(m\\.(obj|ply))"), "b$1"));
  }
}

// The memory plan's figure for each format, made before any writer, is what the format's
// writer says when the run asks it; only the text formats have vertex lines to format.
TEST(SlabVertexText, ThePlanAndTheWriterAgreeOnTheVertexLines) {
  test::ScratchDirectory dir;
  for (const bool normals : {false, true}) {
    MeshWriterOptions options;
    options.normals_given = normals;
    for (const MeshFormat format :
         {MeshFormat::ply, MeshFormat::ply_ascii, MeshFormat::stl, MeshFormat::obj}) {
      SCOPED_TRACE(std::string(mesh_format_name(format)) + (normals ? " with normals" : ""));
      if (format == MeshFormat::stl && normals) continue;  // STL has face normals only
      const auto writer = open_mesh_writer(dir.file("m"), format, options);
      const auto lines = writer->vertex_text_formatter();
      const bool text = format == MeshFormat::obj || format == MeshFormat::ply_ascii;
      EXPECT_EQ(lines != nullptr, text);
      EXPECT_EQ(formatted_bytes_per_vertex(format, normals),
                lines ? lines->most_bytes_per_vertex() : 0);
    }
  }
}

}  // namespace
}  // namespace mvox
