// The element walk of src/read/dicom/dicom_file_scan.h, which keeps malformed files away from
// GDCM (built with assertions, it aborts on them): every truncation of a file in several
// encodings, one cut after planning, elements with a wrong or unknown VR, and random byte changes
// in every encoding, each read or refused naming the file, never a crash.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "command_runner.h"
#include "dicom_series.h"
#include "dicom_writer.h"
#include "error.h"
#include "file_io.h"
#include "read/dicom/dicom_series_source.h"

namespace mvox {
namespace {

namespace fs = std::filesystem;
using test::DicomSliceSpec;
using test::read_bytes;
using test::ScratchDirectory;
using test::write_bytes;
using test::dicom_series::expect_error;
using test::dicom_series::open_series;
using test::dicom_series::pattern;
using test::dicom_series::read_values;
using test::dicom_series::Vec3;
using test::dicom_series::write_series;

void truncate_copy(const std::string& from, const std::string& to, std::uintmax_t bytes) {
  std::ifstream in(from, std::ios::binary);
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(to, std::ios::binary | std::ios::trunc) << data.substr(0, bytes);
}

// Every shorter prefix of a file, in several encodings, is refused naming it: the walk in
// dicom_file_scan.cpp keeps GDCM (which aborts on a cut element) from ever seeing one.
TEST(DicomSeries, EveryTruncationOfAFileIsRefusedNamingIt) {
  ScratchDirectory source_dir;
  DicomSliceSpec spec;
  spec.position = Vec3{0, 0, 0};
  spec.orientation = std::array<double, 6>{1, 0, 0, 0, 1, 0};
  spec.pixel_spacing = std::array<double, 2>{1, 1};
  spec.stored = pattern(16, 12, 0);
  test::write_dicom(source_dir / "native.dcm", spec);
  spec.transfer_syntax_uid = test::kImplicitLittleEndianUid;
  test::write_dicom(source_dir / "implicit.dcm", spec);
  spec.transfer_syntax_uid = test::kExplicitBigEndianUid;
  test::write_dicom(source_dir / "big.dcm", spec);
  ASSERT_TRUE(
      test::recode(source_dir / "native.dcm", source_dir / "rle.dcm", test::kRleLosslessUid));

  for (const char* name : {"native.dcm", "implicit.dcm", "big.dcm", "rle.dcm"}) {
    ScratchDirectory dir;
    const std::string whole = source_dir / name;
    const std::uintmax_t size = fs::file_size(whole);
    // Two intact neighbours, so a file that silently dropped out would still give a volume.
    spec.transfer_syntax_uid = test::kExplicitLittleEndianUid;
    spec.position = Vec3{0, 0, -1};
    test::write_dicom(dir / "before.dcm", spec);
    spec.position = Vec3{0, 0, 1};
    test::write_dicom(dir / "next.dcm", spec);
    const std::string cut = dir / "cut.dcm";
    int refused = 0;
    for (std::uintmax_t bytes = 0; bytes < size; ++bytes) {
      truncate_copy(whole, cut, bytes);
      try {
        DicomSeriesSource source = open_series(dir.path().string());
        read_values(source);
        ADD_FAILURE() << name << " cut to " << bytes << " of " << size << " bytes was read";
      } catch (const Error& e) {
        if (e.subject() == cut)
          ++refused;
        else
          ADD_FAILURE() << name << " cut to " << bytes << ": " << e.what();
      }
    }
    EXPECT_EQ(refused, static_cast<int>(size)) << name;
  }
}

TEST(DicomSeries, AFileTruncatedAfterPlanningIsRefusedWhenItsSliceIsRead) {
  ScratchDirectory dir;
  write_series(dir.path().string(), "s", DicomSliceSpec{}, 3, {0, 0, 0}, 1);
  DicomSeriesSource source = open_series(dir.path().string());
  const std::string victim = dir / "s1.dcm";
  const std::string whole = dir / "whole.bin";
  fs::copy_file(victim, whole);
  truncate_copy(whole, victim, fs::file_size(whole) - 100);
  SliceView slice;
  ASSERT_TRUE(source.next_slice(&slice));
  expect_error([&] { source.next_slice(&slice); }, victim, "truncated DICOM file");
}

// GDCM asserts when an element it reads has another VR than the standard's, or an unknown one.
TEST(DicomSeries, ElementsWithWrongOrUnknownVrsAreRefused) {
  ScratchDirectory dir;
  DicomSliceSpec spec;
  spec.stored = pattern(16, 12, 0);
  test::write_dicom(dir / "plain.dcm", spec);
  const std::string plain = read_bytes(dir / "plain.dcm");
  fs::remove(dir / "plain.dcm");
  const std::string rows("\x28\x00\x10\x00US", 6);  // (0028,0010) US, explicit little endian
  const std::size_t at = plain.find(rows);
  ASSERT_NE(at, std::string::npos);
  std::string wrong = plain, unknown = plain, recognition = plain;
  wrong[at + 5] = 'L';    // UL: a real VR, not Rows'
  unknown[at + 5] = 'H';  // UH: no such VR
  const std::size_t modality =
      plain.find(std::string("\x08\x00\x60\x00"
                             "CS",
                             6));
  ASSERT_NE(modality, std::string::npos);
  recognition[modality + 2] = 0x10;  // (0008,0060) Modality becomes (0008,0010) RecognitionCode
  recognition[modality + 4] = 'S';
  recognition[modality + 5] = 'H';
  write_bytes(dir / "image.dcm", wrong);
  expect_error([&] { open_series(dir.path().string()); }, dir / "image.dcm",
               "element (0028,0010) at byte " + std::to_string(at) + " has VR UL, expected US");
  write_bytes(dir / "image.dcm", unknown);
  expect_error([&] { open_series(dir.path().string()); }, dir / "image.dcm", "unknown VR UH");
  write_bytes(dir / "image.dcm", recognition);
  expect_error([&] { open_series(dir.path().string()); }, dir / "image.dcm",
               "(RecognitionCode) does not name ACR-NEMA");
}

// A file of zeros reads as element (0000,0000) of length 0, again and again: a large one (a
// preallocated or sparse file in a DICOM folder) was walked to its end, a terabyte in most of an
// hour. A repeated tag ends the walk at the second element: named as malformed when the file
// claims to be DICOM (.dcm), and left out as not DICOM otherwise, beside a series that reads.
TEST(DicomSeries, AFileOfZerosIsToldFromItsSecondElement) {
  ScratchDirectory dir;
  DicomSliceSpec spec;
  spec.stored = pattern(16, 12, 0);
  test::write_dicom(dir / "image.dcm", spec);
  write_bytes(dir / "zeros.dcm", std::string(4096, '\0'));
  expect_error([&] { open_series(dir.path().string()); }, dir / "zeros.dcm",
               "element (0000,0000) at byte 8 repeats the element before it");
  fs::rename(dir / "zeros.dcm", dir / "zeros");
  fs::resize_file(dir / "zeros", std::uintmax_t{1} << 40);  // a terabyte of holes
  std::vector<std::string> notes;
  EXPECT_EQ(open_series(dir.path().string(), &notes).info().depth, 1u);
}

// Random byte changes in files of every encoding: each is read or refused with an mvox::Error
// naming it; none may crash the process (which would end this test binary). Fixed seed.
TEST(DicomSeries, CorruptedBytesAreReadOrRefusedNeverACrash) {
  ScratchDirectory originals;
  DicomSliceSpec spec;
  spec.width = 24;
  spec.height = 20;
  spec.position = Vec3{0, 0, 0};
  spec.orientation = std::array<double, 6>{1, 0, 0, 0, 1, 0};
  spec.pixel_spacing = std::array<double, 2>{1, 1};
  spec.slope = 1;
  spec.intercept = -1024;
  spec.stored = pattern(24, 20, 0);
  test::write_dicom(originals / "explicit.dcm", spec);
  spec.transfer_syntax_uid = test::kImplicitLittleEndianUid;
  test::write_dicom(originals / "implicit.dcm", spec);
  spec.transfer_syntax_uid = test::kExplicitBigEndianUid;
  test::write_dicom(originals / "big.dcm", spec);
  std::vector<std::string> files = {"explicit.dcm", "implicit.dcm", "big.dcm"};
  for (const char* syntax : {test::kRleLosslessUid, test::kJpegLosslessUid,
                             test::kJpegLsLosslessUid, test::kJpeg2000LosslessUid}) {
    files.push_back(std::string(syntax) + ".dcm");
    ASSERT_TRUE(test::recode(originals / "explicit.dcm", originals / files.back(), syntax));
  }
  std::mt19937 random(20240611);
  ScratchDirectory dir;
  const std::string victim = dir / "case.dcm";
  int read = 0, refused = 0;
  for (int trial = 0; trial < 1400; ++trial) {
    std::string bytes = read_bytes(originals / files[trial % files.size()]);
    const int changes = 1 + static_cast<int>(random() % 4);
    for (int c = 0; c < changes; ++c) bytes[random() % bytes.size()] = static_cast<char>(random());
    write_bytes(victim, bytes);
    try {
      DicomSeriesSource source({victim}, DicomOptions{});
      read_values(source);
      ++read;
    } catch (const Error& e) {
      ++refused;
      EXPECT_TRUE(e.subject() == victim) << e.what();
      const std::string what = e.what();
      EXPECT_TRUE(std::all_of(what.begin(), what.end(), [](char c) { return c >= 32 && c < 127; }))
          << what;
    }
  }
  EXPECT_GT(read, 200);  // most changes hit pixel values, which are read as they are
  EXPECT_GT(refused, 200);
}

}  // namespace
}  // namespace mvox
