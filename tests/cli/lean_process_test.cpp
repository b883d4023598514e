// A run loads the heavy libraries its input or outputs need, and no other: OpenCV's image codecs,
// GDCM and libtiff live in modules (modules/module_loader.h) that raw, NRRD, MetaImage, PNG,
// uncompressed and deflate TIFF runs, --help, phantom and demo never load, and a TIFF run of
// another compression loads libtiff's alone. Checked the way
// the dynamic loader itself reports what it maps (LD_DEBUG=files), and by runs with no module
// directory at all; a run that needs a missing module fails in one line that names it and how to
// install what it needs.
#include <gtest/gtest.h>
#include <tiffio.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "support/command_runner.h"
#include "support/dicom_writer.h"
#include "support/file_io.h"

namespace mvox {
namespace {

using test::run_mvox;
using test::ScratchDirectory;

// The shared libraries the dynamic loader mapped for `arguments`, as it reports them.
struct Loaded {
  bool opencv = false;
  bool gdcm = false;
  bool tiff = false;  // libtiff and its codec libraries
  bool mpi = false;   // only mvox-mpi links MPI
  int exit_code = -1;
  std::string output;
};

Loaded loaded_by(const std::string& arguments, const ScratchDirectory& dir) {
  // LD_DEBUG writes to standard error, one "file=NAME [0];  needed by ..." or "... dynamically
  // loaded by ..." line per library; the runner keeps both streams.
  const test::CommandResult result = run_mvox(arguments, dir.path(), "LD_DEBUG=files");
  Loaded loaded;
  loaded.exit_code = result.exit_code;
  loaded.output = result.output;
  loaded.opencv = result.output.find("file=libopencv_") != std::string::npos ||
                  result.output.find("libmvox_image_codecs.so [0]") != std::string::npos;
  loaded.gdcm = result.output.find("file=libgdcm") != std::string::npos ||
                result.output.find("libmvox_dicom_codecs.so [0]") != std::string::npos;
  loaded.tiff = result.output.find("file=libtiff") != std::string::npos ||
                result.output.find("libmvox_tiff_codecs.so [0]") != std::string::npos;
  loaded.mpi = result.output.find("file=libmpi") != std::string::npos;
  return loaded;
}

// Runs `arguments`, which must succeed and load neither OpenCV nor GDCM nor MPI, and libtiff
// only when `tiff` says so.
void expect_lean(const std::string& arguments, const ScratchDirectory& dir, bool tiff = false) {
  SCOPED_TRACE(arguments);
  const Loaded loaded = loaded_by(arguments, dir);
  EXPECT_EQ(loaded.exit_code, 0) << loaded.output.substr(
      loaded.output.size() > 2000 ? loaded.output.size() - 2000 : 0);
  EXPECT_FALSE(loaded.opencv) << "OpenCV was loaded";
  EXPECT_FALSE(loaded.gdcm) << "GDCM was loaded";
  EXPECT_FALSE(loaded.mpi) << "MPI was loaded";
  EXPECT_EQ(loaded.tiff, tiff) << (tiff ? "libtiff was not loaded" : "libtiff was loaded");
}

void write_tiff(const std::string& path, int pages, std::uint16_t compression = COMPRESSION_NONE) {
  TIFF* tiff = TIFFOpen(path.c_str(), "w");
  ASSERT_NE(tiff, nullptr);
  for (int page = 0; page < pages; ++page) {
    TIFFSetField(tiff, TIFFTAG_COMPRESSION, compression);
    TIFFSetField(tiff, TIFFTAG_IMAGEWIDTH, 8);
    TIFFSetField(tiff, TIFFTAG_IMAGELENGTH, 6);
    TIFFSetField(tiff, TIFFTAG_BITSPERSAMPLE, 8);
    TIFFSetField(tiff, TIFFTAG_SAMPLESPERPIXEL, 1);
    TIFFSetField(tiff, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    TIFFSetField(tiff, TIFFTAG_ROWSPERSTRIP, 6);
    std::vector<unsigned char> row(8);
    for (int y = 0; y < 6; ++y) {
      for (int x = 0; x < 8; ++x) row[x] = (x > 1 && x < 6 && y > 1 && y < 5) ? 200 : 0;
      ASSERT_EQ(TIFFWriteScanline(tiff, row.data(), y, 0), 1);
    }
    TIFFWriteDirectory(tiff);
  }
  TIFFClose(tiff);
}

// Three 8x6 PGM slices (P5): a format OpenCV reads and mvox does not decode itself.
void write_pgm_stack(const ScratchDirectory& dir) {
  for (int z = 0; z < 3; ++z) {
    std::vector<unsigned char> bytes;
    const std::string header = "P5\n8 6\n255\n";
    bytes.assign(header.begin(), header.end());
    for (int i = 0; i < 48; ++i) bytes.push_back((i % 8 > 2 && z == 1) ? 200 : 0);
    test::write_bytes(dir.path() / "pgm" / ("s" + std::to_string(z) + ".pgm"), bytes);
  }
}

void write_dicom_series(const ScratchDirectory& dir) {
  std::filesystem::create_directories(dir.path() / "dicom");
  for (int z = 0; z < 3; ++z) {
    test::DicomSliceSpec spec;
    spec.width = 8;
    spec.height = 6;
    spec.stored.assign(48, z == 1 ? 500 : 0);
    spec.position = std::array<double, 3>{0, 0, double(z)};
    spec.orientation = std::array<double, 6>{1, 0, 0, 0, 1, 0};
    test::write_dicom((dir.path() / "dicom" / ("s" + std::to_string(z) + ".dcm")).string(), spec);
  }
}

class LeanProcess : public ::testing::Test {
 protected:
  ScratchDirectory dir_;
};

TEST_F(LeanProcess, HelpPhantomAndDemoLoadNoModule) {
  expect_lean("--help", dir_);
  expect_lean("extract --help", dir_);
  expect_lean("phantom sphere -o stack --size 16x16x8 -q", dir_);
  expect_lean("phantom blobs -o stack16 --size 16x12x6 --bits 16 -q", dir_);
  expect_lean("demo --size 32 -o demo.ply --image demo.png -q", dir_);
}

TEST_F(LeanProcess, RawNrrdMetaImageAndPngRunsLoadNoModuleAndTiffLoadsLibtiffOnlyToDecode) {
  std::vector<unsigned char> volume(8 * 6 * 4, 0);
  for (std::size_t i = 48; i < 144; ++i) volume[i] = (i % 8 > 2) ? 200 : 0;
  test::write_bytes(dir_.path() / "v.raw", volume);
  const std::string nrrd_header =
      "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 8 6 4\nencoding: raw\n\n";
  std::vector<unsigned char> nrrd(nrrd_header.begin(), nrrd_header.end());
  nrrd.insert(nrrd.end(), volume.begin(), volume.end());
  test::write_bytes(dir_.path() / "v.nrrd", nrrd);
  const std::string mhd =
      "ObjectType = Image\nNDims = 3\nDimSize = 8 6 4\nElementType = MET_UCHAR\n"
      "ElementDataFile = v.raw\n";
  test::write_bytes(dir_.path() / "v.mhd", std::vector<unsigned char>(mhd.begin(), mhd.end()));
  write_tiff((dir_.path() / "v.tif").string(), 4);
  write_tiff((dir_.path() / "deflate.tif").string(), 4, COMPRESSION_ADOBE_DEFLATE);
  write_tiff((dir_.path() / "lzw.tif").string(), 4, COMPRESSION_LZW);
  ASSERT_EQ(run_mvox("phantom sphere -o stack --size 16x16x8 -q", dir_.path()).exit_code, 0);
  ASSERT_EQ(run_mvox("phantom blobs -o stack16 --size 16x12x6 --bits 16 -q", dir_.path()).exit_code,
            0);

  const std::string outputs = " -t 100 -o m.ply --image p.png --stats s.json -q";
  expect_lean("extract v.raw --raw 8x6x4:u8" + outputs, dir_);
  expect_lean("extract v.nrrd" + outputs, dir_);
  expect_lean("extract v.mhd" + outputs, dir_);
  // mvox reads TIFF directories, uncompressed data and deflate data itself.
  expect_lean("extract v.tif" + outputs, dir_);
  expect_lean("extract deflate.tif" + outputs, dir_);
  expect_lean("extract lzw.tif" + outputs, dir_, true);
  expect_lean("extract stack" + outputs + " --frames frames --every 2", dir_);
  expect_lean("extract stack16 -t 1000 -o m16.obj --image p16.png -q", dir_);
  expect_lean("render m.ply -o r.png", dir_);
}

TEST_F(LeanProcess, PngRunsNeedNoModuleAtAll) {
  ASSERT_EQ(run_mvox("phantom sphere -o stack --size 16x16x8 -q", dir_.path()).exit_code, 0);
  const test::CommandResult result =
      run_mvox("extract stack -t 100 -o m.ply --image p.png -q", dir_.path(),
               "MVOX_MODULE_PATH=/nonexistent/mvox-modules");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_TRUE(test::exists((dir_.path() / "p.png").string()));
}

TEST_F(LeanProcess, DicomLoadsGdcmOnly) {
  write_dicom_series(dir_);
  const Loaded loaded = loaded_by("extract dicom -t 100 -o m.ply --image p.png -q", dir_);
  EXPECT_EQ(loaded.exit_code, 0);
  EXPECT_TRUE(loaded.gdcm);
  EXPECT_FALSE(loaded.opencv);
}

TEST_F(LeanProcess, FormatsMvoxDoesNotDecodeLoadOpenCv) {
  write_pgm_stack(dir_);
  Loaded loaded = loaded_by("extract pgm -t 100 -o m.ply -q", dir_);
  EXPECT_EQ(loaded.exit_code, 0);
  EXPECT_TRUE(loaded.opencv);  // (Debian's OpenCV links GDCM itself, for its own DICOM reader)
  // A picture of another type than PNG is OpenCV's to write.
  ASSERT_EQ(run_mvox("phantom sphere -o stack --size 16x16x8 -q", dir_.path()).exit_code, 0);
  loaded = loaded_by("extract stack -t 100 --image p.tif -q", dir_);
  EXPECT_EQ(loaded.exit_code, 0);
  EXPECT_TRUE(loaded.opencv);
}

TEST_F(LeanProcess, AMissingModuleIsOneLineNamingItAndHowToInstall) {
  const std::string nowhere = "MVOX_MODULE_PATH=/nonexistent/mvox-modules";
  write_dicom_series(dir_);
  write_tiff((dir_.path() / "v.tif").string(), 2, COMPRESSION_LZW);
  test::CommandResult result = run_mvox("extract v.tif -t 100 -o t.ply -q", dir_.path(), nowhere);
  test::expect_one_line_error(result, "v.tif");
  EXPECT_NE(result.output.find("TIFF module (libtiff) libmvox_tiff_codecs.so"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("apt-get install libtiff-dev"), std::string::npos) << result.output;

  result = run_mvox("extract dicom -t 100 -o m.ply -q", dir_.path(), nowhere);
  test::expect_one_line_error(result, "dicom/s0.dcm");
  EXPECT_NE(result.output.find("DICOM module (GDCM) libmvox_dicom_codecs.so"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("/nonexistent/mvox-modules"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("apt-get install libgdcm-dev"), std::string::npos) << result.output;

  write_pgm_stack(dir_);
  result = run_mvox("extract pgm -t 100 -o m.ply -q", dir_.path(), nowhere);
  test::expect_one_line_error(result, "pgm/s0.pgm");
  EXPECT_NE(result.output.find("image codecs module (OpenCV) libmvox_image_codecs.so"),
            std::string::npos)
      << result.output;

  ASSERT_EQ(run_mvox("phantom sphere -o stack --size 16x16x8 -q", dir_.path()).exit_code, 0);
  result = run_mvox("extract stack -t 100 --image p.bmp -q", dir_.path(), nowhere);
  test::expect_one_line_error(result, "p.bmp");
  EXPECT_NE(result.output.find("libmvox_image_codecs.so"), std::string::npos) << result.output;
  for (const char* output : {"t.ply", "m.ply", "p.bmp"})
    EXPECT_FALSE(test::exists((dir_.path() / output).string())) << output;
}

}  // namespace
}  // namespace mvox

namespace mvox {
namespace {

// Started through a symbolic link by its path, mvox still finds its modules beside the real
// executable (argv[0] would name the link's folder).
TEST(LeanProcessLinks, ASymbolicLinkToMvoxFindsTheModulesBesideTheRealFile) {
  test::ScratchDirectory dir;
  write_pgm_stack(dir);
  std::filesystem::create_directories(dir.path() / "bin");
  std::filesystem::create_symlink(MVOX_BINARY, dir.path() / "bin" / "mvox");
  const std::string command = "cd '" + dir.str() + "' && env -u MVOX_MODULE_PATH bin/mvox " +
                              "extract pgm -t 100 -o m.ply -q 2>&1";
  const int status = std::system(command.c_str());
  EXPECT_EQ(status, 0);
  EXPECT_TRUE(test::exists((dir.path() / "m.ply").string()));
}

// A module file that is there but damaged is reported with the dynamic loader's reason, not
// as a library to install.
TEST(LeanProcessLinks, ADamagedModuleIsOneLineWithTheLoadersReason) {
  test::ScratchDirectory dir;
  write_pgm_stack(dir);
  test::write_bytes(dir.path() / "modules" / "libmvox_image_codecs.so",
                    std::vector<unsigned char>{'n', 'o', 't', ' ', 'E', 'L', 'F'});
  const test::CommandResult result =
      run_mvox("extract pgm -t 100 -o m.ply -q", dir.path(), "MVOX_MODULE_PATH=modules");
  test::expect_one_line_error(result, "pgm/s0.pgm");
  EXPECT_NE(result.output.find("file too short"), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("install"), std::string::npos) << result.output;
}

// A picture name without an extension is refused for what it is, without loading OpenCV to
// ask about it.
TEST(LeanProcessLinks, APictureWithoutAnExtensionIsRefusedWithoutAnyModule) {
  test::ScratchDirectory dir;
  ASSERT_EQ(run_mvox("phantom sphere -o stack --size 16x16x8 -q", dir.path()).exit_code, 0);
  const test::CommandResult result = run_mvox("extract stack -t 100 --image picture -q", dir.path(),
                                              "MVOX_MODULE_PATH=/nonexistent/modules");
  test::expect_one_line_error(result, "picture");
  EXPECT_NE(result.output.find("no image type"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace mvox
