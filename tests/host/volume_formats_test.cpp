// NRRD and MetaImage volumes: the header parsers (pure functions, so every refusal is checked on
// text), the readers on files the tests write from a sim/ phantom (same samples as the phantom
// and as the raw volume reader on the same bytes), the command line's refusals (one line, exit
// code, no output file), and the shared datasets tooth.nrrd and HeadMRVolume.mhd when present.
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "command_runner.h"
#include "deflate.h"
#include "error.h"
#include "error_capture.h"
#include "gtest/gtest.h"
#include "mesh_capture.h"
#include "mesh_compare.h"
#include "mesh_topology.h"
#include "ply_mesh.h"
#include "read/input_format.h"
#include "read/metaimage/metaimage_header.h"
#include "read/nrrd/nrrd_header.h"
#include "read/ply/ply_reader.h"
#include "read/raw/raw_format.h"
#include "read/raw/raw_volume_source.h"
#include "volume_samples.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::deflate_bytes;
using test::error_of;

using test::expect_one_line_error;
using test::run_mvox;
using test::ScratchDirectory;

// Odd, different sizes on every axis, so that a swapped axis cannot go unnoticed.
constexpr std::uint32_t kWidth = 13, kHeight = 11, kDepth = 9;
constexpr const char* kSizes = "13 11 9";

void write_file(const std::string& path, const std::string& text,
                const std::vector<unsigned char>& bytes = {}) {
  std::ofstream out(path, std::ios::binary);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

std::string text_of(const std::vector<unsigned char>& bytes) {
  return std::string(bytes.begin(), bytes.end());
}

// Every sample of the volume the factory opens for `path` (no --raw).
template <typename T>
std::vector<T> read_volume(const std::string& path, VolumeInfo* info = nullptr) {
  auto source = open_slice_source({path}, std::nullopt);
  if (info) *info = source->info();
  return test::read_samples<T>(*source);
}

const char* order_name(ByteOrder order) { return order == ByteOrder::big ? "big" : "little"; }

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
  std::vector<unsigned char> prefixed = {'a', 'b', 'c'};
  prefixed.insert(prefixed.end(), raw.begin(), raw.end());
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
// NRRD: geometry, from the header text alone

NrrdHeader parse_nrrd(const std::string& fields) {
  return parse_nrrd_header(
      "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 13 11 9\nencoding: raw\n" + fields + "\n\n",
      "test.nrrd");
}

void expect_axes(const VolumeInfo& info, const double (&axes)[3][3], const double (&spacing)[3]) {
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(info.spacing[a], spacing[a], 1e-12) << "axis " << a;
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(info.axes[a][i], axes[a][i], 1e-12) << a << "," << i;
  }
}

TEST(NrrdHeader, AnisotropicSpaceDirectionsGiveSpacingAndIdentityAxes) {
  const NrrdHeader header = parse_nrrd(
      "space: left-posterior-superior\nspace directions: (0.5,0,0) (0, 0.75, 0) (0,0,2.5)\n"
      "space origin: (-10.5,20,3e1)\nkinds: domain domain domain");
  expect_axes(header.volume.info, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {0.5, 0.75, 2.5});
  EXPECT_DOUBLE_EQ(header.volume.info.origin[0], -10.5);
  EXPECT_DOUBLE_EQ(header.volume.info.origin[1], 20);
  EXPECT_DOUBLE_EQ(header.volume.info.origin[2], 30);
  EXPECT_TRUE(header.ended_by_blank_line);
  EXPECT_TRUE(header.data_file.empty());
}

TEST(NrrdHeader, RotatedFrameGivesUnitAxesAndLengths) {
  // Columns run along +y, rows along -x (a quarter turn about z), slices tilted in y-z by 30
  // degrees: each vector's length is the spacing and its direction the axis.
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  char third[64];
  std::snprintf(third, sizeof third, "(0,%.17g,%.17g)", 3 * s, 3 * c);  // every digit
  const std::string directions = std::string("(0,0.8,0) (-1.2,0,0) ") + third;
  const NrrdHeader header =
      parse_nrrd("space dimension: 3\nspace directions: " + directions + "\nspace origin: (1,2,3)");
  expect_axes(header.volume.info, {{0, 1, 0}, {-1, 0, 0}, {0, s, c}}, {0.8, 1.2, 3});
  EXPECT_DOUBLE_EQ(header.volume.info.origin[2], 3);
}

TEST(NrrdHeader, SpacingsNanAndNegative) {
  const NrrdHeader header = parse_nrrd("spacings: 1.5 NaN -2");
  // NaN means "unknown": 1. A negative spacing turns the axis and keeps a positive size.
  expect_axes(header.volume.info, {{1, 0, 0}, {0, 1, 0}, {0, 0, -1}}, {1.5, 1, 2});
}

TEST(NrrdHeader, CommentsKeyValuesAndAliasesAreAccepted) {
  const NrrdHeader header = parse_nrrd_header(
      "NRRD0001\r\n# a comment\r\nTYPE: unsigned char\r\nDimension: 3\r\nsizes: 2 3 4\r\n"
      "encoding: raw\r\nmodality:=CT\r\ncontent: a:=b\r\nlineskip: 1\r\nbyteskip: 2\r\n"
      "datafile: x.raw\r\nlabels: \"x\" \"y\" \"z\"\r\n",
      "a.nhdr");
  EXPECT_EQ(header.volume.info.width, 2u);
  EXPECT_EQ(header.volume.info.depth, 4u);
  EXPECT_EQ(header.data_file, "x.raw");
  EXPECT_EQ(header.line_skip, 1u);
  EXPECT_EQ(header.byte_skip, 2);
  EXPECT_FALSE(header.ended_by_blank_line);
}

TEST(NrrdHeader, HeaderBytesEndAfterTheBlankLine) {
  const std::string header = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\n";
  EXPECT_EQ(parse_nrrd_header(header + "\n\nDATA", "a.nrrd").header_bytes, header.size());
}

TEST(NrrdHeader, RefusalsNameTheFileLineAndProblem) {
  const std::string base = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 13 11 9\nencoding: raw\n";
  struct Case {
    std::string text;
    std::string expected;  // part of the message after "bad.nrrd: "
  };
  const Case cases[] = {
      {"P5\n", "not a NRRD file"},
      {"NRRD0009\n", "line 1: unknown NRRD version"},
      {"NRRD0004\ntype: int32\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\n",
       "line 2: type: \"int32\" (32-bit signed integer) is not supported"},
      {"NRRD0004\ntype: double\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\n",
       "\"double\" (64-bit float) is not supported"},
      {"NRRD0004\ntype: complex\n\n", "line 2: type: unknown type \"complex\""},
      {base + "spacing: 1 1 1\n\n", "line 6: unknown field \"spacing\""},
      {base + "no colon here\n\n", "line 6: expected FIELD: VALUE"},
      {base + "sizes: 1 2 3\n\n", "line 6: sizes: given again (first on line 4)"},
      {"NRRD0004\ntype: uchar\ndimension: 3\nencoding: raw\n\n", "no \"sizes:\" field"},
      {"NRRD0004\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\n", "no \"type:\" field"},
      {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 1\n\n", "no \"encoding:\" field"},
      {"NRRD0004\ntype: short\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\n",
       "no \"endian:\" field"},
      {"NRRD0004\ntype: uchar\ndimension: 4\nsizes: 1 1 1 1\nencoding: raw\n\n",
       "line 3: dimension: 4 is not supported"},
      {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 13 11\nencoding: raw\n\n",
       "line 4: sizes: expected 3 values (dimension 3), got 2"},
      {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 13 0 9\nencoding: raw\n\n",
       "size \"0\" of axis 1 is not a whole number"},
      {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 13 -1 9\nencoding: raw\n\n",
       "size \"-1\" of axis 1"},
      {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 99999999999 1 1\nencoding: raw\n\n",
       "size \"99999999999\" of axis 0"},
      {"NRRD0004\ntype: float\ndimension: 3\nsizes: 4294967295 4294967295 4294967295\n"
       "encoding: raw\nendian: little\n\n",
       "too large to address"},
      {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 1\nencoding: bzip2\n\n",
       "line 5: encoding: \"bzip2\" is not supported"},
      {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 1\nencoding: zip\n\n",
       "unknown encoding \"zip\""},
      {"NRRD0004\ntype: short\ndimension: 3\nsizes: 1 1 1\nencoding: raw\nendian: middle\n\n",
       "endian: expected little or big"},
      {base + "kinds: RGB-color domain domain\n\n", "line 6: kinds: axis 0 is of kind"},
      {base + "kinds: domain domain\n\n", "kinds: expected 3 values"},
      {base + "space: RAS\nspace directions: (1,0,0) (0,1,0) (0,0,1)\nspacings: 1 1 1\n\n",
       "line 8: spacings: given with \"space directions:\""},
      {base + "space: RAS\nspace directions: none (0,1,0) (0,0,1)\n\n",
       "space directions: axis 0 is \"none\""},
      {base + "space: RAS\nspace directions: (0,0,0) (0,1,0) (0,0,1)\n\n",
       "the direction of axis 0 \"(0,0,0)\" has zero length"},
      {base + "space: RAS\nspace directions: (1,0) (0,1,0) (0,0,1)\n\n",
       "expected a vector of 3 numbers (space dimension 3), got \"(1,0)\""},
      {base + "space: RAS\nspace directions: (1,0,0,0) (0,1,0) (0,0,1)\n\n",
       "expected a vector of 3 finite numbers"},
      {base + "space: RAS\nspace directions: (1,0,x) (0,1,0) (0,0,1)\n\n",
       "expected a vector of 3 finite numbers"},
      {base + "space: RAS\nspace directions: [1,0,0] (0,1,0) (0,0,1)\n\n",
       "expected a vector like (1,0,0)"},
      {base + "space directions: (1,0,0) (0,1,0) (0,0,1)\n\n",
       "needs a \"space:\" or \"space dimension:\""},
      {base + "space: RAST\n\n", "a 4-dimensional space is not supported"},
      {base + "space: somewhere\n\n", "unknown space \"somewhere\""},
      {base + "space: RAS\nspace dimension: 3\n\n", "the format allows only one of them"},
      {base + "spacings: 1 0 1\n\n", "spacing \"0\" of axis 1 is not a non-zero finite number"},
      {base + "spacings: 1 inf 1\n\n", "spacing \"inf\" of axis 1"},
      {base + "space: RAS\nspace directions: (1,0,0) (0,1,0) (0,2,0)\n\n",
       "line 7: space directions: the three axes are parallel or coplanar"},
      {base + "space: RAS\nspace directions: (1,0,0) (0,1,0) (1,1,0)\n\n",
       "the three axes are parallel or coplanar"},
      {base + "data file: LIST\n", "lists and numbered patterns of data files are not supported"},
      {base + "data file: slice%03d.raw 1 9 1\n", "lists and numbered patterns"},
      {base, "names no \"data file:\" and no blank line ends it"},
      {base + "byte skip: -2\n\n", "byte skip: expected a whole number or -1"},
      {"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 1\nencoding: gzip\nbyte skip: -1\n\n",
       "-1 (data at the end of the file) needs raw encoding"},
      {base + "line skip: lots\n\n", "line skip: expected a whole number"},
  };
  for (const Case& c : cases) {
    const std::string message = error_of([&] { parse_nrrd_header(c.text, "bad.nrrd"); });
    EXPECT_EQ(message.rfind("bad.nrrd: ", 0), 0u) << message;
    EXPECT_CONTAINS(message, c.expected);
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
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

// ---------------------------------------------------------------------------------------------
// MetaImage: samples

std::string metaimage_fields(const std::string& element_type, const std::string& extra) {
  return std::string("ObjectType = Image\nNDims = 3\nDimSize = ") + kSizes +
         "\nElementType = " + element_type + "\n" + extra;
}

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

// ---------------------------------------------------------------------------------------------
// MetaImage: geometry from the header text alone

MetaImageHeader parse_metaimage(const std::string& extra) {
  return parse_metaimage_header(metaimage_fields("MET_UCHAR", extra + "ElementDataFile = v.raw\n"),
                                "test.mhd");
}

TEST(MetaImageHeader, SpacingOffsetAndTransformMatrix) {
  // TransformMatrix numbers 3i..3i+2 are the direction of axis i (ITK's reading): here x runs
  // along world y, y along world -x, z along z.
  const MetaImageHeader header = parse_metaimage(
      "ElementSpacing = 0.5 0.75 2.5\nElementSize = 9 9 9\nOffset = -1 2.5 1e2\n"
      "TransformMatrix = 0 1 0 -1 0 0 0 0 1\nAnatomicalOrientation = RAI\nComment = ignored\n");
  expect_axes(header.volume.info, {{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}}, {0.5, 0.75, 2.5});
  EXPECT_DOUBLE_EQ(header.volume.info.origin[0], -1);
  EXPECT_DOUBLE_EQ(header.volume.info.origin[1], 2.5);
  EXPECT_DOUBLE_EQ(header.volume.info.origin[2], 100);
  EXPECT_EQ(header.data_file, "v.raw");
  EXPECT_FALSE(header.data_local);
}

TEST(MetaImageHeader, ElementSizeIsTheSpacingOnlyWithoutElementSpacing) {
  expect_axes(parse_metaimage("ElementSize = 2 3 4\n").volume.info,
              {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {2, 3, 4});
  // Position and Origin are Offset's other names; a negative spacing turns its axis.
  const MetaImageHeader header = parse_metaimage("Position = 7 8 9\nElementSpacing = 1 -2 1\n");
  expect_axes(header.volume.info, {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}}, {1, 2, 1});
  EXPECT_DOUBLE_EQ(header.volume.info.origin[1], 8);
}

TEST(MetaImageHeader, LocalDataStartAfterTheElementDataFileLine) {
  const std::string text = metaimage_fields("MET_SHORT", "ElementDataFile = LOCAL\n");
  const MetaImageHeader header = parse_metaimage_header(text + "\x01\x02garbage=\n", "a.mha");
  EXPECT_TRUE(header.data_local);
  EXPECT_EQ(header.header_bytes, text.size());
  EXPECT_EQ(header.volume.byte_order, ByteOrder::little);  // MSB absent: little-endian
}

TEST(MetaImageHeader, RefusalsNameTheFileLineAndProblem) {
  struct Case {
    std::string text;
    std::string expected;
  };
  const std::string end = "ElementDataFile = v.raw\n";
  const Case cases[] = {
      {metaimage_fields("MET_DOUBLE", end), "line 4: ElementType: \"MET_DOUBLE\" is not supported"},
      {metaimage_fields("MET_INT", end), "\"MET_INT\" is not supported"},
      {metaimage_fields("MET_UCHAR_ARRAY", end), "\"MET_UCHAR_ARRAY\" is not supported"},
      {metaimage_fields("MET_UCHAR", "ElementNumberOfChannels = 3\n" + end),
       "line 5: ElementNumberOfChannels: 3 channels"},
      {"NDims = 4\nDimSize = 1 1 1 1\nElementType = MET_UCHAR\n" + end,
       "line 1: NDims: \"4\" is not supported"},
      {"NDims = 3\nElementType = MET_UCHAR\n" + end, "the header has no DimSize line"},
      {"NDims = 3\nDimSize = 1 1 1\n" + end, "the header has no ElementType line"},
      {metaimage_fields("MET_UCHAR", ""), "no ElementDataFile line"},
      {"NDims = 3\nDimSize = 13 11\nElementType = MET_UCHAR\n" + end,
       "line 2: DimSize: expected 3 sizes (NDims)"},
      {"NDims = 3\nDimSize = 13 11 0\nElementType = MET_UCHAR\n" + end, "size \"0\" of axis 2"},
      {"NDims = 3\nDimSize = 4294967295 4294967295 4294967295\nElementType = MET_FLOAT\n" + end,
       "too large to address"},
      {metaimage_fields("MET_UCHAR", "BinaryData = False\n" + end), "BinaryData: False"},
      {"ObjectType = Scene\n" + metaimage_fields("MET_UCHAR", end).substr(19),
       "line 1: ObjectType: \"Scene\" is not an image"},
      {metaimage_fields("MET_UCHAR", "Offset = 0 0 0\nOrigin = 1 1 1\n" + end),
       "line 6: Origin: given again (line 5 gave Offset)"},
      {metaimage_fields("MET_UCHAR", "ElementSpacing = 1 1\n" + end),
       "ElementSpacing: expected 3 finite numbers"},
      {metaimage_fields("MET_UCHAR", "ElementSpacing = 1 0 1\n" + end), "a spacing of 0"},
      {metaimage_fields("MET_UCHAR", "TransformMatrix = 1 0 0 0 1 0\n" + end),
       "TransformMatrix: expected 9 finite numbers"},
      {metaimage_fields("MET_UCHAR", "TransformMatrix = 1 0 0 0 0 0 0 0 1\n" + end),
       "the direction of axis 1 is zero"},
      {metaimage_fields("MET_UCHAR", "TransformMatrix = 1 0 0 0 1 0 1 1 0\n" + end),
       "line 5: TransformMatrix: is singular: its axes are parallel or coplanar"},
      {metaimage_fields("MET_UCHAR", "ElementByteOrderMSB = maybe\n" + end),
       "ElementByteOrderMSB: expected True or False"},
      {metaimage_fields("MET_UCHAR",
                        "ElementByteOrderMSB = True\nBinaryDataByteOrderMSB = "
                        "False\n" +
                            end),
       "contradicts ElementByteOrderMSB"},
      {metaimage_fields("MET_UCHAR", "HeaderSize = -2\n" + end),
       "HeaderSize: expected a whole number or -1"},
      {metaimage_fields("MET_UCHAR", "CompressedData = True\nHeaderSize = -1\n" + end),
       "-1 (data at the end of the file) needs uncompressed data"},
      {metaimage_fields("MET_UCHAR", "ElementDataFile = LIST\n"), "lists and numbered patterns"},
      {metaimage_fields("MET_UCHAR", "ElementDataFile = slice%03d.raw 1 9 1\n"),
       "lists and numbered patterns"},
      {metaimage_fields("MET_UCHAR", "what is this\n" + end), "line 5: expected KEY = VALUE"},
  };
  for (const Case& c : cases) {
    const std::string message = error_of([&] { parse_metaimage_header(c.text, "bad.mhd"); });
    EXPECT_EQ(message.rfind("bad.mhd: ", 0), 0u) << message;
    EXPECT_CONTAINS(message, c.expected);
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
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

// ---------------------------------------------------------------------------------------------
// The command line

TEST(VolumeFilesCli, BadVolumesFailWithOneLineAndNoOutput) {
  const std::vector<std::uint8_t> samples =
      test::phantom_samples<std::uint8_t>(kWidth, kHeight, kDepth);
  const std::vector<unsigned char> raw = test::encode_samples(samples, ByteOrder::little);
  ScratchDirectory dir;
  const std::string header =
      std::string("NRRD0004\ntype: uchar\ndimension: 3\nsizes: ") + kSizes + "\nencoding: raw\n\n";
  write_file(dir / "cut.nrrd", header, std::vector<unsigned char>(raw.begin(), raw.end() - 100));
  write_file(dir / "int.nrrd",
             "NRRD0004\ntype: int\ndimension: 3\nsizes: 1 1 1\nendian: "
             "little\nencoding: raw\n\nxxxx");
  write_file(dir / "nodata.mhd", metaimage_fields("MET_UCHAR", "ElementDataFile = none.raw\n"));
  write_file(dir / "good.nrrd", header, raw);
  const std::string inputs = dir.listing();

  for (const char* input : {"cut.nrrd", "int.nrrd", "nodata.mhd"}) {
    expect_one_line_error(
        run_mvox(std::string("extract ") + input + " -t 100 -o out.ply --image out.png",
                 dir.path()),
        input);
    EXPECT_EQ(dir.listing(), inputs) << "an output or temporary was left behind";
  }
  // --raw with a file that has its own header is a usage error.
  expect_one_line_error(
      run_mvox("extract good.nrrd --raw 13x11x9:u8 -t 100 -o out.ply", dir.path()),
      "--raw: good.nrrd is a NRRD file with its own header", 2);
  EXPECT_EQ(dir.listing(), inputs);

  const test::CommandResult ok = run_mvox("extract good.nrrd -t 100 -o out.ply -q", dir.path());
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_TRUE(fs::exists(dir / "out.ply"));
}

// A spacing or origin that float coordinates cannot hold names the file and says "too large";
// a huge spacing used to overflow the length of its axis vector and be dropped for 1, silently.
TEST(VolumeFilesCli, SpacingOrOriginBeyondFloatNamesTheFile) {
  const std::vector<unsigned char> raw(2 * 2 * 2, 200);
  const std::string nrrd = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n";
  ScratchDirectory dir;
  write_file(dir / "spacings.nrrd", nrrd + "spacings: 1e300 1 1\n\n", raw);
  write_file(dir / "directions.nrrd",
             nrrd + "space: LPS\nspace directions: (1,0,0) (0,1e300,0) (0,0,1)\n\n", raw);
  write_file(dir / "origin.nrrd",
             nrrd +
                 "space: LPS\nspace directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: "
                 "(0,0,-1e39)\n\n",
             raw);
  write_file(dir / "reach.nrrd", nrrd + "spacings: 1 1 3e38\n\n", raw);
  write_file(dir / "spacing.mha",
             "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\nElementSpacing = 1 1 1e300\n"
             "ElementDataFile = LOCAL\n",
             raw);
  const std::string inputs = dir.listing();
  const std::pair<const char*, const char*> cases[] = {
      {"spacings.nrrd",
       "spacing x is too large for float coordinates, got 1e+300 (usable: "
       "2.35099e-38 to 3.40282e+38)"},
      {"directions.nrrd", "spacing y is too large for float coordinates, got 1e+300"},
      {"origin.nrrd",
       "origin z is too large for float coordinates, got -1e+39 (usable: "
       "-3.40282e+38 to 3.40282e+38)"},
      {"reach.nrrd",
       "the mesh would reach 4.5e+38 along z, beyond float's range (at most "
       "3.40282e+38)"},
      {"spacing.mha", "spacing z is too large for float coordinates, got 1e+300"},
  };
  for (const auto& [input, problem] : cases) {
    // A picture alone is refused too: the report gives the placement, and it is the mesh's.
    for (const char* outputs : {" -o out.ply", " --image out.png"}) {
      expect_one_line_error(
          run_mvox(std::string("extract ") + input + " -t 100" + outputs, dir.path()),
          std::string("mvox: error: ") + input + ": " + problem);
      EXPECT_EQ(dir.listing(), inputs) << "an output or temporary was left behind";
    }
  }
  // Given --spacing, the reach is the option's doing: a usage error naming it.
  expect_one_line_error(
      run_mvox("extract spacings.nrrd -t 100 -o out.ply --spacing 1,1,3e38", dir.path()),
      "mvox: error: --spacing: the mesh would reach 4.5e+38 along z", 2);
  const test::CommandResult ok =
      run_mvox("extract spacings.nrrd -t 100 -o out.ply --spacing 1,1,1 -q", dir.path());
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
}

// A detached data file that is a FIFO would keep mvox waiting in open() for a writer that never
// comes: refused before opening, naming header and data file. (timeout: a guard, so that a
// regression fails instead of hanging the suite.)
TEST(VolumeFilesCli, ADataFileThatIsNotARegularFileIsRefusedWithoutOpeningIt) {
  ScratchDirectory dir;
  ASSERT_EQ(::mkfifo((dir / "samples.raw").c_str(), 0600), 0);
  write_file(dir / "volume.nhdr",
             "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\ndata file: "
             "samples.raw\n");
  write_file(
      dir / "volume.mhd",
      "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\nElementDataFile = samples.raw\n");
  write_file(dir / "device.mhd",
             "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\nElementDataFile = /dev/zero\n");
  for (const char* header : {"volume.nhdr", "volume.mhd"}) {
    expect_one_line_error(
        run_mvox(std::string("extract ") + header + " -t 100 -o out.ply", dir.path(), "timeout 30"),
        std::string("mvox: error: ") + header +
            ": data file samples.raw is a FIFO, not a regular file");
  }
  expect_one_line_error(run_mvox("extract device.mhd -t 100 -o out.ply", dir.path(), "timeout 30"),
                        "mvox: error: device.mhd: data file /dev/zero is a device, not a regular "
                        "file");
  EXPECT_EQ(dir.listing(), "device.mhd samples.raw volume.mhd volume.nhdr ");
}

// ---------------------------------------------------------------------------------------------
// The shared datasets, when ../shared/datasets is present (never in the repository)

struct SharedVolume {
  const char* name;
  const char* file;  // relative to the datasets folder
  std::uint32_t width, height, depth;
  double spacing;
  double mean;  // from the dataset's INFO.txt
  double threshold;
};

void expect_shared_volume(const SharedVolume& volume) {
  const std::string path = std::string(MVOX_SHARED_DATASETS) + volume.file;
  if (!fs::exists(path)) GTEST_SKIP() << path << " is absent (optional real data)";

  VolumeInfo info;
  const std::vector<std::uint8_t> samples = read_volume<std::uint8_t>(path, &info);
  EXPECT_EQ(info.width, volume.width);
  EXPECT_EQ(info.height, volume.height);
  EXPECT_EQ(info.depth, volume.depth);
  EXPECT_EQ(info.type, SampleType::u8);
  for (int a = 0; a < 3; ++a) {
    EXPECT_DOUBLE_EQ(info.spacing[a], volume.spacing);
    EXPECT_DOUBLE_EQ(info.origin[a], 0);
    for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(info.axes[a][i], a == i ? 1 : 0);
  }
  double sum = 0;
  for (std::uint8_t s : samples) sum += s;
  EXPECT_NEAR(sum / static_cast<double>(samples.size()), volume.mean, 0.001);

  ScratchDirectory dir;
  const test::CommandResult result =
      run_mvox("extract '" + path + "' -t " + std::to_string(volume.threshold) + " -o mesh.ply -q",
               dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const PlyMesh ply = read_ply(dir / "mesh.ply");
  const test::Topology t = test::analyse(test::to_mesh(ply));
  EXPECT_TRUE(t.closed_and_consistent()) << volume.name << ": " << test::describe(t);
  EXPECT_GT(t.signed_volume, 0);
  EXPECT_GT(t.faces, 1000u);
  // The spacing reaches the mesh: the largest coordinate is about (size - 1) * spacing.
  float max_x = 0;
  for (const auto& p : ply.positions) max_x = std::max(max_x, p[0]);
  EXPECT_LE(max_x, (volume.width - 0.5) * volume.spacing);
  EXPECT_GT(max_x, volume.width * volume.spacing / 2);
}

TEST(SharedDatasets, ToothNrrd) {
  expect_shared_volume({"tooth", "/tooth/tooth.nrrd", 103, 94, 161, 1, 103.165, 100});
}

TEST(SharedDatasets, HeadMrMetaImage) {
  expect_shared_volume(
      {"head_mr_small", "/head_mr_small/HeadMRVolume.mhd", 48, 62, 42, 4, 24.468, 50});
}

}  // namespace
}  // namespace mvox
