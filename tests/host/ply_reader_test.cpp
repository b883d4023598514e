// The strict PLY reader (src/read/ply/ply_reader.h): all three formats with extra properties and
// elements, point clouds and empty meshes, every bad header and body refused naming the file,
// absurd counts refused before allocating, single-byte corruptions that never crash, printable
// messages, and file errors that name the path.
#include "read/ply/ply_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "command_runner.h"
#include "error.h"
#include "error_capture.h"
#include "file_io.h"

namespace mvox {
namespace {

using test::error_of;
using test::ScratchDirectory;
using test::write_bytes;

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
  ScratchDirectory dir;
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

// `mvox render /dev/zero` read the endless device into memory until the system ran out, and a
// 100 GiB file was allocated whole before its first bytes were looked at. The header is checked
// first, and a binary body is read only as far as its header's counts allow.
TEST(PlyReader, IsRefusedFromItsStartWithoutReadingMoreThanItsHeaderAllows) {
  EXPECT_CONTAINS(error_of([] { read_ply("/dev/zero"); }),
                  "/dev/zero: not a PLY file: the first line is not \"ply\"");
  ScratchDirectory dir;
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  // 3 vertices of 12 bytes and a face of at most 1 + 255 x 4 bytes after the header.
  const std::uint64_t most = header.size() + 3 * 12 + 1 + 255 * 4;
  const std::string sparse = dir.file("sparse.ply");
  write_bytes(sparse, header);
  std::filesystem::resize_file(sparse, std::uint64_t{1} << 30);  // a gigabyte of holes
  EXPECT_CONTAINS(error_of([&] { read_ply(sparse); }),
                  sparse + ": holds more than its header describes (at most " +
                      std::to_string(most) + " bytes)");
  // A file at that limit is read, and refused for what its body holds; one byte more is not read.
  const std::string at_most = dir.file("at_most.ply");
  write_bytes(at_most, header + std::string(most - header.size(), '\0'));
  EXPECT_CONTAINS(error_of([&] { read_ply(at_most); }), "face 0: face with 0 vertices");
  write_bytes(at_most, header + std::string(most - header.size() + 1, '\0'));
  EXPECT_CONTAINS(error_of([&] { read_ply(at_most); }), "holds more than its header describes");
  // A header is read from the first MiB: one longer says so, not that it has no end.
  std::string comments;
  while (comments.size() <= (std::size_t{1} << 20))
    comments += "comment " + std::string(90, 'c') + "\n";
  const std::string long_header = dir.file("long_header.ply");
  write_bytes(long_header, "ply\nformat ascii 1.0\n" + comments + "element vertex 0\nend_header\n");
  EXPECT_CONTAINS(error_of([&] { read_ply(long_header); }),
                  "header has no end_header line in its first MiB");
}

}  // namespace
}  // namespace mvox
