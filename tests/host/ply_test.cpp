// Tests of OutputFile, PlyWriter and the strict PLY reader: writer output read back exactly,
// header layout to the byte, all-or-nothing file creation, and the reader's refusals.
#include <dirent.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "error.h"
#include "file_io.h"
#include "read/ply/ply_reader.h"
#include "stdout_redirect.h"
#include "write/mesh/ply_writer.h"
#include "write/output_file.h"

namespace mvox {
namespace {

using test::read_bytes;
using test::write_bytes;

// HELPERS -------------------------------------------------------------------------------------

// A fresh directory per test, removed with its contents afterwards.
class TempDir {
 public:
  TempDir() {
    std::string pattern = ::testing::TempDir() + "mvox_ply_test.XXXXXX";
    std::vector<char> name(pattern.begin(), pattern.end());
    name.push_back('\0');
    if (::mkdtemp(name.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = name.data();
  }
  ~TempDir() {
    for (const std::string& entry : entries()) ::unlink((path_ + "/" + entry).c_str());
    ::rmdir(path_.c_str());
  }
  std::string file(const std::string& name) const { return path_ + "/" + name; }
  // Every name in the directory, hidden ones included (the writers' temporaries are hidden).
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    if (DIR* dir = ::opendir(path_.c_str())) {
      while (const dirent* entry = ::readdir(dir)) {
        const std::string name = entry->d_name;
        if (name != "." && name != "..") names.push_back(name);
      }
      ::closedir(dir);
    }
    return names;
  }

 private:
  std::string path_;
};

bool exists(const std::string& path) {
  struct stat status {};
  return ::stat(path.c_str(), &status) == 0;
}

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

// OUTPUT FILE ---------------------------------------------------------------------------------

TEST(OutputFile, AppearsOnlyAtCommit) {
  TempDir dir;
  const std::string target = dir.file("out.bin");
  {
    OutputFile out(target);
    out.write("hello world", 11);
    EXPECT_TRUE(out.can_overwrite());
    EXPECT_FALSE(exists(target));
    ASSERT_EQ(dir.entries().size(), 1u);
    EXPECT_EQ(dir.entries()[0].rfind(".out.bin.", 0), 0u) << dir.entries()[0];
    out.overwrite(6, "W", 1);
    EXPECT_EQ(out.bytes_written(), 11u);
    out.commit();
  }
  EXPECT_EQ(read_bytes(target), "hello World");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.bin"});
}

TEST(OutputFile, WritesLargerThanTheBufferArriveInOrder) {
  TempDir dir;
  std::string expected;
  {
    OutputFile out(dir.file("big.bin"));
    for (int round = 0; round < 3; ++round) {
      // Small writes that straddle the buffer, then one block larger than the buffer.
      for (int i = 0; i < 70000; ++i) {
        const std::string piece = std::to_string(i) + ",";
        out.write(piece.data(), piece.size());
        expected += piece;
      }
      const std::string block(BufferedWriter::kBufferBytes + 17, static_cast<char>('a' + round));
      out.write(block.data(), block.size());
      expected += block;
    }
    out.overwrite(1, "#", 1);
    expected[1] = '#';
    out.commit();
  }
  EXPECT_EQ(read_bytes(dir.file("big.bin")), expected);
}

TEST(OutputFile, DestructorWithoutCommitLeavesNothingAndKeepsThePreviousFile) {
  TempDir dir;
  const std::string target = dir.file("keep.txt");
  write_bytes(target, "previous");
  {
    OutputFile out(target);
    out.write("new", 3);
  }
  EXPECT_EQ(read_bytes(target), "previous");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"keep.txt"});
}

TEST(OutputFile, MissingDirectoryNamesTheTarget) {
  TempDir dir;
  const std::string target = dir.file("no/such/dir/mesh.ply");
  try {
    OutputFile out(target);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()),
              target + ": cannot create file: No such file or directory");
    EXPECT_EQ(error.subject(), target);
  }
}

TEST(OutputFile, DirectoryTargetIsRefused) {
  TempDir dir;
  EXPECT_THROW(OutputFile out(dir.file("")), Error);
  try {
    OutputFile out(::testing::TempDir());
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("Is a directory"), std::string::npos);
  }
}

TEST(OutputFile, FullDeviceIsReported) {
  if (!exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  try {
    // A device is written directly (renaming onto it would replace the device node).
    OutputFile out("/dev/full");
    EXPECT_FALSE(out.can_overwrite());
    out.write("x", 1);
    out.commit();
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), "/dev/full: write failed: No space left on device");
  }
  struct stat status {};
  ASSERT_EQ(::stat("/dev/full", &status), 0);
  EXPECT_TRUE(S_ISCHR(status.st_mode)) << "/dev/full was replaced";
}

TEST(OutputFile, StandardOutputFullIsReported) {
  if (!exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  std::string message;
  {
    test::StdoutRedirect redirect("/dev/full");
    try {
      OutputFile out("-");
      out.write("x", 1);
      out.commit();
    } catch (const Error& error) {
      message = error.what();
    }
  }
  EXPECT_EQ(message, "standard output: write failed: No space left on device");
}

// PLY WRITER ----------------------------------------------------------------------------------

TEST(PlyWriter, BinaryTetrahedronWithSpacingAndOrigin) {
  TempDir dir;
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
  TempDir dir;
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
  TempDir dir;
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
  TempDir dir;
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
  TempDir dir;
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

TEST(PlyWriter, NoTargetBeforeFinishNorWithoutIt) {
  TempDir dir;
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
  TempDir dir;
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
  TempDir dir;
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
  TempDir dir;
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
  TempDir dir;
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

TEST(PlyWriter, RefusesMoreVerticesThanIntIndicesAddress) {
  TempDir dir;
  PlyWriter writer(dir.file("mesh.ply"));
  // The count is checked before any vertex is read, so one real vertex suffices.
  EXPECT_EQ(writer.consume_vertices(kTetraVertices.data(), (std::size_t{1} << 31) + 1),
            Status::sink_refused);
  EXPECT_THROW(writer.finish(), Error);
}

TEST(PlyWriter, RefusesBadOptions) {
  TempDir dir;
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
  TempDir dir;
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
int write_past_file_size_limit(const TempDir& dir) {
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
  TempDir dir;
  EXPECT_EXIT(std::_Exit(write_past_file_size_limit(dir)), ::testing::ExitedWithCode(0), "");
}

// PLY READER ----------------------------------------------------------------------------------

// Builds binary PLY bodies in either byte order.
class Bytes {
 public:
  explicit Bytes(bool big_endian) : big_endian_(big_endian) {}
  template <class T>
  Bytes& put(T value) {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    // The test host is little-endian (x86, ARM); reverse for big-endian files.
    if (big_endian_) std::reverse(raw, raw + sizeof(T));
    text_.append(reinterpret_cast<const char*>(raw), sizeof(T));
    return *this;
  }
  const std::string& str() const { return text_; }

 private:
  bool big_endian_;
  std::string text_;
};

PlyMesh parse(const std::string& bytes) { return parse_ply(bytes.data(), bytes.size(), "t.ply"); }

// Expects a refusal that names the file and mentions `problem`.
void expect_refused(const std::string& bytes, const std::string& problem) {
  try {
    parse(bytes);
    ADD_FAILURE() << "accepted, expected \"" << problem << "\":\n" << bytes;
  } catch (const Error& error) {
    EXPECT_EQ(error.subject(), "t.ply");
    EXPECT_NE(error.problem().find(problem), std::string::npos)
        << "message: " << error.what() << "\nexpected: " << problem;
  }
}

// clang-format off
// A header with extra vertex properties of several types, a list in the vertex element, an
// extra element with a list, and "vertex_index" with a ushort count.
std::string rich_header(const std::string& format) {
  return "ply\r\n"  // CRLF header lines are accepted
         "format " + format + " 1.0\n"
         "comment from another program\n"
         "obj_info scanner 7\n"
         "element vertex 3\n"
         "property double x\n"
         "property uchar red\n"
         "property int16 y\n"
         "property list uint8 float32 texcoord\n"
         "property float z\n"
         "element face 2\n"
         "property uchar flags\n"
         "property list ushort uint vertex_index\n"
         "element edge 1\n"
         "property list int int8 pair\n"
         "property char crease\n"
         "end_header\n";
}

void expect_rich_mesh(const PlyMesh& mesh) {
  ASSERT_EQ(mesh.vertex_count(), 3u);
  EXPECT_EQ(mesh.positions[0], (std::array<float, 3>{1.5f, -2.0f, 0.25f}));
  EXPECT_EQ(mesh.positions[1], (std::array<float, 3>{-1e10f, 300.0f, 7.0f}));
  EXPECT_EQ(mesh.positions[2], (std::array<float, 3>{0.0f, -32768.0f, -0.5f}));
  ASSERT_EQ(mesh.face_count(), 2u);
  EXPECT_EQ(mesh.face_offsets, (std::vector<std::uint32_t>{0, 3, 7}));
  EXPECT_EQ(mesh.face_indices, (std::vector<std::uint32_t>{0, 1, 2, 2, 1, 0, 1}));
}

std::string rich_binary(bool big_endian) {
  using std::int8_t, std::int16_t, std::int32_t, std::uint8_t, std::uint16_t, std::uint32_t;
  Bytes body(big_endian);
  // One line per element instance, as in the header's order of properties.
  body.put(1.5).put<uint8_t>(255).put<int16_t>(-2).put<uint8_t>(2).put(0.5f).put(0.75f).put(0.25f);
  body.put(-1e10).put<uint8_t>(0).put<int16_t>(300).put<uint8_t>(0).put(7.0f);
  body.put(0.0).put<uint8_t>(1).put<int16_t>(-32768).put<uint8_t>(1).put(1.0f).put(-0.5f);
  body.put<uint8_t>(9).put<uint16_t>(3).put<uint32_t>(0).put<uint32_t>(1).put<uint32_t>(2);
  body.put<uint8_t>(0).put<uint16_t>(4).put<uint32_t>(2).put<uint32_t>(1).put<uint32_t>(0)
      .put<uint32_t>(1);
  body.put<int32_t>(2).put<int8_t>(-1).put<int8_t>(1).put<int8_t>(-100);
  return rich_header(big_endian ? "binary_big_endian" : "binary_little_endian") + body.str();
}
// clang-format on

const char kRichAscii[] =
    "1.5 255 -2 2 0.5 0.75 0.25\n"
    "-1e10 0 300 0 7\n"
    "0\t1 -32768 1 1.0 -0.5   \r\n"
    "9 3 0 1 2\n"
    "0 4 2 1 0 1\n"
    "2 -1 1 -100\n";

TEST(PlyReader, ReadsAllThreeFormatsWithExtraPropertiesAndElements) {
  expect_rich_mesh(parse(rich_binary(false)));
  expect_rich_mesh(parse(rich_binary(true)));
  expect_rich_mesh(parse(rich_header("ascii") + kRichAscii));
  // A file without a trailing newline is complete too.
  std::string ascii = rich_header("ascii") + kRichAscii;
  ascii.pop_back();
  expect_rich_mesh(parse(ascii));
}

TEST(PlyReader, PointCloudWithoutFacesAndEmptyMesh) {
  const PlyMesh cloud = parse(
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n1 2 3\n4 5 6\n");
  EXPECT_EQ(cloud.vertex_count(), 2u);
  EXPECT_EQ(cloud.face_count(), 0u);
  const PlyMesh empty = parse(
      "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n"
      "property float y\nproperty float z\nelement face 0\n"
      "property list uchar int vertex_indices\nend_header\n");
  EXPECT_EQ(empty.vertex_count(), 0u);
  EXPECT_EQ(empty.face_count(), 0u);
}

const char kTriangleHeader[] =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
const char kTriangleVertices[] = "0 0 0\n1 0 0\n0 1 0\n";

TEST(PlyReader, RefusesBadHeaders) {
  expect_refused("", "empty file");
  expect_refused("plx\nformat ascii 1.0\nend_header\n", "not a PLY file");
  expect_refused("PLY\n", "not a PLY file");
  expect_refused("ply", "not a PLY file");
  expect_refused("ply\nformat ascii 1.0\nelement vertex 0\n", "no end_header");
  expect_refused("ply\nformat binary_middle_endian 1.0\nend_header\n", "unknown format");
  expect_refused("ply\nformat ascii 2.0\nend_header\n", "unsupported PLY version");
  expect_refused("ply\nformat ascii\nend_header\n", "needs 2 values");
  expect_refused("ply\nelement vertex 0\nend_header\n", "element before the format line");
  expect_refused("ply\nend_header\n", "end_header before the format line");
  expect_refused("ply\nformat ascii 1.0\nformat ascii 1.0\nend_header\n", "second format");
  expect_refused("ply\nformat ascii 1.0\nproperty float x\nend_header\n", "property before");
  expect_refused("ply\nformat ascii 1.0\nelephant vertex 1\nend_header\n", "unknown header");
  expect_refused("ply\nformat ascii 1.0\n\nend_header\n", "empty header line");
  expect_refused("ply\nformat ascii 1.0\nend_header\n", "no vertex element");
  expect_refused("ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", "element count");
  expect_refused("ply\nformat ascii 1.0\nelement vertex 99999999999999999999\nend_header\n",
                 "element count");
  const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
  expect_refused("ply\nformat ascii 1.0\nelement vertex 0\n" + xyz +
                     "property int128 w\n"
                     "end_header\n",
                 "unknown property type");
  expect_refused(
      "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
      "end_header\n",
      "no property \"z\"");
  expect_refused("ply\nformat ascii 1.0\nelement vertex 0\n" + xyz +
                     "property float x\n"
                     "end_header\n",
                 "second property");
  expect_refused("ply\nformat ascii 1.0\nelement vertex 0\n" + xyz +
                     "element vertex 0\n"
                     "end_header\n",
                 "second element");
  expect_refused(
      "ply\nformat ascii 1.0\nelement vertex 0\nproperty list uchar float x\n"
      "property float y\nproperty float z\nend_header\n",
      "is a list");
  expect_refused("ply\nformat ascii 1.0\nelement vertex 0\n" + xyz +
                     "element face 0\n"
                     "property list uchar int vertex_ids\nend_header\n",
                 "no vertex_indices");
  expect_refused("ply\nformat ascii 1.0\nelement vertex 0\n" + xyz +
                     "element face 0\n"
                     "property int vertex_indices\nend_header\n",
                 "not a list");
  expect_refused("ply\nformat ascii 1.0\nelement vertex 0\n" + xyz +
                     "element face 0\n"
                     "property list uchar float vertex_indices\nend_header\n",
                 "non-integer");
  expect_refused("ply\nformat ascii 1.0\nelement vertex 0\n" + xyz +
                     "element face 0\n"
                     "property list float int vertex_indices\nend_header\n",
                 "length type");
  expect_refused(
      "ply\nformat ascii 1.0\nelement vertex 0\n" + xyz +
          "element face 0\n"
          "property list uchar int vertex_indices\nproperty list uchar int vertex_index\n"
          "end_header\n",
      "both");
  expect_refused("ply\nformat ascii 1.0\nelement vertex 0\n" + xyz + "element note 5\nend_header\n",
                 "has no properties");
  // Binary garbage where the header should be.
  expect_refused(std::string("ply\n\x01\xff\x00garbage\n", 15), "unknown header keyword");
}

TEST(PlyReader, RefusesBadAsciiBodies) {
  const std::string header = kTriangleHeader;
  const std::string v = kTriangleVertices;
  EXPECT_EQ(parse(header + v + "3 0 1 2\n").face_count(), 1u);
  expect_refused(header + v + "3 0 1 3\n", "vertex index 3 out of range (3 vertices)");
  expect_refused(header + v + "3 0 -1 2\n", "vertex index -1 out of range");
  expect_refused(header + v + "0\n", "face with 0 vertices");
  expect_refused(header + v + "3 0 1\n", "fewer values");
  expect_refused(header + v + "3 0 1 2 0\n", "more values");
  expect_refused(header + v + "3 0 1 2\n3 0 1 2\n", "after the last element");
  expect_refused(header + v, "header declares 1 face elements");
  expect_refused(header + "0 0 0\n1 0 0\n", "vertex 2 (line 12): fewer values");
  expect_refused(header + "0 0\n", "header declares 3 vertex elements");
  expect_refused(header + "0 0 0\n\n1 0 0\n0 1 0\n3 0 1 2\n", "fewer values");
  expect_refused(header + "0 0 zero\n1 0 0\n0 1 0\n3 0 1 2\n", "\"zero\" is not a number");
  expect_refused(header + "0 0 +1\n1 0 0\n0 1 0\n3 0 1 2\n", "is not a number");
  expect_refused(header + "0 0 nan\n1 0 0\n0 1 0\n3 0 1 2\n", "not a finite float");
  expect_refused(header + "0 0 1e39\n1 0 0\n0 1 0\n3 0 1 2\n", "not a finite float");
  expect_refused(header + "0 0 1e999\n1 0 0\n0 1 0\n3 0 1 2\n", "is not a number");
  expect_refused(header + v + "256 0 1 2\n", "out of range for its type");
  expect_refused(header + v + "3 0 1.0 2\n", "is not an integer");
  expect_refused(header + v + "-3 0 1 2\n", "out of range for its type");
  // Line numbers count from the top of the file.
  expect_refused(header + v + "3 0 1 x\n", "face 0 (line 13)");
}

TEST(PlyReader, RefusesBadBinaryBodies) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  Bytes vertices(false);
  for (int i = 0; i < 9; ++i) vertices.put(static_cast<float>(i));
  auto face = [](int count, std::vector<std::int32_t> indices) {
    Bytes bytes(false);
    bytes.put(static_cast<std::uint8_t>(count));
    for (std::int32_t index : indices) bytes.put(index);
    return bytes.str();
  };
  const std::string good = header + vertices.str() + face(3, {0, 1, 2});
  EXPECT_EQ(parse(good).face_count(), 1u);
  expect_refused(header + vertices.str() + face(3, {0, 3, 2}), "vertex index 3 out of range");
  expect_refused(header + vertices.str() + face(3, {0, -1, 2}), "vertex index -1 out of range");
  expect_refused(header + vertices.str() + face(0, {}), "face with 0 vertices");
  expect_refused(good + "\n", "1 bytes follow the last element");
  expect_refused(header + vertices.str() + face(200, {0, 1, 2}), "file ends too early");
  // Every proper prefix of a valid binary file is refused, and none is read past its end.
  for (std::size_t size = 0; size < good.size(); ++size) {
    EXPECT_THROW(parse_ply(good.data(), size, "t.ply"), Error) << size;
  }
  Bytes nan(false);
  nan.put(std::numeric_limits<float>::quiet_NaN());
  expect_refused(header + nan.str() + vertices.str().substr(4) + face(3, {0, 1, 2}),
                 "not a finite float");
}

TEST(PlyReader, RefusesAbsurdCountsBeforeAllocating) {
  // 4 * 10^9 vertices or 2^64 - 1 faces in a few bytes: refused from the size check, not by
  // bad_alloc.
  expect_refused(
      "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
      "property float x\nproperty float y\nproperty float z\nend_header\n0000",
      "more than the rest of the file can hold");
  expect_refused(
      "ply\nformat binary_big_endian 1.0\nelement vertex 0\nproperty float x\n"
      "property float y\nproperty float z\nelement face 18446744073709551615\n"
      "property list uchar int vertex_indices\nend_header\n",
      "more than the rest of the file can hold");
  expect_refused(
      "ply\nformat ascii 1.0\nelement vertex 4294967296\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n",
      "more than 2^32 - 1");
  // A list length of 2^32 - 1 in an element that is skipped.
  Bytes body(false);
  body.put<std::uint32_t>(0xffffffffu).put<std::uint32_t>(1);
  expect_refused(
      "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n"
      "property float y\nproperty float z\nelement blob 1\n"
      "property list uint double data\nend_header\n" +
          body.str(),
      "file ends too early");
}

// A poor man's fuzzer that runs everywhere: every single-byte change of valid files must give a
// mesh or an mvox::Error, nothing else (run under MVOX_SANITIZE=ON for memory errors and UB).
TEST(PlyReader, SingleByteCorruptionsNeverCrash) {
  const std::string originals[] = {rich_binary(false), rich_binary(true),
                                   rich_header("ascii") + kRichAscii};
  const unsigned char kReplacements[] = {0x00, 0xff, '0', '9', ' ', '\n', '-', 0x80};
  std::size_t refused = 0;
  for (const std::string& original : originals) {
    for (std::size_t i = 0; i < original.size(); ++i) {
      for (unsigned char replacement : kReplacements) {
        std::string corrupt = original;
        corrupt[i] = static_cast<char>(replacement);
        try {
          const PlyMesh mesh = parse(corrupt);
          ASSERT_EQ(mesh.face_offsets.back(), mesh.face_indices.size());
          for (std::uint32_t index : mesh.face_indices) ASSERT_LT(index, mesh.vertex_count());
        } catch (const Error&) {
          ++refused;
        }
      }
    }
  }
  EXPECT_GT(refused, 0u);
}

// Found by fuzz/ply_reader_fuzzer: an element's name went into messages as the file had it, so
// a control character, or a carriage return, reached the terminal.
TEST(PlyReader, MessagesArePrintableWhateverTheElementNames) {
  const std::string name = std::string("fac\x01\x1b[2J\r") + std::string(60, '\xa3');
  const std::string files[] = {
      // An instance of the element fails ...
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nelement " +
          name + " 1\nproperty int a\nend_header\n0 0 0\nnot-a-number\n",
      // ... or its count does not fit in the file.
      "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
      "property float z\nelement " +
          name + " 99\nproperty int a\nend_header\n"};
  for (const std::string& file : files) {
    std::string message;
    try {
      parse(file);
    } catch (const Error& e) {
      message = e.what();
    }
    ASSERT_FALSE(message.empty());
    for (const char c : message)
      EXPECT_TRUE(c >= 0x20 && c < 0x7f)
          << "byte " << int(static_cast<unsigned char>(c)) << " in " << message;
    EXPECT_NE(message.find("fac??[2J??"), std::string::npos) << message;
  }
}

TEST(PlyReader, FileErrorsNameThePath) {
  TempDir dir;
  const std::string missing = dir.file("missing.ply");
  try {
    read_ply(missing);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), missing + ": cannot open file: No such file or directory");
  }
  try {
    read_ply(::testing::TempDir());
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(error.problem().find("Is a directory"), std::string::npos) << error.what();
  }
  const std::string truncated = dir.file("truncated.ply");
  write_bytes(truncated, std::string(kTriangleHeader) + kTriangleVertices + "3 0 1");
  try {
    read_ply(truncated);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(error.subject(), truncated);
  }
}

}  // namespace
}  // namespace mvox
