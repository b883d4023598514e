// NRRD volumes (src/read/nrrd/nrrd_file.h) on files the tests write from a sim/ phantom: every
// type in both byte orders, attached and detached, raw and gzip, gives the phantom's samples
// and the raw volume reader's mesh on the same bytes; line and byte skips, concatenated gzip
// members and two dimensions; and the reader's refusals of missing, short and corrupt data.
#include "read/nrrd/nrrd_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "command_runner.h"
#include "deflate.h"
#include "error_capture.h"
#include "mesh_capture.h"
#include "mesh_compare.h"
#include "mesh_topology.h"
#include "read/input_format.h"
#include "read/range_readable.h"
#include "read/raw/raw_format.h"
#include "read/raw/raw_volume_source.h"
#include "volume_files.h"
#include "volume_samples.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::deflate_bytes;
using test::error_of;
using test::ScratchDirectory;
using test::volume_files::kDepth;
using test::volume_files::kHeight;
using test::volume_files::kSizes;
using test::volume_files::kWidth;
using test::volume_files::order_name;
using test::volume_files::read_volume;
using test::volume_files::write_file;

// ---------------------------------------------------------------------------------------------
// NRRD: samples

// Writes the phantom as `Stored` samples in a NRRD of `type_name`, reads it back as `Engine`
// samples (signed char is widened) and compares with the phantom, attached and detached, raw
// and gzip.
template <typename Stored, typename Engine>
void expect_nrrd_round_trip(const std::string& type_name, SampleType engine_type, ByteOrder order) {
  SCOPED_TRACE(type_name + ", " + order_name(order) + "-endian");
  const std::vector<Stored> stored = test::phantom_samples<Stored>(kWidth, kHeight, kDepth);
  const std::vector<Engine> expected(stored.begin(), stored.end());
  const std::vector<unsigned char> raw = test::encode_samples(stored, order);
  ScratchDirectory dir;
  const std::string fields = "type: " + type_name + "\ndimension: 3\nsizes: " + kSizes +
                             "\nendian: " + order_name(order) + "\n";

  write_file(dir / "attached.nrrd", "NRRD0004\n" + fields + "encoding: raw\n\n", raw);
  write_file(dir / "attached_gz.nrrd", "NRRD0005\n" + fields + "encoding: gzip\n\n",
             deflate_bytes(raw, true));
  write_file(dir / "volume.raw", "", raw);
  write_file(dir / "detached.nhdr",
             "NRRD0004\n" + fields + "encoding: raw\ndata file: volume.raw\n");
  for (const char* name : {"attached.nrrd", "attached_gz.nrrd", "detached.nhdr"}) {
    VolumeInfo info;
    EXPECT_EQ(read_volume<Engine>(dir / name, &info), expected) << name;
    EXPECT_EQ(info.type, engine_type) << name;
    EXPECT_EQ(info.width, kWidth);
    EXPECT_EQ(info.height, kHeight);
    EXPECT_EQ(info.depth, kDepth);
  }
}

TEST(NrrdVolume, EveryTypeInBothByteOrdersRoundTrips) {
  for (ByteOrder order : {ByteOrder::little, ByteOrder::big}) {
    expect_nrrd_round_trip<std::uint8_t, std::uint8_t>("uchar", SampleType::u8, order);
    expect_nrrd_round_trip<std::uint8_t, std::uint8_t>("uint8_t", SampleType::u8, order);
    expect_nrrd_round_trip<std::int8_t, std::int16_t>("signed char", SampleType::i16, order);
    expect_nrrd_round_trip<std::uint16_t, std::uint16_t>("unsigned short", SampleType::u16, order);
    expect_nrrd_round_trip<std::uint16_t, std::uint16_t>("uint16", SampleType::u16, order);
    expect_nrrd_round_trip<std::int16_t, std::int16_t>("short", SampleType::i16, order);
    expect_nrrd_round_trip<std::int16_t, std::int16_t>("Signed Short Int", SampleType::i16, order);
    expect_nrrd_round_trip<float, float>("float", SampleType::f32, order);
  }
}

// A slab's reader opens the data file again (StoredVolumeSource::open_range): a data file
// replaced since, by another file or a FIFO, is refused, not mixed in or waited for.
TEST(NrrdVolume, ARangeOfADataFileReplacedSinceItWasOpenedIsRefused) {
  ScratchDirectory dir;
  write_file(dir / "v.nhdr",
             "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\ndata file: "
             "v.raw\n");
  write_file(dir / "v.raw", std::string(8, '\x10'));
  std::unique_ptr<SliceSource> source = open_slice_source({dir / "v.nhdr"}, std::nullopt);
  const auto* ranges = dynamic_cast<const RangeReadable*>(source.get());
  ASSERT_NE(ranges, nullptr);
  EXPECT_NO_THROW(ranges->open_range(0, 2));
  fs::remove(dir / "v.raw");
  ASSERT_EQ(::mkfifo((dir / "v.raw").c_str(), 0600), 0);
  EXPECT_CONTAINS(error_of([&] { ranges->open_range(1, 2); }),
                  dir / "v.raw: was replaced by another file while mvox read it");
}

TEST(NrrdVolume, SamplesAndMeshEqualTheRawVolumeReaderOnTheSameBytes) {
  const std::vector<std::uint16_t> samples =
      test::phantom_samples<std::uint16_t>(kWidth, kHeight, kDepth);
  const std::vector<unsigned char> raw = test::encode_samples(samples, ByteOrder::big);
  ScratchDirectory dir;
  write_file(dir / "volume.raw", "", raw);
  write_file(dir / "volume.nhdr", std::string("NRRD0004\ntype: ushort\ndimension: 3\nsizes: ") +
                                      kSizes + "\nendian: big\nencoding: raw\ndata file: " +
                                      (dir / "volume.raw") + "\n");  // an absolute data file

  const RawFormat format = parse_raw_format("13x11x9:u16be");
  RawVolumeSource raw_source(dir / "volume.raw", format);
  auto nrrd_source = open_slice_source({dir / "volume.nhdr"}, std::nullopt);
  EXPECT_EQ(test::read_samples<std::uint16_t>(*nrrd_source),
            test::read_samples<std::uint16_t>(raw_source));

  RawVolumeSource raw_again(dir / "volume.raw", format);
  nrrd_source = open_slice_source({dir / "volume.nhdr"}, std::nullopt);
  // Between the phantom's outside (0) and its brain (0.2 and up).
  const double threshold = test::sample_from_density<std::uint16_t>(0.1);
  const test::Mesh from_nrrd = test::extract(*nrrd_source, threshold);
  EXPECT_TRUE(test::meshes_identical(from_nrrd, test::extract(raw_again, threshold)));
  EXPECT_GT(from_nrrd.polygons.size(), 50u);
  EXPECT_TRUE(test::analyse(from_nrrd).closed_and_consistent());
}

TEST(NrrdVolume, LineSkipAndByteSkipFindTheData) {
  const std::vector<std::uint8_t> samples =
      test::phantom_samples<std::uint8_t>(kWidth, kHeight, kDepth);
  const std::vector<unsigned char> raw = test::encode_samples(samples, ByteOrder::little);
  ScratchDirectory dir;
  fs::create_directories(dir / "data");
  // Two text lines and then 5 bytes before the samples, as a PGM-like header would be.
  write_file(dir / "data/slices.pgm", "P5 13 99\n255\nxxxxx", raw);
  write_file(dir / "skip.nhdr", std::string("NRRD0004\ntype: uchar\ndimension: 3\nsizes: ") +
                                    kSizes +
                                    "\nencoding: raw\ndata file: data/slices.pgm\nline skip: 2\n"
                                    "byte skip: 5\n");
  EXPECT_EQ(read_volume<std::uint8_t>(dir / "skip.nhdr"), samples);

  // byte skip -1: the samples are the last bytes of the file, whatever precedes them.
  write_file(dir / "at_end.nrrd",
             std::string("NRRD0004\ntype: uchar\ndimension: 3\nsizes: ") + kSizes +
                 "\nencoding: raw\nbyte skip: -1\n\nsome bytes the reader must pass over",
             raw);
  EXPECT_EQ(read_volume<std::uint8_t>(dir / "at_end.nrrd"), samples);

  // With gzip, teem skips bytes of the decompressed stream.
  // Built by copying into its final size: GCC 12 warned of a read past a vector's end, wrongly,
  // in the inlined growth of insert().
  std::vector<unsigned char> prefixed(3 + raw.size());
  const char prefix[] = "abc";
  std::copy(prefix, prefix + 3, prefixed.begin());
  std::copy(raw.begin(), raw.end(), prefixed.begin() + 3);
  write_file(dir / "skip_gz.nrrd",
             std::string("NRRD0004\ntype: uchar\ndimension: 3\nsizes: ") + kSizes +
                 "\nencoding: gz\nbyte skip: 3\n\n",
             deflate_bytes(prefixed, true));
  EXPECT_EQ(read_volume<std::uint8_t>(dir / "skip_gz.nrrd"), samples);
}

TEST(NrrdVolume, ConcatenatedGzipMembersAreOneStream) {
  const std::vector<std::int16_t> samples =
      test::phantom_samples<std::int16_t>(kWidth, kHeight, kDepth);
  const std::vector<unsigned char> raw = test::encode_samples(samples, ByteOrder::little);
  const std::size_t half = raw.size() / 2 + 7;  // a cut inside a slice and inside a sample
  std::vector<unsigned char> gz =
      deflate_bytes(std::vector<unsigned char>(raw.begin(), raw.begin() + half), true);
  const std::vector<unsigned char> second =
      deflate_bytes(std::vector<unsigned char>(raw.begin() + half, raw.end()), true);
  gz.insert(gz.end(), second.begin(), second.end());
  ScratchDirectory dir;
  write_file(dir / "two_members.nrrd",
             std::string("NRRD0004\ntype: short\ndimension: 3\nsizes: ") + kSizes +
                 "\nendian: little\nencoding: gzip\n\n",
             gz);
  EXPECT_EQ(read_volume<std::int16_t>(dir / "two_members.nrrd"), samples);
}

// The header is read 64 KiB first, then more until its blank line is in (read_file_start): a
// blank line split across the first read's end, and headers of several reads, are found.
TEST(NrrdVolume, HeadersLongerThanTheFirstReadAreReadWhole) {
  const std::vector<std::uint8_t> samples =
      test::phantom_samples<std::uint8_t>(kWidth, kHeight, kDepth);
  const std::vector<unsigned char> raw(samples.begin(), samples.end());
  ScratchDirectory dir;
  const std::string fields =
      "NRRD0004\ntype: uint8\ndimension: 3\nsizes: " + std::string(kSizes) + "\nencoding: raw\n";
  // Comment lines of "# xxx...\n", the last one cut so that the header holds exactly `bytes`.
  auto header_of = [&](std::size_t bytes) {
    std::string header = fields;
    while (header.size() + 100 < bytes) header += "# " + std::string(97, 'x') + "\n";
    header += "# " + std::string(bytes - header.size() - 3, 'y') + "\n";
    return header;
  };
  for (const std::size_t bytes : {std::size_t{65535}, std::size_t{65536}, std::size_t{65537},
                                  std::size_t{300000}, std::size_t{900000}}) {
    SCOPED_TRACE(bytes);
    const std::string header = header_of(bytes);
    ASSERT_EQ(header.size(), bytes);
    write_file(dir / "long.nrrd", header + "\n", raw);
    EXPECT_EQ(read_volume<std::uint8_t>(dir / "long.nrrd"), samples);
  }
}

TEST(NrrdVolume, TwoDimensionsAreOneSlice) {
  const std::vector<std::uint8_t> samples = test::phantom_samples<std::uint8_t>(kWidth, kHeight, 1);
  ScratchDirectory dir;
  write_file(dir / "slice.nrrd",
             "NRRD0004\ntype: uchar\ndimension: 2\nsizes: 13 11\nspacings: 0.5 0.25\n"
             "encoding: raw\n\n",
             test::encode_samples(samples, ByteOrder::little));
  VolumeInfo info;
  EXPECT_EQ(read_volume<std::uint8_t>(dir / "slice.nrrd", &info), samples);
  EXPECT_EQ(info.depth, 1u);
  EXPECT_DOUBLE_EQ(info.spacing[0], 0.5);
  EXPECT_DOUBLE_EQ(info.spacing[1], 0.25);
  EXPECT_DOUBLE_EQ(info.spacing[2], 1);
}

// ---------------------------------------------------------------------------------------------
// NRRD: refusals of the reader, which looks at the files

TEST(NrrdVolume, RefusesMissingShortAndCorruptData) {
  const std::vector<std::uint16_t> samples =
      test::phantom_samples<std::uint16_t>(kWidth, kHeight, kDepth);
  const std::vector<unsigned char> raw = test::encode_samples(samples, ByteOrder::little);
  const std::string fields =
      std::string("NRRD0004\ntype: ushort\ndimension: 3\nsizes: ") + kSizes + "\nendian: little\n";
  ScratchDirectory dir;

  write_file(dir / "missing.nhdr", fields + "encoding: raw\ndata file: nowhere.raw\n");
  std::string message = error_of([&] { read_volume<std::uint16_t>(dir / "missing.nhdr"); });
  EXPECT_CONTAINS(message, dir / "missing.nhdr: data file ");
  EXPECT_CONTAINS(message, "nowhere.raw does not exist");

  // A data file one sample short: named, with both sizes, before any slice is read.
  write_file(dir / "short.raw", "", std::vector<unsigned char>(raw.begin(), raw.end() - 2));
  write_file(dir / "short.nhdr", fields + "encoding: raw\ndata file: short.raw\n");
  message = error_of([&] { open_slice_source({dir / "short.nhdr"}, std::nullopt); });
  EXPECT_CONTAINS(message, dir / "short.raw: file is " + std::to_string(raw.size() - 2) +
                               " bytes, expected at least " + std::to_string(raw.size()) +
                               " for a 13x11x9 u16 volume (" + (dir / "short.nhdr") + ")");

  const std::string attached_header = fields + "encoding: raw\n\n";
  write_file(dir / "cut.nrrd", attached_header,
             std::vector<unsigned char>(raw.begin(), raw.begin() + raw.size() / 2));
  message = error_of([&] { open_slice_source({dir / "cut.nrrd"}, std::nullopt); });
  EXPECT_CONTAINS(message, dir / "cut.nrrd: file is " +
                               std::to_string(attached_header.size() + raw.size() / 2) +
                               " bytes, expected at least " +
                               std::to_string(attached_header.size() + raw.size()));

  // gzip cut short: its trailer is gone, so the stream is measured and found short.
  const std::vector<unsigned char> gz = deflate_bytes(raw, true);
  write_file(dir / "cut_gz.nrrd", fields + "encoding: gzip\n\n",
             std::vector<unsigned char>(gz.begin(), gz.begin() + gz.size() * 2 / 3));
  message = error_of([&] { open_slice_source({dir / "cut_gz.nrrd"}, std::nullopt); });
  EXPECT_CONTAINS(message, dir / "cut_gz.nrrd: compressed data hold ");
  EXPECT_CONTAINS(message, "bytes, expected " + std::to_string(raw.size()));

  // A complete gzip stream of too few samples: its trailer gives the size away.
  write_file(dir / "few_gz.nrrd", fields + "encoding: gzip\n\n",
             deflate_bytes(std::vector<unsigned char>(raw.begin(), raw.end() - 26), true));
  EXPECT_CONTAINS(error_of([&] { open_slice_source({dir / "few_gz.nrrd"}, std::nullopt); }),
                  "compressed data hold " + std::to_string(raw.size() - 26) + " bytes, expected " +
                      std::to_string(raw.size()));

  // Corrupt deflate data in the middle of the stream, with the trailer intact: the trailer's
  // size is trusted when the file opens, and the damage is found while reading.
  std::vector<unsigned char> corrupt = gz;
  for (std::size_t i = 20; i < corrupt.size() - 20; i += 7) corrupt[i] ^= 0x5a;
  write_file(dir / "corrupt_gz.nrrd", fields + "encoding: gzip\n\n", corrupt);
  EXPECT_CONTAINS(error_of([&] { read_volume<std::uint16_t>(dir / "corrupt_gz.nrrd"); }),
                  dir / "corrupt_gz.nrrd: compressed data are corrupt");

  // Not a NRRD at all, and a header with no end within the first MiB.
  write_file(dir / "text.nrrd", "hello\n");
  EXPECT_CONTAINS(error_of([&] { open_slice_source({dir / "text.nrrd"}, std::nullopt); }),
                  dir / "text.nrrd: not a NRRD file");
  write_file(dir / "endless.nrrd", "NRRD0004\n" + std::string(3 << 20, '#'));
  EXPECT_CONTAINS(error_of([&] { open_slice_source({dir / "endless.nrrd"}, std::nullopt); }),
                  "no blank line ends the header within its first 1048576 bytes");

  // line skip past the end of the data file.
  write_file(dir / "lines.raw", "one\ntwo\n");
  write_file(dir / "lines.nhdr", fields + "encoding: raw\ndata file: lines.raw\nline skip: 3\n");
  EXPECT_CONTAINS(error_of([&] { open_slice_source({dir / "lines.nhdr"}, std::nullopt); }),
                  dir / "lines.raw: line skip 3: the file has only 2 lines");

  // A NRRD volume is a whole volume: it cannot be one of several inputs.
  fs::create_directories(dir / "two");
  write_file(dir / "two/a.nrrd", attached_header, raw);
  write_file(dir / "two/b.nrrd", attached_header, raw);
  EXPECT_CONTAINS(error_of([&] { open_slice_source({dir / "two/*.nrrd"}, std::nullopt); }),
                  dir / "two/a.nrrd: is a NRRD volume, which must be the only input (got 2 files)");
  EXPECT_CONTAINS(
      error_of([&] { open_slice_source({dir / "two/a.nrrd"}, parse_raw_format("13x11x9:u16le")); }),
      "--raw: " + (dir / "two/a.nrrd") + " is a NRRD file with its own header");
}

}  // namespace
}  // namespace mvox
