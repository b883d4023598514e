// The MetaImage header parser (src/read/metaimage/metaimage_header.h), a pure function, so
// everything is checked on header text alone: spacing, offset and the transform matrix, the
// element size as spacing, where local data start, and every refusal naming the file, the line
// and the problem.
#include "read/metaimage/metaimage_header.h"

#include <gtest/gtest.h>

#include <string>

#include "error_capture.h"
#include "volume_files.h"

namespace mvox {
namespace {

using test::error_of;
using test::volume_files::expect_axes;
using test::volume_files::metaimage_fields;

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

}  // namespace
}  // namespace mvox
