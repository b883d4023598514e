// Vertex indices past 2^31 and 2^32 in the mesh writers, without writing billions of vertices:
// the engine numbers from just below the limit (detail::number_vertices_from) into a writer
// of a part that starts there (MeshWriterOptions::part). OBJ writes whole indices of any size;
// PLY says "uint" past 2^31 and refuses past 2^32 with one line naming OBJ; the in-memory
// arrays turn to 64-bit indices past 2^31; STL cannot count past 2^32 - 1 triangles. Never a
// wrapped index.
#include <gtest/gtest.h>

#include <cstdint>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "command_runner.h"
#include "file_io.h"
#include "mesh_capture.h"
#include "mvox/engine.h"
#include "mvox/workspace_buffer.h"
#include "pipeline/aligned_arrays_sink.h"
#include "write/mesh/mesh_arrays.h"
#include "write/mesh/mesh_format.h"

namespace mvox {
namespace {

constexpr std::uint32_t kW = 37, kH = 29, kD = 23;
constexpr std::uint64_t k2to31 = std::uint64_t{1} << 31, k2to32 = std::uint64_t{1} << 32;

// Runs the engine over the noise into `writer`, numbering from `first`. The engine's status.
Status extract(MeshWriter& writer, std::uint64_t first) {
  static const test::BinaryVolume noise = test::noise_volume(kW, kH, kD, 11);
  EngineOptions options;
  options.polygon_geometry = writer.needs_polygon_geometry();
  WorkspaceBuffer workspace(engine_workspace_bytes(kW, kH, options));
  Engine engine;
  Status status = engine.init(workspace.data(), workspace.bytes(), kW, kH, 128, options, &writer);
  if (status != Status::ok) return status;
  detail::number_vertices_from(engine, first);
  for (std::uint32_t z = 0; z < kD && status == Status::ok; ++z)
    status = engine.push_slice(test::slice_of(noise, z));
  return status == Status::ok ? engine.finish() : status;
}

MeshWriterOptions part_from(std::uint64_t first) {
  MeshWriterOptions options;
  options.part = MeshWriterOptions::Part{first};
  return options;
}

// The indices of an OBJ's "f" lines, in order.
std::vector<std::uint64_t> face_indices(const std::string& obj) {
  std::vector<std::uint64_t> indices;
  std::istringstream lines(obj);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("f ", 0) != 0) continue;
    std::istringstream fields(line.substr(2));
    std::uint64_t index;
    while (fields >> index) indices.push_back(index);
  }
  return indices;
}

TEST(VertexIndexWriters, ObjWritesWholeIndicesPast2To32) {
  test::ScratchDirectory dir;
  auto from_zero = open_mesh_writer(dir / "zero.obj", MeshFormat::obj, part_from(0));
  ASSERT_EQ(extract(*from_zero, 0), Status::ok);
  from_zero->finish();
  const std::uint64_t first = k2to32 - 10000;
  auto high = open_mesh_writer(dir / "high.obj", MeshFormat::obj, part_from(first));
  ASSERT_EQ(extract(*high, first), Status::ok);
  high->finish();
  const std::vector<std::uint64_t> reference =
      face_indices(test::read_bytes(dir.path() / "zero.obj"));
  const std::vector<std::uint64_t> moved = face_indices(test::read_bytes(dir.path() / "high.obj"));
  ASSERT_EQ(moved.size(), reference.size());
  ASSERT_GT(reference.size(), 50000u);
  std::size_t past = 0;
  for (std::size_t i = 0; i < moved.size(); ++i) {
    ASSERT_EQ(moved[i], reference[i] + first) << "index " << i;
    past += moved[i] > k2to32;
  }
  EXPECT_GT(past, 10000u) << "no index passed 2^32";
}

TEST(VertexIndexWriters, PlySaysUintPast2To31AndRefusesPast2To32) {
  test::ScratchDirectory dir;
  // Past 2^31: written, with unsigned index lists in the head.
  const std::uint64_t first = k2to31 - 10000;
  auto part = open_mesh_writer(dir / "part.ply", MeshFormat::ply, part_from(first));
  ASSERT_EQ(extract(*part, first), Status::ok);
  part->finish();
  const std::string past = mesh_file_head(MeshFormat::ply, {}, part->vertices_written(), 1);
  EXPECT_NE(past.find("property list uchar uint vertex_indices"), std::string::npos) << past;
  const std::string below = mesh_file_head(MeshFormat::ply, {}, k2to31, 1);
  EXPECT_NE(below.find("property list uchar int vertex_indices"), std::string::npos) << below;
  EXPECT_EQ(past.size(), below.size()) << "the head's reserved size moved";
  // Past 2^32: refused, the vertex batch that would cross it, with one line naming OBJ.
  const std::uint64_t high = k2to32 - 10000;
  auto refused = open_mesh_writer(dir / "refused.ply", MeshFormat::ply, part_from(high));
  EXPECT_EQ(extract(*refused, high), Status::sink_refused);
  ASSERT_NE(refused->error(), nullptr);
  const std::string message = refused->error()->what();
  EXPECT_NE(message.find("more than 4294967296 vertices"), std::string::npos) << message;
  EXPECT_NE(message.find("write OBJ"), std::string::npos) << message;
  EXPECT_THROW(refused->finish(), Error);
  refused.reset();  // a writer that never finished deletes its temporary
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"part.ply"}) << "a refused file was left";
}

// The indices an array sink collected, whichever width they are in.
std::vector<std::int64_t> indices_of(const MeshArrays& arrays) {
  if (arrays.wide) return {arrays.wide_polygon_indices.begin(), arrays.wide_polygon_indices.end()};
  return {arrays.polygon_indices.begin(), arrays.polygon_indices.end()};
}

// Runs the engine over the noise into the sink of mvox.extract's common case, numbering from
// `first`; its arrays.
MeshArrays aligned_arrays_from(std::uint64_t first) {
  const std::string label = "mvox.extract";
  const WorldTransform placement;  // the sink keeps a reference
  AlignedArraysSink sink(placement, kD, label, first);
  static const test::BinaryVolume noise = test::noise_volume(kW, kH, kD, 11);
  EngineOptions options;
  WorkspaceBuffer workspace(engine_workspace_bytes(kW, kH, options));
  Engine engine;
  Status status = engine.init(workspace.data(), workspace.bytes(), kW, kH, 128, options, &sink);
  detail::number_vertices_from(engine, first);
  for (std::uint32_t z = 0; z < kD && status == Status::ok; ++z)
    status = engine.push_slice(test::slice_of(noise, z));
  if (status == Status::ok) status = engine.finish();
  EXPECT_EQ(status, Status::ok);
  return std::move(sink.mesh());
}

// The arrays Python gets: 32-bit indices up to 2^31 vertices, then 64-bit ones, whole past
// 2^32 too, from MeshArraysWriter (mvox.Extractor, and mvox.extract with options) and from
// the common case's own sink alike; the indices already held move into the wide array when
// the count passes 2^31.
TEST(VertexIndexWriters, ArraysTurnTo64BitIndicesPast2To31AndStayWholePast2To32) {
  MeshArraysWriter zero(part_from(0), "mvox.extract");
  ASSERT_EQ(extract(zero, 0), Status::ok);
  zero.finish();
  ASSERT_FALSE(zero.arrays().wide);
  const std::vector<std::int64_t> reference = indices_of(zero.arrays());
  ASSERT_GT(reference.size(), 50000u);
  EXPECT_EQ(indices_of(aligned_arrays_from(0)), reference);
  ASSERT_FALSE(aligned_arrays_from(0).wide);

  for (const std::uint64_t first : {k2to31 - 10000, k2to32 - 10000}) {
    MeshArraysWriter writer(part_from(first), "mvox.extract");
    ASSERT_EQ(extract(writer, first), Status::ok) << first;
    writer.finish();
    for (const MeshArrays& arrays : {std::move(writer.arrays()), aligned_arrays_from(first)}) {
      ASSERT_TRUE(arrays.wide) << first;
      EXPECT_EQ(arrays.polygon_indices.size(), 0u);
      ASSERT_EQ(arrays.polygon_offsets.data()[arrays.face_count()],
                static_cast<std::int64_t>(arrays.index_count()));
      const std::vector<std::int64_t> moved = indices_of(arrays);
      ASSERT_EQ(moved.size(), reference.size());
      std::size_t past = 0;
      for (std::size_t i = 0; i < moved.size(); ++i) {
        ASSERT_EQ(moved[i], reference[i] + static_cast<std::int64_t>(first)) << "index " << i;
        past += static_cast<std::uint64_t>(moved[i]) >= (first < k2to32 ? k2to31 : k2to32);
      }
      EXPECT_GT(past, 10000u) << "no index passed the limit from " << first;
    }
  }
}

// A slab's polygons come with their indices moved by an offset, modulo 2^32 (SlabReplay);
// past 2^32 vertices each must land among the last 2^32 taken. Worked by hand: with 2^32 + 5000
// taken, those are 5000 to 2^32 + 4999.
TEST(VertexIndexWriters, WideIndicesAreMovedThenMadeWhole) {
  MeshArrays arrays;
  widen_indices(arrays);
  Polygon polygon;
  polygon.vertex_count = 3;
  polygon.vertices[0] = 4000;                                       // + 1000: 5000
  polygon.vertices[1] = static_cast<std::uint32_t>(k2to32 - 2000);  // 2^32 - 1000
  polygon.vertices[2] = 10;                                         // 1010: 2^32 + 1010
  polygon.vertices[3] = 0xdeadbeef;                                 // past the size
  append_wide_polygons(arrays, &polygon, 1, 1000, k2to32 + 5000);
  ASSERT_EQ(arrays.index_count(), 3u);
  EXPECT_EQ(arrays.wide_polygon_indices.data()[0], 5000);
  EXPECT_EQ(arrays.wide_polygon_indices.data()[1], static_cast<std::int64_t>(k2to32 - 1000));
  EXPECT_EQ(arrays.wide_polygon_indices.data()[2], static_cast<std::int64_t>(k2to32 + 1010));
  ASSERT_EQ(arrays.face_count(), 1u);
  EXPECT_EQ(arrays.polygon_offsets.data()[1], 3);
}

TEST(VertexIndexWriters, StlCountsTo2To32) {
  EXPECT_NO_THROW(mesh_file_head(MeshFormat::stl, {}, 0, k2to32 - 1));
  EXPECT_THROW(mesh_file_head(MeshFormat::stl, {}, 0, k2to32), Error);
}

}  // namespace
}  // namespace mvox
