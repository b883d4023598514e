// PlyWriter (src/write/mesh/ply_writer.h): its output read back exactly by the strict PLY reader
// in both formats whatever the batching, the header's layout to the byte, no file before
// finish() nor without it, refusals that keep the previous file, standard output, and a device
// or a file size limit that fills up.
#include "write/mesh/ply_writer.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "command_runner.h"
#include "error.h"
#include "file_io.h"
#include "read/ply/ply_reader.h"
#include "stdout_redirect.h"

namespace mvox {
namespace {

using test::exists;
using test::read_bytes;
using test::ScratchDirectory;
using test::write_bytes;

Vertex vertex(float x, float y, float z) {
  Vertex v;
  v.x = x;
  v.y = y;
  v.z = z;
  return v;
}

Polygon polygon(std::initializer_list<std::uint32_t> indices) {
  Polygon p;
  for (std::uint32_t index : indices) p.vertices[p.vertex_count++] = index;
  return p;
}

// A tetrahedron at half-integer voxel midpoints, wound counter-clockwise seen from outside.
const std::vector<Vertex> kTetraVertices = {vertex(0.5f, 0, 0), vertex(3, 0.5f, 0),
                                            vertex(0, 2.5f, 0), vertex(0, 0, 1.5f)};
const std::vector<Polygon> kTetraFaces = {polygon({0, 2, 1}), polygon({0, 1, 3}),
                                          polygon({1, 2, 3}), polygon({2, 0, 3})};

// The unit cube [0,1]^3 as six quads.
const std::vector<Vertex> kCubeVertices = {vertex(0, 0, 0), vertex(1, 0, 0), vertex(1, 1, 0),
                                           vertex(0, 1, 0), vertex(0, 0, 1), vertex(1, 0, 1),
                                           vertex(1, 1, 1), vertex(0, 1, 1)};
const std::vector<Polygon> kCubeFaces = {polygon({0, 3, 2, 1}), polygon({4, 5, 6, 7}),
                                         polygon({0, 1, 5, 4}), polygon({2, 3, 7, 6}),
                                         polygon({1, 2, 6, 5}), polygon({0, 4, 7, 3})};

// Feeds a mesh the way the engine does: vertex batches, then polygon batches whose vertices
// have all been sent. `batch` sizes cycle (0 is a legal empty batch).
void feed(PolygonSink& sink, const std::vector<Vertex>& vertices,
          const std::vector<Polygon>& polygons, const std::vector<std::size_t>& batches = {}) {
  std::size_t turn = 0;
  auto next_batch = [&](std::size_t left) {
    if (batches.empty()) return left;
    return std::min(left, batches[turn++ % batches.size()]);
  };
  for (std::size_t i = 0; i < vertices.size();) {
    const std::size_t count = next_batch(vertices.size() - i);
    ASSERT_EQ(sink.consume_vertices(vertices.data() + i, count), Status::ok);
    i += count;
  }
  for (std::size_t i = 0; i < polygons.size();) {
    const std::size_t count = next_batch(polygons.size() - i);
    ASSERT_EQ(sink.consume_polygons(polygons.data() + i, count), Status::ok);
    i += count;
  }
}

// The mesh as the reader should return it.
void expect_mesh(const PlyMesh& mesh, const std::vector<Vertex>& vertices,
                 const std::vector<Polygon>& polygons, const PlyWriterOptions& options = {}) {
  ASSERT_EQ(mesh.vertex_count(), vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const float voxel[3] = {vertices[i].x, vertices[i].y, vertices[i].z};
    for (int axis = 0; axis < 3; ++axis) {
      const float expected = static_cast<float>(options.transform.origin[axis] +
                                                options.transform.spacing[axis] * voxel[axis]);
      EXPECT_EQ(mesh.positions[i][axis], expected) << "vertex " << i << " axis " << axis;
    }
  }
  ASSERT_EQ(mesh.face_count(), polygons.size());
  ASSERT_EQ(mesh.face_offsets.front(), 0u);
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    const std::uint32_t begin = mesh.face_offsets[i];
    ASSERT_EQ(mesh.face_offsets[i + 1] - begin, polygons[i].vertex_count) << "face " << i;
    for (int k = 0; k < polygons[i].vertex_count; ++k) {
      EXPECT_EQ(mesh.face_indices[begin + k], polygons[i].vertices[k]) << "face " << i;
    }
  }
}

std::size_t face_bytes(const std::vector<Polygon>& polygons) {
  std::size_t bytes = 0;
  for (const Polygon& p : polygons) bytes += 1 + 4 * p.vertex_count;
  return bytes;
}

// Checks the writer's header layout: the expected lines, then a padding comment of spaces, then
// end_header ending exactly at the reserved size. Returns the header.
std::string expect_padded_header(const std::string& file, const std::string& expected_lines,
                                 const PlyWriterOptions& options) {
  const std::size_t reserved = PlyWriter::reserved_header_bytes(options);
  EXPECT_GE(file.size(), reserved);
  const std::string header = file.substr(0, reserved);
  EXPECT_EQ(header.compare(0, expected_lines.size(), expected_lines), 0) << header;
  const std::size_t end = header.find("end_header\n");
  EXPECT_EQ(end, reserved - std::strlen("end_header\n")) << header;
  const std::string padding = header.substr(expected_lines.size(), end - expected_lines.size());
  EXPECT_EQ(padding.rfind("comment ", 0), 0u) << padding;
  EXPECT_EQ(padding.back(), '\n');
  EXPECT_EQ(padding.find_first_not_of(' ', 7), padding.size() - 1) << "padding is not spaces";
  return header;
}

// A deterministic mixed mesh: `vertex_count` vertices, polygons of 3..7 vertices.
void make_mesh(std::size_t vertex_count, std::size_t polygon_count, std::vector<Vertex>* vertices,
               std::vector<Polygon>* polygons) {
  std::uint64_t state = 12345;
  auto next = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<std::uint32_t>(state >> 33);
  };
  vertices->clear();
  polygons->clear();
  for (std::size_t i = 0; i < vertex_count; ++i) {
    vertices->push_back(vertex(static_cast<float>(next() % 4096) * 0.5f,
                               static_cast<float>(next() % 4096) * 0.5f,
                               static_cast<float>(next() % 4096) * 0.5f));
  }
  for (std::size_t i = 0; i < polygon_count; ++i) {
    Polygon p;
    p.vertex_count = static_cast<std::uint8_t>(3 + next() % 5);
    for (int k = 0; k < p.vertex_count; ++k) p.vertices[k] = next() % vertex_count;
    polygons->push_back(p);
  }
}

// PLY WRITER ----------------------------------------------------------------------------------

TEST(PlyWriter, BinaryTetrahedronWithSpacingAndOrigin) {
  ScratchDirectory dir;
  const std::string target = dir.file("tetra.ply");
  PlyWriterOptions options;
  options.transform.spacing = {0.5, 2.0, 0.25};
  options.transform.origin = {10.0, -3.0, 100.5};
  options.comments = {"generated by mvox, threshold 600"};
  PlyWriter writer(target, options);
  feed(writer, kTetraVertices, kTetraFaces);
  EXPECT_FALSE(exists(target));
  writer.finish();
  EXPECT_EQ(writer.vertices_written(), 4u);
  EXPECT_EQ(writer.faces_written(), 4u);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"tetra.ply"});

  const std::string file = read_bytes(target);
  expect_padded_header(file,
                       "ply\n"
                       "format binary_little_endian 1.0\n"
                       "comment generated by mvox, threshold 600\n"
                       "element vertex 4\n"
                       "property float x\n"
                       "property float y\n"
                       "property float z\n"
                       "element face 4\n"
                       "property list uchar int vertex_indices\n",
                       options);
  EXPECT_EQ(file.size(), PlyWriter::reserved_header_bytes(options) + 12 * 4 + 13 * 4);
  // The first vertex, byte for byte: 10 + 0.5 * 0.5 = 10.25 = 0x41240000 little-endian.
  EXPECT_EQ(file.substr(PlyWriter::reserved_header_bytes(options), 4),
            std::string("\x00\x00\x24\x41", 4));

  expect_mesh(read_ply(target), kTetraVertices, kTetraFaces, options);
}

TEST(PlyWriter, AsciiCubeOfQuadsSplitAcrossBatches) {
  ScratchDirectory dir;
  const std::string target = dir.file("cube.ply");
  PlyWriterOptions options;
  options.format = PlyFormat::ascii;
  PlyWriter writer(target, options);
  feed(writer, kCubeVertices, kCubeFaces, {3, 0, 5, 1, 2});
  writer.finish();

  const std::string file = read_bytes(target);
  expect_padded_header(file,
                       "ply\n"
                       "format ascii 1.0\n"
                       "element vertex 8\n"
                       "property float x\n"
                       "property float y\n"
                       "property float z\n"
                       "element face 6\n"
                       "property list uchar int vertex_indices\n",
                       options);
  EXPECT_EQ(file.substr(PlyWriter::reserved_header_bytes(options)),
            "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
            "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n");
  expect_mesh(read_ply(target), kCubeVertices, kCubeFaces);
}

TEST(PlyWriter, AsciiFloatsRoundTripExactly) {
  ScratchDirectory dir;
  const std::string target = dir.file("floats.ply");
  PlyWriterOptions options;
  options.format = PlyFormat::ascii;
  options.transform.spacing = {0.1, 0.3, 1.0 / 3.0};
  options.transform.origin = {-12.345, 1e-3, 7e6};
  const std::vector<Vertex> vertices = {vertex(0.5f, 1.5f, 2.5f), vertex(2047.5f, 1.0f, 3999.5f),
                                        vertex(1e-7f, 123456.5f, 0)};
  PlyWriter writer(target, options);
  feed(writer, vertices, {polygon({0, 1, 2})});
  writer.finish();
  expect_mesh(read_ply(target), vertices, {polygon({0, 1, 2})}, options);
}

TEST(PlyWriter, BatchingDoesNotChangeTheBytes) {
  ScratchDirectory dir;
  std::vector<Vertex> vertices;
  std::vector<Polygon> polygons;
  make_mesh(1000, 1500, &vertices, &polygons);
  for (PlyFormat format : {PlyFormat::binary_little_endian, PlyFormat::ascii}) {
    PlyWriterOptions options;
    options.format = format;
    PlyWriter whole(dir.file("whole.ply"), options);
    feed(whole, vertices, polygons);
    whole.finish();
    PlyWriter split(dir.file("split.ply"), options);
    feed(split, vertices, polygons, {1, 7, 0, 64, 3});
    split.finish();
    EXPECT_EQ(read_bytes(dir.file("whole.ply")), read_bytes(dir.file("split.ply")));
  }
}

// Larger than the write buffers, so vertices and faces cross several flushes.
TEST(PlyWriter, LargeMixedMeshRoundTripsInBothFormats) {
  ScratchDirectory dir;
  std::vector<Vertex> vertices;
  std::vector<Polygon> polygons;
  make_mesh(120000, 150000, &vertices, &polygons);
  for (PlyFormat format : {PlyFormat::binary_little_endian, PlyFormat::ascii}) {
    SCOPED_TRACE(format == PlyFormat::ascii ? "ascii" : "binary");
    PlyWriterOptions options;
    options.format = format;
    options.transform.spacing = {0.75, 0.5, 1.25};
    const std::string target = dir.file("large.ply");
    PlyWriter writer(target, options);
    feed(writer, vertices, polygons, {4096});
    writer.finish();
    if (format == PlyFormat::binary_little_endian) {
      EXPECT_EQ(read_bytes(target).size(), PlyWriter::reserved_header_bytes(options) +
                                               12 * vertices.size() + face_bytes(polygons));
    }
    expect_mesh(read_ply(target), vertices, polygons, options);
  }
}

// Binary PLY without normals places a vertex batch straight into its buffer, a run of
// MeshWriter::kPositionsPerRun at a time: batches of one vertex, of a run and one, and of
// several runs read back as placed, to a file and to standard output (where the vertices wait
// in a scratch file); and a vertex beyond float's range in a later run is named as a placed
// batch names it.
TEST(PlyWriter, BinaryPositionsGoStraightIntoTheBufferRunByRun) {
  ScratchDirectory dir;
  std::vector<Vertex> vertices;
  std::vector<Polygon> polygons;
  make_mesh(3 * MeshWriter::kPositionsPerRun + 5, 1000, &vertices, &polygons);
  PlyWriterOptions options;
  options.transform.spacing = {0.75, 0.5, 1.25};
  options.transform.origin = {-3.0, 0.0, 7.5};
  const std::string target = dir.file("runs.ply");
  {
    PlyWriter writer(target, options);
    feed(writer, vertices, polygons, {1, MeshWriter::kPositionsPerRun + 1, vertices.size()});
    writer.finish();
  }
  expect_mesh(read_ply(target), vertices, polygons, options);
  {
    test::StdoutRedirect redirect(dir.file("piped.ply"));
    PlyWriter writer("-", options);
    feed(writer, vertices, polygons, {vertices.size()});
    writer.finish();
  }
  expect_mesh(read_ply(dir.file("piped.ply")), vertices, polygons, options);

  PlyWriterOptions far;
  far.transform.spacing = {1e36, 1.0, 1.0};  // x beyond 340 leaves float's range
  std::vector<Vertex> batch(2 * MeshWriter::kPositionsPerRun, vertex(1, 2, 3));
  batch[MeshWriter::kPositionsPerRun + 7].x = 400;
  PlyWriter writer(dir.file("far.ply"), far);
  EXPECT_EQ(writer.consume_vertices(batch.data(), batch.size()), Status::sink_refused);
  ASSERT_NE(writer.error(), nullptr);
  const std::string words = writer.error()->what();
  EXPECT_NE(words.find("vertex " + std::to_string(MeshWriter::kPositionsPerRun + 7) +
                       " lies outside the float range"),
            std::string::npos)
      << words;
  EXPECT_THROW(writer.finish(), Error);
  EXPECT_FALSE(exists(dir.file("far.ply")));
}

TEST(PlyWriter, NoTargetBeforeFinishNorWithoutIt) {
  ScratchDirectory dir;
  const std::string target = dir.file("mesh.ply");
  {
    PlyWriter writer(target);
    feed(writer, kCubeVertices, kCubeFaces);
    EXPECT_FALSE(exists(target));
    // Only the vertex temporary has a name; the face scratch file was unlinked at creation.
    ASSERT_EQ(dir.entries().size(), 1u);
    EXPECT_EQ(dir.entries()[0].rfind(".mesh.ply.", 0), 0u) << dir.entries()[0];
  }
  EXPECT_FALSE(exists(target));
  EXPECT_TRUE(dir.entries().empty());
}

TEST(PlyWriter, MissingDirectoryIsAnErrorNamingThePath) {
  ScratchDirectory dir;
  const std::string target = dir.file("out/mesh.ply");
  try {
    PlyWriter writer(target);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()),
              target + ": cannot create file: No such file or directory");
  }
  EXPECT_TRUE(dir.entries().empty());
}

TEST(PlyWriter, RefusalKeepsThePreviousFileAndFinishThrows) {
  ScratchDirectory dir;
  const std::string target = dir.file("mesh.ply");
  write_bytes(target, "previous mesh");
  {
    PlyWriter writer(target);
    ASSERT_EQ(writer.consume_vertices(kTetraVertices.data(), kTetraVertices.size()), Status::ok);
    // Vertex 4 was never sent: the engine broke its contract, and the writer refuses.
    const Polygon bad = polygon({0, 1, 4});
    EXPECT_EQ(writer.consume_polygons(&bad, 1), Status::sink_refused);
    ASSERT_NE(writer.error(), nullptr);
    EXPECT_NE(std::string(writer.error()->what()).find("refers to vertex 4"), std::string::npos);
    // Refusal is final.
    EXPECT_EQ(writer.consume_polygons(kTetraFaces.data(), kTetraFaces.size()),
              Status::sink_refused);
    EXPECT_EQ(writer.consume_vertices(kTetraVertices.data(), 1), Status::sink_refused);
    try {
      writer.finish();
      FAIL() << "no error";
    } catch (const Error& error) {
      EXPECT_EQ(error.subject(), target);
      EXPECT_NE(std::string(error.what()).find("refers to vertex 4"), std::string::npos);
    }
  }
  EXPECT_EQ(read_bytes(target), "previous mesh");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"mesh.ply"});
}

TEST(PlyWriter, SuccessReplacesThePreviousFile) {
  ScratchDirectory dir;
  const std::string target = dir.file("mesh.ply");
  write_bytes(target, "previous mesh");
  PlyWriter writer(target);
  feed(writer, kTetraVertices, kTetraFaces);
  EXPECT_EQ(read_bytes(target), "previous mesh");
  writer.finish();
  expect_mesh(read_ply(target), kTetraVertices, kTetraFaces);
  EXPECT_THROW(writer.finish(), Error);
}

TEST(PlyWriter, RefusesPolygonsOfWrongSize) {
  ScratchDirectory dir;
  for (std::uint8_t count : {0, 2, 8, 255}) {
    PlyWriter writer(dir.file("mesh.ply"));
    ASSERT_EQ(writer.consume_vertices(kCubeVertices.data(), kCubeVertices.size()), Status::ok);
    Polygon bad = polygon({0, 1, 2});
    bad.vertex_count = count;
    EXPECT_EQ(writer.consume_polygons(&bad, 1), Status::sink_refused) << int{count};
    EXPECT_THROW(writer.finish(), Error);
  }
  EXPECT_TRUE(dir.entries().empty());
}

TEST(PlyWriter, RefusesMoreVerticesThanItsIndexListsAddress) {
  ScratchDirectory dir;
  PlyWriter writer(dir.file("mesh.ply"));
  // The count is checked before any vertex is read, so one real vertex suffices. Up to 2^32
  // vertices PLY's lists take "uint" (vertex_index_writers_test); one more is refused. (This
  // test asked for 2^31 + 1 once, when the lists were "int" only; since, that many passed the
  // check and the batch failed for want of memory instead.)
  EXPECT_EQ(writer.consume_vertices(kTetraVertices.data(), (std::size_t{1} << 32) + 1),
            Status::sink_refused);
  ASSERT_NE(writer.error(), nullptr);
  EXPECT_NE(std::string(writer.error()->what()).find("32-bit index lists"), std::string::npos)
      << writer.error()->what();
  EXPECT_THROW(writer.finish(), Error);
}

TEST(PlyWriter, RefusesBadOptions) {
  ScratchDirectory dir;
  const double kBadSpacings[] = {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                                 std::numeric_limits<double>::infinity(), 1e300};
  for (double spacing : kBadSpacings) {
    PlyWriterOptions options;
    options.transform.spacing[1] = spacing;
    EXPECT_THROW(PlyWriter(dir.file("mesh.ply"), options), Error) << spacing;
  }
  PlyWriterOptions options;
  options.transform.origin[2] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(PlyWriter(dir.file("mesh.ply"), options), Error);
  options = {};
  options.comments = {"two\nlines"};
  EXPECT_THROW(PlyWriter(dir.file("mesh.ply"), options), Error);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(PlyWriter, StandardOutputGetsAnUnpaddedFile) {
  ScratchDirectory dir;
  const std::string captured = dir.file("stdout.ply");
  for (PlyFormat format : {PlyFormat::binary_little_endian, PlyFormat::ascii}) {
    PlyWriterOptions options;
    options.format = format;
    {
      test::StdoutRedirect redirect(captured);
      PlyWriter writer("-", options);
      feed(writer, kCubeVertices, kCubeFaces, {5});
      writer.finish();
    }
    const std::string file = read_bytes(captured);
    EXPECT_EQ(file.find("comment"), std::string::npos);
    if (format == PlyFormat::binary_little_endian) {
      EXPECT_EQ(file.size(), file.find("end_header\n") + 11 + 12 * 8 + 17 * 6);
    }
    expect_mesh(read_ply(captured), kCubeVertices, kCubeFaces);
  }
}

TEST(PlyWriter, FullDeviceIsAnError) {
  if (!exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  PlyWriter writer("/dev/full");
  feed(writer, kCubeVertices, kCubeFaces);
  try {
    writer.finish();
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), "/dev/full: write failed: No space left on device");
  }
}

// Runs in a child process with a file size limit; returns its exit code: 0 when the writer
// refused, finish() reported the write error, and the directory was left empty.
int write_past_file_size_limit(const ScratchDirectory& dir) {
  std::vector<Vertex> vertices;
  std::vector<Polygon> polygons;
  make_mesh(200000, 10, &vertices, &polygons);  // 2.4 MB of vertices, past the 1 MiB buffer
  std::signal(SIGXFSZ, SIG_IGN);                // get EFBIG instead of being killed
  const rlimit limit = {64 * 1024, 64 * 1024};
  if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) return 3;
  int exit_code = 1;
  {
    PlyWriter writer(dir.file("mesh.ply"));
    bool refused = false;
    for (std::size_t i = 0; i < vertices.size() && !refused; i += 4096) {
      const std::size_t count = std::min<std::size_t>(4096, vertices.size() - i);
      refused = writer.consume_vertices(vertices.data() + i, count) == Status::sink_refused;
    }
    try {
      writer.finish();
    } catch (const Error& error) {
      const bool reported =
          std::string(error.what()).find(": write failed: File too large") != std::string::npos;
      if (refused && reported) exit_code = 0;
    }
  }
  if (!dir.entries().empty()) exit_code = 2;
  return exit_code;
}

// A disk that fills up mid-mesh, simulated with a file size limit in a child process.
TEST(PlyWriter, FileSizeLimitMidMeshLeavesNothing) {
  ScratchDirectory dir;
  EXPECT_EXIT(std::_Exit(write_past_file_size_limit(dir)), ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace mvox
