// The NRRD header parser (src/read/nrrd/nrrd_header.h), a pure function, so everything is checked
// on header text alone: space directions, rotated frames and spacings give unit axes and
// spacing, comments and aliases are accepted, the header ends after its blank line, and every
// refusal names the file, the line and the problem.
#include "read/nrrd/nrrd_header.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "error_capture.h"
#include "volume_files.h"

namespace mvox {
namespace {

using test::error_of;
using test::volume_files::expect_axes;

NrrdHeader parse_nrrd(const std::string& fields) {
  return parse_nrrd_header(
      "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 13 11 9\nencoding: raw\n" + fields + "\n\n",
      "test.nrrd");
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

}  // namespace
}  // namespace mvox
