// MetaImage volumes (src/read/metaimage/metaimage_file.h) on files the tests write from a sim/
// phantom: every type in both byte orders, in a separate file, local, compressed, gives the
// phantom's samples; HeaderSize skips bytes or puts the data at the end, and the mesh equals the
// raw volume reader's on the same bytes; and the reader's refusals of missing, short and
// truncated data.
#include "read/metaimage/metaimage_file.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "command_runner.h"
#include "deflate.h"
#include "error_capture.h"
#include "mesh_capture.h"
#include "mesh_compare.h"
#include "read/input_format.h"
#include "read/raw/raw_format.h"
#include "read/raw/raw_volume_source.h"
#include "volume_files.h"
#include "volume_samples.h"

namespace mvox {
namespace {

using test::deflate_bytes;
using test::error_of;
using test::ScratchDirectory;
using test::volume_files::kDepth;
using test::volume_files::kHeight;
using test::volume_files::kWidth;
using test::volume_files::metaimage_fields;
using test::volume_files::order_name;
using test::volume_files::read_volume;
using test::volume_files::write_file;

// ---------------------------------------------------------------------------------------------
// MetaImage: samples

template <typename Stored, typename Engine>
void expect_metaimage_round_trip(const std::string& element_type, ByteOrder order) {
  SCOPED_TRACE(element_type + ", " + order_name(order) + "-endian");
  const std::vector<Stored> stored = test::phantom_samples<Stored>(kWidth, kHeight, kDepth);
  const std::vector<Engine> expected(stored.begin(), stored.end());
  const std::vector<unsigned char> raw = test::encode_samples(stored, order);
  const std::string msb = order == ByteOrder::big ? "True" : "False";
  ScratchDirectory dir;

  write_file(dir / "volume.raw", "", raw);
  write_file(dir / "separate.mhd",
             metaimage_fields(element_type,
                              "ElementByteOrderMSB = " + msb + "\nElementDataFile = volume.raw\n"));
  write_file(dir / "local.mha",
             metaimage_fields(element_type, "BinaryData = True\nBinaryDataByteOrderMSB = " + msb +
                                                "\nElementDataFile = LOCAL\n"),
             raw);
  const std::vector<unsigned char> compressed = deflate_bytes(raw, false);
  write_file(dir / "compressed.mha",
             metaimage_fields(element_type, "BinaryDataByteOrderMSB = " + msb +
                                                "\nCompressedData = True\nCompressedDataSize = " +
                                                std::to_string(compressed.size()) +
                                                "\nElementDataFile = LOCAL\n"),
             compressed);
  write_file(dir / "volume.zraw", "", compressed);
  write_file(dir / "compressed.mhd",
             metaimage_fields(element_type, "ElementByteOrderMSB = " + msb +
                                                "\nCompressedData = True\n"
                                                "ElementDataFile = volume.zraw\n"));
  for (const char* name : {"separate.mhd", "local.mha", "compressed.mha", "compressed.mhd"}) {
    EXPECT_EQ(read_volume<Engine>(dir / name), expected) << name;
  }
}

TEST(MetaImageVolume, EveryTypeInBothByteOrdersRoundTrips) {
  for (ByteOrder order : {ByteOrder::little, ByteOrder::big}) {
    expect_metaimage_round_trip<std::uint8_t, std::uint8_t>("MET_UCHAR", order);
    expect_metaimage_round_trip<std::int8_t, std::int16_t>("MET_CHAR", order);
    expect_metaimage_round_trip<std::uint16_t, std::uint16_t>("MET_USHORT", order);
    expect_metaimage_round_trip<std::int16_t, std::int16_t>("MET_SHORT", order);
    expect_metaimage_round_trip<float, float>("MET_FLOAT", order);
  }
}

TEST(MetaImageVolume, HeaderSizeSkipsBytesOrPutsTheDataAtTheEnd) {
  const std::vector<float> samples = test::phantom_samples<float>(kWidth, kHeight, kDepth);
  const std::vector<unsigned char> raw = test::encode_samples(samples, ByteOrder::little);
  ScratchDirectory dir;
  write_file(dir / "prefixed.raw", "a 17-byte prefix.", raw);
  write_file(dir / "skip.mhd", metaimage_fields("MET_FLOAT",
                                                "HeaderSize = 17\n"
                                                "ElementDataFile = prefixed.raw\n"));
  EXPECT_EQ(read_volume<float>(dir / "skip.mhd"), samples);
  write_file(dir / "end.mhd", metaimage_fields("MET_FLOAT",
                                               "HeaderSize = -1\n"
                                               "ElementDataFile = prefixed.raw\n"));
  EXPECT_EQ(read_volume<float>(dir / "end.mhd"), samples);
  write_file(dir / "end.mha",
             metaimage_fields("MET_FLOAT", "HeaderSize = -1\nElementDataFile = LOCAL\n") + "junk",
             raw);
  EXPECT_EQ(read_volume<float>(dir / "end.mha"), samples);

  // And the mesh of the float volume equals the raw volume reader's on the same bytes.
  write_file(dir / "plain.raw", "", raw);
  RawVolumeSource raw_source(dir / "plain.raw", parse_raw_format("13x11x9:f32le"));
  auto source = open_slice_source({dir / "end.mha"}, std::nullopt);
  const double threshold = test::sample_from_density<float>(0.1);
  const test::Mesh from_metaimage = test::extract(*source, threshold);
  EXPECT_TRUE(test::meshes_identical(from_metaimage, test::extract(raw_source, threshold)));
  EXPECT_GT(from_metaimage.polygons.size(), 50u);
}

TEST(MetaImageVolume, RefusesMissingShortAndTruncatedData) {
  const std::vector<std::uint8_t> samples =
      test::phantom_samples<std::uint8_t>(kWidth, kHeight, kDepth);
  const std::vector<unsigned char> raw = test::encode_samples(samples, ByteOrder::little);
  ScratchDirectory dir;
  write_file(dir / "missing.mhd", metaimage_fields("MET_UCHAR", "ElementDataFile = gone.raw\n"));
  EXPECT_CONTAINS(error_of([&] { open_slice_source({dir / "missing.mhd"}, std::nullopt); }),
                  dir / "missing.mhd: data file ");

  write_file(dir / "short.raw", "", std::vector<unsigned char>(raw.begin(), raw.end() - 1));
  write_file(dir / "short.mhd", metaimage_fields("MET_UCHAR", "ElementDataFile = short.raw\n"));
  EXPECT_CONTAINS(error_of([&] { open_slice_source({dir / "short.mhd"}, std::nullopt); }),
                  dir / "short.raw: file is " + std::to_string(raw.size() - 1) +
                      " bytes, expected at least " + std::to_string(raw.size()));

  // Compressed data cut short, with CompressedDataSize saying how much there should be.
  const std::vector<unsigned char> compressed = deflate_bytes(raw, false);
  const std::string header = metaimage_fields(
      "MET_UCHAR", "CompressedData = True\nCompressedDataSize = " +
                       std::to_string(compressed.size()) + "\nElementDataFile = LOCAL\n");
  write_file(dir / "cut.mha", header,
             std::vector<unsigned char>(compressed.begin(), compressed.end() - 10));
  EXPECT_CONTAINS(
      error_of([&] { open_slice_source({dir / "cut.mha"}, std::nullopt); }),
      dir / "cut.mha: file is " + std::to_string(header.size() + compressed.size() - 10) +
          " bytes, expected at least " + std::to_string(header.size() + compressed.size()));
  // Without CompressedDataSize the stream itself is found short.
  write_file(dir / "cut2.mha",
             metaimage_fields("MET_UCHAR", "CompressedData = True\nElementDataFile = LOCAL\n"),
             std::vector<unsigned char>(compressed.begin(), compressed.end() - 10));
  EXPECT_CONTAINS(error_of([&] { open_slice_source({dir / "cut2.mha"}, std::nullopt); }),
                  dir / "cut2.mha: compressed data hold ");
}

}  // namespace
}  // namespace mvox
