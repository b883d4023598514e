// put_ply_faces (src/write/mesh/binary_records.h) must write exactly the record PLY defines for
// each face, a count byte and `vertex_count` little-endian indices plus the offset, modulo
// 2^32, whatever the unused index slots hold; and never touch a byte past the room it reserved
// (it writes all seven slots of every face and lets the next record cover the unused ones).
#include "write/mesh/binary_records.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace mvox {
namespace {

constexpr unsigned char kGuard = 0xa5;

// A Sink that hands out exactly the room asked for, followed by guard bytes, and checks at
// each commit that the guards are untouched and that no more than the room was committed.
class GuardedSink {
 public:
  void* reserve(std::size_t bytes) {
    room_ = bytes;
    run_.assign(bytes + kGuardBytes, kGuard);
    return run_.data();
  }
  void commit(std::size_t bytes) {
    EXPECT_LE(bytes, room_);
    for (std::size_t i = room_; i < run_.size(); ++i)
      ASSERT_EQ(run_[i], kGuard) << "written " << i - room_ << " bytes past the room";
    written_.insert(written_.end(), run_.begin(), run_.begin() + static_cast<long>(bytes));
    ++runs_;
  }
  const std::vector<unsigned char>& written() const { return written_; }
  int runs() const { return runs_; }

 private:
  static constexpr std::size_t kGuardBytes = 64;
  std::vector<unsigned char> run_;
  std::vector<unsigned char> written_;
  std::size_t room_ = 0;
  int runs_ = 0;
};

// The records as PLY defines them, a byte at a time.
std::vector<unsigned char> reference_records(const std::vector<Polygon>& faces,
                                             std::uint32_t index_offset) {
  std::vector<unsigned char> bytes;
  for (const Polygon& face : faces) {
    bytes.push_back(face.vertex_count);
    for (int k = 0; k < face.vertex_count; ++k) {
      const std::uint32_t index = face.vertices[k] + index_offset;
      for (int shift = 0; shift < 32; shift += 8)
        bytes.push_back(static_cast<unsigned char>(index >> shift));
    }
  }
  return bytes;
}

// Faces of every size from 3 to kMaxPolygonVertices in random order, their unused slots
// holding random values, as the engine's reused polygon arrays may.
std::vector<Polygon> random_faces(std::size_t count, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> size(3, kMaxPolygonVertices);
  std::vector<Polygon> faces(count);
  for (Polygon& face : faces) {
    face.vertex_count = static_cast<std::uint8_t>(size(random));
    for (std::uint32_t& slot : face.vertices) slot = static_cast<std::uint32_t>(random());
  }
  return faces;
}

TEST(BinaryRecords, PlyFacesAreTheDefinedRecordsWhateverTheUnusedSlotsHold) {
  const std::vector<Polygon> faces = random_faces(1000, 1);
  for (std::uint32_t offset : {0u, 17u, 0xfffffff0u}) {  // the last wraps modulo 2^32
    SCOPED_TRACE(offset);
    GuardedSink sink;
    put_ply_faces(sink, faces.data(), faces.size(), offset, "test.ply");
    EXPECT_EQ(sink.written(), reference_records(faces, offset));
  }
}

TEST(BinaryRecords, PlyFacesStayInsideTheirRoomAcrossRuns) {
  // Three runs' worth of faces; the first run ends with a triangle, the record with the most
  // unused slots.
  constexpr std::size_t kPerRun =
      BufferedWriter::kBufferBytes / ply_face_record_bytes(kMaxPolygonVertices);
  std::vector<Polygon> faces = random_faces(2 * kPerRun + 5, 2);
  faces[kPerRun - 1].vertex_count = 3;
  GuardedSink sink;
  put_ply_faces(sink, faces.data(), faces.size(), 5, "test.ply");
  EXPECT_EQ(sink.runs(), 3);
  EXPECT_EQ(sink.written(), reference_records(faces, 5));
}

TEST(BinaryRecords, PlyFacesOfTheLargestSizeFillTheirRoomExactly) {
  // Every face as large as can be: the room reserved is used to the byte, so a record written
  // past its own end would reach the guards.
  std::vector<Polygon> faces = random_faces(100, 3);
  for (Polygon& face : faces) face.vertex_count = kMaxPolygonVertices;
  GuardedSink sink;
  put_ply_faces(sink, faces.data(), faces.size(), 0, "test.ply");
  EXPECT_EQ(sink.written().size(), faces.size() * ply_face_record_bytes(kMaxPolygonVertices));
  EXPECT_EQ(sink.written(), reference_records(faces, 0));
}

TEST(BinaryRecords, PlyFaceLargerThanSevenIsRefusedNamingTheFile) {
  std::vector<Polygon> faces = random_faces(3, 4);
  faces[1].vertex_count = kMaxPolygonVertices + 1;
  GuardedSink sink;
  try {
    put_ply_faces(sink, faces.data(), faces.size(), 0, "out/mesh.ply");
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("out/mesh.ply"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace mvox
